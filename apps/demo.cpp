// wiredem-demo: pours nothing yet — drops a few hundred grains into a
// cylinder, lets them settle and reports what the engine did. The main job
// until the triaxial campaign exists.
#include "laws/hertz.hpp"
#include "scene.hpp"
#include "simulation.hpp"
#include "timestep.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

using namespace wiredem::engine;

int main(int argc, char** argv)
{
    CLI::App app{"wiredem-demo: settle a small pile of grains in a cylinder"};
    ContainerSpec spec;
    spec.container_radius_m = 8e-3;
    spec.grains = 500;
    spec.lattice_gap = 0.3;
    unsigned threads = 0;
    double duration_s = 0.2;
    app.add_option("--grains", spec.grains, "number of grains")->check(CLI::Range(1, 100000));
    app.add_option("--threads", threads, "threads (0 = all cores)")->check(CLI::Range(0, 256));
    app.add_option("--time", duration_s, "simulated time [s]")->check(CLI::Range(1e-4, 10.0));
    CLI11_PARSE(app, argc, argv);

    Simulation sim(threads);
    build_container(sim.world, spec);
    World& w = sim.world;
    const double mass = w.bodies[0].mass_kg[0];
    const double e_star = effective_modulus_pa(spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio,
        spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio);
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.5, 0.5 * mass, 0.1, e_star, 0.5 * spec.grain_radius_m);
    const StableStep crit = stable_time_step(w);
    w.dt_s = crit.auto_s;
    std::printf("%zu grains (r = %.2f mm) in a %.0f mm-radius cylinder, %u threads\n", spec.grains,
        spec.grain_radius_m * 1e3, spec.container_radius_m * 1e3, sim.threads());
    std::printf("critical δt %.3g s (limited by %s), using %.3g s; γ_n = %.3g s for e_n = 0.5 at 0.1 m/s\n",
        crit.critical_s, crit.limited_by.c_str(), w.dt_s, w.contact.normal_damping_s);

    const auto steps = static_cast<std::uint64_t>(duration_s / w.dt_s);
    const auto start = std::chrono::steady_clock::now();
    RunControl control;
    control.progress_every = steps / 10;
    control.progress = [&](std::uint64_t done, std::uint64_t total) {
        std::printf("  %3.0f %%  t = %.4f s  kinetic energy %.3e J  contacts %zu\n", 100.0 * done / total, w.time_s,
            kinetic_energy_j(w, sim.pool()), w.contacts.size());
    };
    const RunOutcome out = sim.run(steps, control);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double weight = mass * 10.0 * w.bodies[0].size();
    std::printf("%llu steps in %.2f s: %.3g body-steps/s; floor carries %.1f %% of the weight (the rest hangs on the "
                "cylinder by friction)\n",
        static_cast<unsigned long long>(out.steps), wall, static_cast<double>(w.body_count()) * out.steps / wall,
        -100.0 * w.wall_loads[0].total_force_n.z() / weight);
    return out.end == RunEnd::completed ? 0 : 1;
}
