// wiredem-bench: engine throughput at the paper's specimen size.
//
// Settles ~8000 grains (r = 1.23 mm, the paper's material) in a 20 mm-radius
// cylinder, then times steps on the static packing for each thread count.
// Every case starts from the same settled state, and the final states are
// hashed: equal hashes across thread counts show the run is deterministic.
#include "core/hash.hpp"
#include "forces/membrane_forces.hpp"
#include "forces/wire_forces.hpp"
#include "laws/hertz.hpp"
#include "scene.hpp"
#include "simulation.hpp"
#include "timestep.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

using namespace wiredem::engine;

namespace {

struct Case {
    std::string name;
    unsigned threads = 1;
    std::size_t bodies = 0;
    std::size_t contacts = 0;
    std::uint64_t steps = 0;
    double wall_s = 0.0;
    std::uint64_t hash = 0;
    [[nodiscard]] double body_steps_per_s() const { return static_cast<double>(bodies) * steps / wall_s; }
    [[nodiscard]] double ns_per_contact() const { return wall_s * 1e9 / (static_cast<double>(contacts) * steps); }
};

std::uint64_t hash_world(const World& w)
{
    Fnv1a h;
    for (const auto& body : w.bodies)
        for (const auto& x : body.x) h.add(x);
    for (const auto& x : w.grain_rotation.w) h.add(x);
    return h.value();
}

std::size_t touching(const World& w)
{
    std::size_t n = 0;
    for (auto t : w.contacts.touching) n += t;
    for (const Wall& wall : w.walls) n += wall.contacts;
    return n;
}

/// LAMMPS/LIGGGHTS data file (atom_style granular) of the grains, for the
/// side-by-side run in bench/liggghts.
void write_liggghts_data(const World& w, const ContainerSpec& spec, const std::string& path)
{
    const auto& g = w.bodies[0];
    double z_max = 0.0;
    for (const Vec3& x : g.x[0]) z_max = std::max(z_max, x.z());
    std::ofstream out(path);
    out.precision(17);
    out << "wiredem settled packing\n\n" << g.size() << " atoms\n2 atom types\n\n"; // type 2: the walls
    const double half = spec.container_radius_m * 1.05;
    out << -half << ' ' << half << " xlo xhi\n" << -half << ' ' << half << " ylo yhi\n"
        << -0.001 << ' ' << z_max + 4 * spec.grain_radius_m << " zlo zhi\n\nAtoms\n\n";
    for (std::size_t i = 0; i < g.size(); ++i)
        out << i + 1 << " 1 " << 2 * g.radius_m[i] << ' ' << spec.grain.density_kg_per_m3 << ' '
            << g.x[0][i].x() << ' ' << g.x[0][i].y() << ' ' << g.x[0][i].z() << '\n';
}

/// Times `steps` steps from the same starting world for each thread count.
std::vector<Case> time_cases(const std::string& name, const World& start, std::uint64_t steps,
    const std::vector<unsigned>& thread_counts)
{
    std::vector<Case> cases;
    for (unsigned threads : thread_counts) {
        Simulation sim(threads);
        sim.world = start;
        sim.step(); // warm-up outside the timing
        const auto t0 = std::chrono::steady_clock::now();
        sim.run(steps);
        Case c;
        c.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        c.name = name;
        c.threads = threads;
        c.bodies = sim.world.body_count();
        c.contacts = touching(sim.world);
        c.steps = steps;
        c.hash = hash_world(sim.world);
        cases.push_back(c);
    }
    return cases;
}

/// The paper-size cell: grains on a loose lattice (gap 0.15 d) inside a
/// deformable membrane under σ₃ = 20 kPa, with the wire threaded as a
/// serpentine through the lattice's free channels (vertical runs between four
/// grain columns, joined in the half-layer planes). Timed from the lattice, so
/// the column is collapsing under gravity while it is timed.
World wire_membrane_column(const ContainerSpec& base, std::size_t wire_nodes)
{
    World w;
    ContainerSpec spec = base;
    spec.lattice_gap = 0.15; // channels between four grain columns clear r_p + r_w
    const double top = build_container(w, spec);
    w.walls.pop_back(); // the membrane replaces the cylinder wall
    const double r = spec.grain_radius_m;
    const double pitch = 2.0 * r * (1.0 + spec.lattice_gap);
    const double z0 = r + 0.5 * (pitch - 2.0 * r);
    configure_wire(w, WireSpec{});
    const double lw = w.wire.segment_length_m;
    std::vector<Vec3> channels;
    const int half = static_cast<int>(spec.container_radius_m / pitch);
    for (int iy = -half; iy < half; ++iy)
        for (int ix = -half; ix < half; ++ix) {
            const double x = (ix + 0.5) * pitch, y = (iy + 0.5) * pitch;
            if (std::hypot(x, y) < spec.container_radius_m - 2.0 * pitch) channels.emplace_back(x, y, 0.0);
        }
    const double z_lo = z0 + 0.5 * pitch, z_hi = top - 0.5 * pitch;
    bool up = true;
    Vec3 at = channels.front() + Vec3(0, 0, z_lo);
    append_wire_node(w, at);
    for (std::size_t c = 0; c < channels.size() && w.of(BodyKind::wire).size() < wire_nodes; ++c) {
        // Across to the channel (in the half-layer plane), then along it.
        const Vec3 target = channels[c] + Vec3(0, 0, at.z());
        for (Vec3 d = target - at; d.norm() >= lw && w.of(BodyKind::wire).size() < wire_nodes; d = target - at)
            append_wire_node(w, at += lw * d.normalized());
        const double z_end = up ? z_hi : z_lo;
        while (std::abs(z_end - at.z()) >= lw && w.of(BodyKind::wire).size() < wire_nodes)
            append_wire_node(w, at += Vec3(0, 0, up ? lw : -lw));
        up = !up;
    }
    MembraneSpec m;
    m.radius_m = spec.container_radius_m + m.contact_radius_m; // grains' outer surface meets the node spheres
    m.height_m = top + 2.0 * pitch;
    build_membrane(w, m);
    set_membrane_rigid(w, false);
    w.membrane.pressure_pa = 20e3;
    const double mass = w.bodies[0].mass_kg[0];
    const double e_star = effective_modulus_pa(spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio,
        spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio);
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.5, 0.5 * mass, 0.1, e_star, 0.5 * spec.grain_radius_m);
    w.dt_s = auto_time_step_fraction * critical_time_step(w).critical_s;
    return w;
}

