#include "simulation.hpp"

#include "integrate/clumps.hpp"

namespace wiredem::engine {

RunOutcome Simulation::run(std::uint64_t steps, const RunControl& control)
{
    RunOutcome out;
    for (; out.steps < steps; ++out.steps) {
        if (control.cancel && control.cancel->load(std::memory_order_relaxed)) {
            out.end = RunEnd::cancelled;
            return out;
        }
        const StepReport r = step();
        if (r.blew_up) {
            ++out.steps;
            out.end = RunEnd::blew_up;
            return out;
        }
        if (control.progress && control.progress_every > 0 && (out.steps + 1) % control.progress_every == 0)
            control.progress(out.steps + 1, steps);
        if (control.after_step && !control.after_step(world, r)) {
            ++out.steps;
            out.end = RunEnd::stopped;
            return out;
        }
    }
    return out;
}

double kinetic_energy_j(const World& w, ThreadPool& pool)
{
    const double inv_dt2 = 1.0 / (w.dt_s * w.dt_s);
    double e = 0.0;
    for (const auto& body : w.bodies) {
        e += reduce_blocks(
            pool, body.size(), 0.0,
            [&](std::size_t b, std::size_t end) {
                double s = 0.0;
                for (std::size_t i = b; i < end; ++i)
                    if (is_dynamic(body, i)) s += 0.5 * body.mass_kg[i] * body.x[1][i].squaredNorm() * inv_dt2;
                return s;
            },
            [](double a, double b) { return a + b; });
    }
    const RotationalState& rot = w.grain_rotation;
    e += reduce_blocks(
        pool, rot.orientation.size(), 0.0,
        [&](std::size_t b, std::size_t end) {
            double s = 0.0;
            for (std::size_t i = b; i < end; ++i)
                if (rot.inv_inertia_per_kg_m2[i] != 0.0)
                    s += 0.5 / rot.inv_inertia_per_kg_m2[i] * rot.theta[1][i].squaredNorm() * inv_dt2;
            return s;
        },
        [](double a, double b) { return a + b; });
    if (!w.clumps.empty()) e += clump_kinetic_energy_j(w); // their spheres weigh nothing
    return e;
}

} // namespace wiredem::engine
