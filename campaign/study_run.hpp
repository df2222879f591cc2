// A parameter study run here (`wiredem study run`): each point's campaign in
// DIR/points/<k>/ through the stages (stages.hpp), several at once, each
// resumable; the study's summary from the points' summaries (api/study.hpp).
#pragma once

#include "api/study.hpp"
#include "stages.hpp"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace wiredem::campaign {

/// What happens to the points, for a display: (point index, "started" |
/// "succeeded" | "failed" | "done already", detail). Called one at a time.
using StudyEvent = std::function<void(std::size_t, const std::string&, const std::string&)>;

/// The directory of point k of a study directory.
[[nodiscard]] std::filesystem::path point_dir(const std::filesystem::path& study_dir, std::size_t k);

/// Runs every point not yet done, `at_once` of them at a time, the threads
/// of `control` shared among them; a failed point is reported and the others
/// go on. Returns each point's outcome (parallel to study.points), and
/// writes DIR/summary.json and DIR/summary.csv from them.
[[nodiscard]] std::vector<api::PointOutcome> run_study(const api::Study& study, const std::filesystem::path& dir,
    std::size_t at_once, const StageControl& control, const StudyEvent& event);

} // namespace wiredem::campaign
