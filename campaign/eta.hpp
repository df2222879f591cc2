// The time left of a campaign, from its work and the rate this process
// measures: steps left (api::estimated_work's steps, less what is done,
// earlier runs of the directory included) over the steps this process has
// run per second since its first report (of the tests, once they run: the
// preparation's rate only stands in for theirs until then). Not "elapsed × (1 − f) / f": that
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
    /// Whether the tests are running (else the preparation): the two step at
    /// rates of their own — the pour at its own time step, which the
    /// estimate's step count (at the tests' step) does not know — so the
    /// rate is measured afresh when the tests begin.
    bool testing = false;
};

/// Turns work reports into a time left.
class EtaEstimate {
public:
    /// Records `work` at time `t_s` (any steady clock [s]); returns the time
    /// left [s], or nothing until steps have been run since the first report
    /// (of the preparation, or of the tests).
    std::optional<double> update(double t_s, const WorkSteps& work)
    {
        if (!started_ || work.testing != testing_) {
            started_ = true;
            testing_ = work.testing;
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
    bool testing_ = false;
    double t0_ = 0.0;
    double run0_ = 0.0;
};

} // namespace wiredem::campaign
