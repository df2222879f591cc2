// The runner's progress lines (the runner contract, docs/api.md): one JSON
// object per line on its stdout, e.g.
//   {"stage":"test 2/4","progress":0.41,"eta_s":812,"message":"…"}
// Read here, apart from the queue's locking, so that it can be tested and
// fuzzed as a pure function of the line (tests/fuzz/fuzz_progress_line.cpp).
// The fields end up in the store and in every job's JSON: whatever a line
// holds, what is kept is bounded, valid UTF-8 and a sane number.
#pragma once

#include "job_queue.hpp"

#include <boost/json/value.hpp>

#include <initializer_list>
#include <optional>
#include <string_view>

namespace wiredem::server {

/// The longest stage name and message kept from a progress line [bytes].
inline constexpr std::size_t max_stage_bytes = 64;
inline constexpr std::size_t max_message_bytes = 512;

/// The number at `path` (object keys) in `v`, if there is one.
[[nodiscard]] std::optional<double> number_at(const boost::json::value& v, std::initializer_list<const char*> path);

/// What one progress line says; a field it does not give is unset.
struct ProgressLine {
    std::optional<std::string> stage;      ///< at most max_stage_bytes
    std::optional<double> progress;        ///< in [0, 1]
    bool has_eta = false;                  ///< the line gives eta_s (null: no estimate)
    std::optional<double> eta_s;           ///< the estimate, when given as a usable number [s]
    std::optional<std::string> message;    ///< at most max_message_bytes
    std::optional<double> body_steps_per_second;  ///< the engine's throughput [body-steps/s]
};

/// Reads one line of the runner's stdout: a JSON object gives the fields it
/// has (stage and message cut to their limits at a character boundary,
/// progress clamped to [0, 1], an ETA kept only when finite and not
/// negative, a rate only when finite and positive); nullopt when the line is
/// not a JSON object (the runner's other output).
[[nodiscard]] std::optional<ProgressLine> parse_progress_line(std::string_view line);

/// Applies a progress line to a job's live progress: the fields it gives, and
/// preparing → running once a stage other than "preparing" is reported.
void apply_progress_line(const ProgressLine& line, LiveProgress& live);

} // namespace wiredem::server
