// A World with its thread pool and a run loop that a host program can stop
// and watch (cancellation flag, progress callback).
#pragma once

#include "parallel/thread_pool.hpp"
#include "state/world.hpp"
#include "step.hpp"

#include <atomic>
#include <cstdint>
#include <functional>

namespace wiredem::engine {

/// How a host controls a run. All members optional.
struct RunControl {
    /// Set to true (from any thread) to stop the run at the next step boundary.
    const std::atomic<bool>* cancel = nullptr;
    /// Called on the running thread every `progress_every` steps with
    /// (steps done in this run, steps requested).
    std::function<void(std::uint64_t, std::uint64_t)> progress;
    std::uint64_t progress_every = 1000;
    /// Called after every step; return false to stop early (e.g. settled).
    std::function<bool(const World&, const StepReport&)> after_step;
};

/// Why a run ended.
enum class RunEnd { completed, stopped, cancelled, blew_up };

struct RunOutcome {
    std::uint64_t steps = 0;
    RunEnd end = RunEnd::completed;
};

/// Owns the thread pool for a world.
class Simulation {
public:
    /// @param threads worker threads, caller included; 0 = all cores
    explicit Simulation(unsigned threads = 0) : pool_(threads) {}

    World world;
    /// When set, every step adds its time per stage to it (engine/profile.hpp).
    StepProfile* profile = nullptr;

    [[nodiscard]] ThreadPool& pool() { return pool_; }
    [[nodiscard]] unsigned threads() const { return pool_.size(); }

    /// One step.
    StepReport step() { return engine::step(world, pool_, profile); }

    /// Up to `steps` steps; stops early on cancellation, on after_step
    /// returning false, or when the state blows up.
    RunOutcome run(std::uint64_t steps, const RunControl& control = {});

private:
    ThreadPool pool_;
};

/// Kinetic energy (translational + rotational) of all moving bodies [J],
/// summed deterministically.
[[nodiscard]] double kinetic_energy_j(const World& w, ThreadPool& pool);

} // namespace wiredem::engine
