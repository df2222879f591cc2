// Loading, the phase of a column test in which the top plate moves down at a
// constant speed until the column reaches a target axial strain (or the test
// decides it is done), and the step every phase of a column test takes
// (ColumnTestStepper): the triaxial test (triaxial.hpp) and the free-standing
// test (free_standing.hpp) are sequences of phases over the same step.
#pragma once

#include "core/result.hpp"
#include "simulation.hpp"
#include "timestep.hpp"

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>

namespace wiredem::engine {

/// Simulated time of a loading of a column of height `height_m` to
/// `target_axial_strain` at `plate_speed_m_per_s` [s].
[[nodiscard]] double loading_time_s(double target_axial_strain, double height_m, double plate_speed_m_per_s) noexcept;

/// The step every phase of a column test takes, and what a host needs
/// between two steps. `State` is the test driver's own state (a checkpoint
/// saves it with the World): it counts the test's steps (`steps`) and the
/// wall time of the runs before this one (`wall_time_s`), and says whether
/// the live springs' warning is in its `result.warnings`
/// (`live_springs_reported`), so that a continued test does not repeat it.
template <class State>
class ColumnTestStepper {
public:
    using BetweenSteps = std::function<void(const World&, const State&)>;

    /// @param test  what the messages call the test ("the triaxial test")
    ColumnTestStepper(Simulation& sim, const RunControl& control, const BetweenSteps& between_steps, State& st,
        std::string test, std::chrono::steady_clock::time_point wall_start)
        : sim_(sim), control_(control), between_steps_(between_steps), st_(st), test_(std::move(test)),
          wall_start_(wall_start)
    {
    }
    /// The stepper keeps a reference to `between_steps`: a temporary (`{}`)
    /// would dangle after the constructor (ASan found one in the cuboid cell).
    ColumnTestStepper(Simulation& sim, const RunControl& control, BetweenSteps&& between_steps, State& st,
        std::string test, std::chrono::steady_clock::time_point wall_start) = delete;

    /// One step. Before it, a host may take a checkpoint (between_steps: not
    /// before the first step of this run, whose state is the one the run
    /// started from, but also when the run is about to be cancelled, so that
    /// a host saves on its way out); then cancellation is checked and
    /// `prescribe()` sets what the phase prescribes for the step (pressure,
    /// plate and node velocities). After it, a blow-up is an error, so is a
    /// step more than live_contact_tolerance times the limit of the
    /// stiffest live contact (live_limits, every live_check_steps); a step
    /// more than that beyond the stiffest sticking spring's limit (every
    /// live_spring_check_steps) is a warning in the test's result
    /// (`State::result.warnings`), once per test (`State::live_springs_reported`); and
    /// progress is reported every control.progress_every steps as
    /// `progress_of()`, a (done, total) pair.
    /// @return an error message, or nothing
    template <class Prescribe, class Progress>
    [[nodiscard]] std::optional<std::string> step(Prescribe&& prescribe, Progress&& progress_of)
    {
        if (between_steps_ && !first_of_run_) {
            st_.wall_time_s += elapsed_s();
            between_steps_(sim_.world, st_);
            st_.wall_time_s -= elapsed_s();
        }
        first_of_run_ = false;
        if (control_.cancel && control_.cancel->load(std::memory_order_relaxed))
            return "cancelled after " + std::to_string(st_.steps) + " steps of " + test_;
        prescribe();
        const StepReport report = sim_.step();
        ++st_.steps;
        if (report.blew_up) return blow_up_error(sim_.world.dt_s, "after " + std::to_string(st_.steps) + " steps of " + test_);
        // The stiffest live contact, every live_check_steps: a column pressed
        // beyond the overlap its step was set for stops here with what to
        // change, before Gear-5 diverges (docs/model.md, "The stiffest live
        // contact"). It reads the World only: results do not change.
        // The stiffest sticking tangential and rolling springs are reported
        // once per test, not stopped on: beyond Gear-5's bound such a spring
        // breaks at its friction limit and slides, bounded (docs/model.md,
        // "The tangential and rolling springs in the step").
        if (st_.steps % live_check_steps == 0) {
            // The springs every live_spring_check_steps, until reported.
            const bool springs = !st_.live_springs_reported && st_.steps % live_spring_check_steps == 0;
            const LiveLimits live = live_limits(sim_.world, sim_.pool(), springs);
            const auto after = [&] { return "after " + std::to_string(st_.steps) + " steps of " + test_; };
            if (sim_.world.dt_s > live_contact_tolerance * live.contact.critical_s)
                return live_contact_error(live.contact, sim_.world.dt_s, after());
            if (springs && sim_.world.dt_s > live_contact_tolerance * live.springs.critical_s) {
                st_.result.warnings.push_back(live_spring_warning(live.springs, sim_.world.dt_s, after()));
                st_.live_springs_reported = true;
            }
        }
        if (control_.progress && control_.progress_every > 0 && st_.steps % control_.progress_every == 0) {
            const auto [done, total] = progress_of();
            control_.progress(done, total);
        }
        return std::nullopt;
    }

    /// Wall time of the test so far: the runs before this one and this one [s].
    [[nodiscard]] double wall_time_s() const { return st_.wall_time_s + elapsed_s(); }

private:
    [[nodiscard]] double elapsed_s() const
    {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
    }

    Simulation& sim_;
    const RunControl& control_;
    const BetweenSteps& between_steps_;
    State& st_;
    std::string test_;
    std::chrono::steady_clock::time_point wall_start_;
    bool first_of_run_ = true;
};

/// How a loading ended.
enum class LoadingEnd : std::uint8_t {
    target,      ///< the axial strain reached the target
    done,        ///< the test's own criterion ended it before (a failure)
    host,        ///< RunControl::after_step returned false
};

/// The loading loop: `advance()` takes one step (an error message or
/// nothing), `strain_after_step()` reads the axial strain after it (and takes
/// what is due at that strain, snapshots), `done(strain)` is the test's own
/// end before the target. The caller has set the plate moving and stops it.
template <class Advance, class StrainAfterStep, class Done>
[[nodiscard]] Result<LoadingEnd, std::string> load_to_target(const World& w, const RunControl& control,
    double target_axial_strain, Advance&& advance, StrainAfterStep&& strain_after_step, Done&& done)
{
    for (;;) {
        if (auto e = advance()) return Err(std::move(*e));
        const double strain = strain_after_step();
        if (strain >= target_axial_strain) return LoadingEnd::target;
        if (done(strain)) return LoadingEnd::done;
        if (control.after_step && !control.after_step(w, StepReport{})) return LoadingEnd::host;
    }
}

} // namespace wiredem::engine