void print_case_json(const Case& c, double dt)
{
    std::printf("{\"case\":\"%s\",\"threads\":%u,\"bodies\":%zu,\"contacts\":%zu,\"steps\":%llu,"
                "\"wall_time_s\":%.6f,\"time_step_s\":%.6g,\"body_steps_per_second\":%.6g,"
                "\"ns_per_contact\":%.4g,\"state_hash\":\"%016llx\"}\n",
        c.name.c_str(), c.threads, c.bodies, c.contacts, static_cast<unsigned long long>(c.steps), c.wall_s, dt,
        c.body_steps_per_s(), c.ns_per_contact(), static_cast<unsigned long long>(c.hash));
}

} // namespace

int main(int argc, char** argv)
{
    CLI::App app{"wiredem-bench: DEM engine throughput on a settled packing at the paper's size"};
    ContainerSpec spec;
    std::uint64_t steps = 2000;
    double settle_s = 0.2;
    std::vector<unsigned> thread_counts{1, 2};
    bool json = false;
    std::string liggghts_data;
    app.add_option("--grains", spec.grains, "number of grains")->check(CLI::Range(10, 2000000));
    app.add_option("--steps", steps, "timed steps per case")->check(CLI::Range(1, 100000000));
    app.add_option("--settle-time", settle_s, "simulated settling time before timing [s]")->check(CLI::Range(0.0, 10.0));
    app.add_option("--threads", thread_counts, "thread counts to time")->delimiter(',')->check(CLI::Range(1, 256));
    app.add_flag("--json", json, "one JSON object per line and case");
    bool with_wire_membrane = true;
    std::size_t wire_nodes = 8000;
    app.add_flag("!--no-wire-membrane", with_wire_membrane, "skip the wire + membrane case");
    app.add_option("--wire-nodes", wire_nodes, "wire nodes in the wire + membrane case")->check(CLI::Range(2, 1000000));
    app.add_option("--liggghts-data", liggghts_data, "also write the settled packing as a LIGGGHTS data file");
    CLI11_PARSE(app, argc, argv);

    // The paper's grains; plates and cylinder with E_b = 1 GPa; e_n = 0.5.
    Simulation settle(0);
    spec.lattice_gap = 0.02;
    build_container(settle.world, spec);
    World& w = settle.world;
    const double mass = w.bodies[0].mass_kg[0];
    const double e_star = effective_modulus_pa(spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio,
        spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio);
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.5, 0.5 * mass, 0.1, e_star, 0.5 * spec.grain_radius_m);
    w.dt_s = auto_time_step_fraction * critical_time_step(w).critical_s;
    const auto t0 = std::chrono::steady_clock::now();
    settle.run(static_cast<std::uint64_t>(settle_s / w.dt_s));
    const double settle_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!json)
        std::printf("settled %zu grains for %.3f s simulated (δt = %.3g s, %llu steps) in %.1f s wall; "
                    "kinetic energy %.3g J\n",
            w.bodies[0].size(), settle_s, w.dt_s, static_cast<unsigned long long>(w.step_count), settle_wall,
            kinetic_energy_j(w, settle.pool()));
    if (!liggghts_data.empty()) write_liggghts_data(w, spec, liggghts_data);

    std::vector<Case> cases = time_cases("settled_packing", w, steps, thread_counts);
    std::vector<double> dts(cases.size(), w.dt_s);
    if (with_wire_membrane) {
        const World column = wire_membrane_column(spec, wire_nodes);
        const auto more = time_cases("wire_membrane", column, steps, thread_counts);
        cases.insert(cases.end(), more.begin(), more.end());
        dts.insert(dts.end(), more.size(), column.dt_s);
        if (!json)
            std::printf("wire_membrane: %zu grains, %zu wire nodes, %zu membrane nodes, δt = %.3g s (set by %s)\n",
                column.bodies[0].size(), column.bodies[1].size(), column.bodies[2].size(), column.dt_s,
                critical_time_step(column).limited_by.c_str());
    }
    if (json)
        for (std::size_t i = 0; i < cases.size(); ++i) print_case_json(cases[i], dts[i]);
    if (!json) {
        std::printf("\n%-16s %7s %7s %9s %7s %10s %16s %14s %10s\n", "case", "threads", "bodies", "contacts", "steps",
            "wall [s]", "body-steps/s", "ns/contact", "speed-up");
        // Speed-up and bit-identity against the first run of the same case.
        auto first_of = [&](const Case& c) -> const Case& {
            for (const Case& f : cases)
                if (f.name == c.name) return f;
            return c;
        };
        bool same = true;
        for (const Case& c : cases) {
            std::printf("%-16s %7u %7zu %9zu %7llu %10.3f %16.4g %14.4g %9.2fx\n", c.name.c_str(), c.threads, c.bodies,
                c.contacts, static_cast<unsigned long long>(c.steps), c.wall_s, c.body_steps_per_s(), c.ns_per_contact(),
                first_of(c).wall_s / c.wall_s);
            same = same && c.hash == first_of(c).hash;
        }
        std::printf("final states %s across thread counts\n", same ? "bit-identical" : "DIFFER");
    }
    return 0;
}
