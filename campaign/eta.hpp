// The time left of a campaign, from its work and the rate this process
// measures: steps left (api::estimated_work's steps, less what is done,
// earlier runs of the directory included) over the steps this process has
// run per second since its first report. Not "elapsed × (1 − f) / f": that
// extrapolation has nothing to say at 0 %, and after a resume it divides the
// few seconds of this process by the progress of every earlier one.
#pragma once

#include <optional>

namespace wiredem::campaign {

/// A campaign's work in estimated time steps, as `run` reports it
/// (StageControl::work).
struct WorkSteps {
    /// Steps this process has run (not those of earlier runs, not the rest
    /// of a pour that settled before its time limit).
    double run = 0.0;
    double left = 0.0;  ///< steps still to run, by the estimate
};

/// Turns work reports into a time left.
class EtaEstimate {
public:
    /// Records `work` at time `t_s` (any steady clock [s]); returns the time
    /// left [s], or nothing until steps have been run since the first report.
    std::optional<double> update(double t_s, const WorkSteps& work)
    {
        if (!started_) {
            started_ = true;
            t0_ = t_s;
            run0_ = work.run;
            return std::nullopt;
        }
        const double steps = work.run - run0_;
        const double seconds = t_s - t0_;
        if (!(steps > 0.0) || !(seconds > 0.0)) return std::nullopt;
        return work.left > 0.0 ? work.left * seconds / steps : 0.0;
    }

private:
    bool started_ = false;
    double t0_ = 0.0;
    double run0_ = 0.0;
};

} // namespace wiredem::campaign
