// Text the client shows people: the results table of a summary, a job's
// status block, the job list and the progress bar of `wait`. Pure functions
// of JSON documents from the server (missing fields print as "-"), so they
// are testable without a server. Thread-safe.
#pragma once

#include <boost/json/value.hpp>

#include <string>
#include <string_view>

namespace wiredem::client {

/// The results of a succeeded job as a table: per confining pressure the peak
/// deviatoric stress and where it occurred; the Mohr-Coulomb φ and c; the
/// specimen's volume fractions; engine figures; warnings. Stresses in kPa.
[[nodiscard]] std::string format_summary(const boost::json::value& summary);

/// A study's summary (api/study.hpp: study_summary): per group of replicates
/// φ and c as mean ± standard deviation (n), then one line per point with
/// its state, φ, c and R², or why it failed. Stresses in kPa.
[[nodiscard]] std::string format_study_summary(const boost::json::value& summary);

/// A job (GET /v1/jobs/{id}) as aligned "key  value" lines.
[[nodiscard]] std::string format_job(const boost::json::value& job);

/// A page of jobs (GET /v1/jobs) as a table, one job per line.
[[nodiscard]] std::string format_job_list(const boost::json::value& page);

/// One line for a terminal: `[=======>      ]  45%  testing  eta 1m20s`,
/// `width` characters for the bar.
[[nodiscard]] std::string format_progress_bar(const boost::json::value& job, int width);

/// One plain line for logs: `running  testing  45%  eta 1m20s  step 3 of 8`.
[[nodiscard]] std::string format_progress_line(const boost::json::value& job);

/// `text` safe to print on a terminal: C0 and C1 control characters, DEL,
/// the line and paragraph separators U+2028/2029 and the bidirectional
/// controls (U+200E/200F, U+202A–202E, U+2066–2069) become visible escapes
/// (\x1b, \u{202e}), and bytes that are not UTF-8 become \xNN; everything
/// else is kept. Job names and runner messages come from other people: a name
/// must not move the cursor, clear the screen or reverse the text after it.
[[nodiscard]] std::string printable(std::string_view text);

/// 0 s → "0s", 80 → "1m20s", 4000 → "1h06m".
[[nodiscard]] std::string format_duration(double seconds);

} // namespace wiredem::client
