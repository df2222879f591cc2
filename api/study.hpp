// A parameter study: a base job and the fields to vary, as a full grid
//
//   {"name": "patterns", "base": {…job…},
//    "vary": {"specimen.wire.pattern": ["none", "helix"], "seed": [1, 2, 3]}}
//
// or as a list of explicit points
//
//   {"name": "two", "base": {…}, "points": [{"seed": 1}, {"seed": 7, "specimen.wire.pattern": "helix"}]}
//
// Each point is the base with its values set at their paths (dot-separated
// field names of the job spec), validated as a job: every problem is reported
// with the point and the field (`points[3] (seed=-1): seed: …`). The
// summary groups the points that differ only in their seed (the replicates)
// and gives the mean, standard deviation and count of φ and c per group.
// docs/studies.md.
#pragma once

#include "api/job_spec.hpp"

#include <boost/json.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wiredem::api {

/// Points a study may have unless a server says otherwise.
inline constexpr std::size_t default_max_study_points = 256;

/// One job of a study.
struct StudyPoint {
    /// The varied fields at this point, in the study's path order.
    std::vector<std::pair<std::string, boost::json::value>> values;
    std::string label;  ///< "specimen.wire.pattern=helix seed=1"
    JobSpec spec;       ///< the base with those values
};

struct Study {
    std::string name;
    std::vector<std::string> paths;   ///< the varied fields, in document order
    std::vector<StudyPoint> points;   ///< grid order: the last path varies fastest
};

/// Parses and validates a study document; `max_points` bounds the grid
/// (checked before any point is built). Never throws on bad input.
[[nodiscard]] engine::Result<Study, std::vector<FieldError>> parse_study(
    const boost::json::value& doc, std::size_t max_points = default_max_study_points);
/// The same from JSON text.
[[nodiscard]] engine::Result<Study, std::vector<FieldError>> parse_study(
    std::string_view text, std::size_t max_points = default_max_study_points);

/// How one point of a study went, for its summary.
struct PointOutcome {
    std::string state;                        ///< queued … succeeded | failed | cancelled
    std::string job_id;                       ///< "" when run without a server
    std::string error;                        ///< why it failed, if it did
    std::optional<boost::json::value> summary; ///< its summary.json once it has succeeded
};

/// The study's summary: one row per point (its values, state, φ, c, R², the
/// yield and maximum q per pressure, volume fractions, wire lag) and one per
/// group of replicates (the points equal but for "seed"): mean, standard
/// deviation (n − 1; null below 2) and n of φ and c over its succeeded points.
/// `outcomes` is parallel to study.points.
[[nodiscard]] boost::json::object study_summary(const Study& study, const std::vector<PointOutcome>& outcomes);

/// The summary's point rows as CSV (a header, then a row per point; numbers
/// in their shortest exact form, a list in one cell joined by ';').
[[nodiscard]] std::string study_summary_csv(const boost::json::object& summary);

} // namespace wiredem::api
