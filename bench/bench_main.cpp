// wiredem-bench: engine throughput at the paper's specimen size.
//
// Settles ~8000 grains (r = 1.23 mm, the paper's material) in a 20 mm-radius
// cylinder, then times steps on the static packing for each thread count.
// Every case starts from the same settled state, and the final states are
// hashed: equal hashes across thread counts show the run is deterministic.
#include "api/engine_settings.hpp"
#include "api/job_spec.hpp"
#include "stages.hpp"
#include "contact/pair_kernel_simd.hpp"
#include "forces/membrane_forces.hpp"
#include "forces/wire_forces.hpp"
#include "io/snapshot.hpp"
#include "laws/hertz.hpp"
#include "scene.hpp"
#include "simulation.hpp"
#include "state/state_hash.hpp"
#include "timestep.hpp"
#include "triaxial/triaxial.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

using namespace wiredem::engine;
namespace api = wiredem::api;
namespace campaign = wiredem::campaign;

namespace {

struct Case {
    std::string name;
    Integrator integrator = Integrator::gear5;
    unsigned threads = 1;
    std::size_t bodies = 0;
    std::size_t contacts = 0;    ///< touching pairs and body–wall contacts at the end
    std::size_t list_pairs = 0;  ///< pairs in the neighbour list (touching or within the skin)
    std::size_t near_pairs = 0;  ///< of those, the near pairs the kernel evaluates (NearPairs)
    std::uint64_t near_selections = 0; ///< selections of the near pairs during the timed steps
    std::uint64_t rebuilds = 0;  ///< neighbour-list rebuilds during the timed steps
    std::uint64_t steps = 0;
    double wall_s = 0.0;
    double cpu_s = 0.0; ///< CPU time of the whole process over the timed steps (all threads)
    std::uint64_t hash = 0;
    StepProfile profile; ///< time per stage over the timed steps
    [[nodiscard]] double body_steps_per_s() const { return static_cast<double>(bodies) * steps / wall_s; }
    [[nodiscard]] double ns_per_contact() const { return wall_s * 1e9 / (static_cast<double>(contacts) * steps); }
};

std::size_t touching(const World& w)
{
    std::size_t n = 0;
    for (auto t : w.contacts.touching) n += t; // body pairs and body–wall contacts
    return n;
}

/// Half the width of the box of a heap's data file (--heap) [m]: the floor
/// the peers' grains may spread over (a grain beyond it is lost to them).
constexpr double heap_box_half_width_m = 0.1;

/// LAMMPS/LIGGGHTS data file (atom_style granular) of the grains, for the
/// side-by-side runs in bench/liggghts; the box is the container's, or
/// heap_box_half_width_m wide for a heap, and as high again above the highest
/// sphere with a tube (--tube: room for the peers to lift it).
void write_liggghts_data(const World& w, const ContainerSpec& spec, const std::string& path, bool heap, bool tube)
{
    const auto& g = w.bodies[0];
    double z_max = 0.0;
    for (const Vec3& x : g.x[0]) z_max = std::max(z_max, x.z());
    std::ofstream out(path);
    out.precision(17);
    out << "wiredem settled packing\n\n" << g.size() << " atoms\n2 atom types\n\n"; // type 2: the walls
    const double half = std::max(spec.container_radius_m * 1.05, heap ? heap_box_half_width_m : 0.0);
    out << -half << ' ' << half << " xlo xhi\n" << -half << ' ' << half << " ylo yhi\n"
        << -0.001 << ' ' << (tube ? 2.0 : 1.0) * z_max + 4 * spec.grain_radius_m << " zlo zhi\n\nAtoms\n\n";
    for (std::size_t i = 0; i < g.size(); ++i)
        out << i + 1 << " 1 " << 2 * g.radius_m[i] << ' ' << spec.grain.density_kg_per_m3 << ' '
            << g.x[0][i].x() << ' ' << g.x[0][i].y() << ' ' << g.x[0][i].z() << '\n';
}

/// The sites of a rough base under a heap (--rough-base): a square lattice of
/// the poured lattice's pitch at z = r, shifted by half a pitch from the poured
/// lattice's columns (a landing grain meets a pocket, not a grain's top), to
/// `radius_m` from the axis.
std::vector<Vec3> rough_base_sites(const ContainerSpec& spec, double radius_m)
{
    const double r = spec.grain_radius_m;
    const double pitch = 2.0 * r * (1.0 + spec.lattice_gap);
    const int half = static_cast<int>(std::floor(radius_m / pitch));
    std::vector<Vec3> sites;
    for (int iy = -half; iy <= half; ++iy)
        for (int ix = -half; ix <= half; ++ix) {
            const double x = (ix + 0.5) * pitch, y = (iy + 0.5) * pitch;
            if (std::hypot(x, y) <= radius_m) sites.emplace_back(x, y, r);
        }
    return sites;
}

/// A rough base under a heap (--rough-base): the poured grains move up by one
/// lattice pitch, and fixed grains of their size fill rough_base_sites. The
/// base grains come after the poured ones (their ids are higher), so the peers
/// can tell them apart by id.
void add_rough_base(World& w, const ContainerSpec& spec, double radius_m)
{
    const double pitch = 2.0 * spec.grain_radius_m * (1.0 + spec.lattice_gap);
    if (!w.clumps.empty()) {
        // Clumps (--clumps): each moves up whole, its spheres with it.
        for (std::uint32_t c = 0; c < w.clumps.size(); ++c) {
            w.clumps.x[0][c] += Vec3(0.0, 0.0, pitch);
            place_clump_spheres(w, c, w.clumps.orientation[c]);
        }
        invalidate_neighbours(w);
    } else {
        const auto poured = static_cast<std::uint32_t>(w.bodies[0].size());
        for (std::uint32_t i = 0; i < poured; ++i)
            place_body(w, BodyRef(BodyKind::grain, i), w.bodies[0].x[0][i] + Vec3(0.0, 0.0, pitch));
    }
    const std::uint8_t material = w.bodies[0].material.at(0);
    for (const Vec3& site : rough_base_sites(spec, radius_m)) {
        const std::uint32_t id = add_grain(w, site, spec.grain_radius_m, material);
        set_motion(w, BodyRef(BodyKind::grain, id), Motion::fixed);
    }
}

/// The tube of a repose heap (--tube): rings of spheres of the grains' size
/// and material around the lattice's cylinder (centres r outside it, so that
/// their inner tops are the cylinder), each ring closed (neighbours at most 2r
/// apart: no grain passes) and turned by half a step from the one below, √3 r
/// higher (the rings touch: a close-packed sheet rolled into a tube). The
/// lowest ring stands 1 % of r clear of the rough base's tops (its centres at
/// 3.03 r: a grain in a pocket of the base cannot pass under it), the highest
/// covers the highest grain. Fixed here; --lift-tube moves them. Their ids
/// follow the base's. Returns how many were added.
std::size_t add_tube(World& w, const ContainerSpec& spec)
{
    const double r = spec.grain_radius_m;
    const double ring_radius = spec.container_radius_m + r;
    const auto per_ring = static_cast<int>(std::ceil(std::numbers::pi / std::asin(r / ring_radius)));
    double top = 0.0;
    for (const Vec3& x : w.bodies[0].x[0]) top = std::max(top, x.z() + r);
    const std::uint8_t material = w.bodies[0].material.at(0);
    std::size_t added = 0;
    for (int ring = 0;; ++ring) {
        const double z = 3.03 * r + ring * std::sqrt(3.0) * r;
        if (z - r > top) break;
        for (int k = 0; k < per_ring; ++k) {
            const double phi = 2.0 * std::numbers::pi * (k + 0.5 * (ring % 2)) / per_ring;
            const std::uint32_t id
                = add_grain(w, Vec3(ring_radius * std::cos(phi), ring_radius * std::sin(phi), z), r, material);
            set_motion(w, BodyRef(BodyKind::grain, id), Motion::fixed);
            ++added;
        }
    }
    return added;
}

/// The lift of a repose heap's tube (--lift-tube): its spheres (grains from
/// `tube_first` on, kinematic) stand still for `hold_s`, then move up at
/// `speed_m_per_s` (a kinematic sphere keeps the velocity it is given), for
/// `all_s` in all.
void hold_then_lift(Simulation& sim, std::size_t tube_first, double hold_s, double all_s, double speed_m_per_s)
{
    World& w = sim.world;
    const auto hold = static_cast<std::uint64_t>(hold_s / w.dt_s);
    const auto all = static_cast<std::uint64_t>(all_s / w.dt_s);
    sim.run(std::min(hold, all));
    for (std::size_t i = tube_first; i < w.bodies[0].size(); ++i)
        set_velocity(w, BodyRef(BodyKind::grain, static_cast<std::uint32_t>(i)), Vec3(0.0, 0.0, speed_m_per_s));
    sim.run(all - std::min(hold, all));
}

/// Replaces the grains of a freshly built container by the packing in a data
/// file written by write_liggghts_data (positions and diameters; the grains
/// start at rest with fresh springs, as LIGGGHTS does when it reads the file).
void read_liggghts_data(World& w, const ContainerSpec& spec, const std::string& path)
{
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read packing file " + path);
    std::string line;
    std::size_t atoms = 0;
    while (std::getline(in, line) && line != "Atoms")
        if (line.find(" atoms") != std::string::npos) atoms = std::stoul(line);
    if (atoms == 0) throw std::runtime_error(path + ": no 'N atoms' line before the Atoms section");
    World fresh;
    ContainerSpec none = spec;
    none.grains = 0;
    build_container(fresh, none);
    fresh.materials = w.materials;
    fresh.contact = w.contact;
    for (std::size_t i = 0; i < atoms;) {
        if (!std::getline(in, line)) throw std::runtime_error(path + ": fewer atoms than declared");
        std::istringstream row(line);
        std::size_t id = 0;
        int type = 0;
        double diameter = 0.0, density = 0.0, x = 0.0, y = 0.0, z = 0.0;
        if (!(row >> id >> type >> diameter >> density >> x >> y >> z)) continue; // blank line
        add_grain(fresh, Vec3(x, y, z), 0.5 * diameter, w.bodies[0].material.at(0));
        ++i;
    }
    fresh.dt_s = w.dt_s;
    w = std::move(fresh);
}

/// CPU time used by this process so far, all threads [s]. On a busy machine
/// the wall time of a one-thread run includes waiting for a core; its CPU time
/// does not.
double process_cpu_s()
{
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Times `steps` steps from the same starting world for each thread count.
std::vector<Case> time_cases(const std::string& name, const World& start, std::uint64_t steps,
    const std::vector<unsigned>& thread_counts, Integrator integrator)
{
    std::vector<Case> cases;
    for (unsigned threads : thread_counts) {
        Simulation sim(threads);
        sim.world = start;
        set_integrator(sim.world, integrator);
        sim.step(); // warm-up outside the timing
        Case c;
        sim.profile = &c.profile;
        const std::uint64_t builds0 = sim.world.neighbour_builds;
        const std::uint64_t selections0 = sim.world.near.selections;
        const double cpu0 = process_cpu_s();
        const auto t0 = std::chrono::steady_clock::now();
        sim.run(steps);
        c.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        c.cpu_s = process_cpu_s() - cpu0;
        c.name = name;
        c.integrator = integrator;
        c.threads = threads;
        c.bodies = sim.world.body_count();
        c.contacts = touching(sim.world);
        c.list_pairs = sim.world.contacts.size();
        c.near_pairs = sim.world.near.pairs.size();
        c.near_selections = sim.world.near.selections - selections0;
        c.rebuilds = sim.world.neighbour_builds - builds0;
        c.steps = steps;
        c.hash = state_hash(sim.world);
        cases.push_back(c);
    }
    return cases;
}

/// The paper-size cell: grains on a loose lattice (gap 0.15 d) inside a
/// deformable membrane under σ₃ = 20 kPa, with the wire threaded through the
/// lattice's free lines: up and down the vertical channels between four
/// grain columns, joined along the horizontal channels of the half-layer
/// planes (a line half a pitch from two rows and two layers is as far from
/// the grain centres, p/√2, as a vertical channel, and clears r_p + r_w).
/// The wire's segments are half a pitch long, so every straight leg is a
/// whole number of segments and ends on a channel line: no node starts
/// inside a grain. Timed from the lattice, so the column is collapsing under
/// gravity while it is timed. (Until 2026-12-02 the legs ended up to a
/// segment short of the channels and the joins ran diagonally through the
/// grains: nodes started deep inside grains and were flung out at 10³ m/s,
/// which rebuilt the neighbour list at nearly every timed step.)
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
    WireSpec wire;
    wire.segment_length_m = 0.5 * pitch;
    configure_wire(w, wire);
    // The channels row by row (y), along each row (x) forth and back, so that
    // no leg crosses a channel that a later run goes up or down.
    std::vector<Vec3> channels;
    const int half = static_cast<int>(spec.container_radius_m / pitch);
    for (int iy = -half; iy < half; ++iy) {
        const std::size_t row = channels.size();
        for (int ix = -half; ix < half; ++ix) {
            const double x = (ix + 0.5) * pitch, y = (iy + 0.5) * pitch;
            if (std::hypot(x, y) < spec.container_radius_m - 2.0 * pitch) channels.emplace_back(x, y, 0.0);
        }
        if ((iy + half) % 2 == 1) std::reverse(channels.begin() + static_cast<std::ptrdiff_t>(row), channels.end());
    }
    const double z_lo = z0 + 0.5 * pitch, z_hi = top - 0.5 * pitch;  // half-layer planes
    Vec3 at = channels.front() + Vec3(0, 0, z_lo);
    const auto room = [&] { return w.of(BodyKind::wire).size() < wire_nodes; };
    append_wire_node(w, at);
    // A straight leg from `at` to `to`, a whole number of segments.
    const auto leg = [&](const Vec3& to) {
        const Vec3 from = at;
        const long segments = std::lround((to - from).norm() / w.wire.segment_length_m);
        for (long k = 1; k <= segments && room(); ++k)
            append_wire_node(w, at = from + (static_cast<double>(k) / static_cast<double>(segments)) * (to - from));
    };
    bool up = true;
    for (std::size_t c = 0; c < channels.size() && room(); ++c) {
        // To the channel in the half-layer plane; from one row's end to the
        // next row's, first along the axis that stays outside both rows (the
        // longer row's end lies beyond the shorter's). Then up or down it.
        const Vec3 target = channels[c] + Vec3(0, 0, at.z());
        if (target.y() != at.y()) {
            const bool target_further_out = std::abs(target.x()) > std::abs(at.x());
            leg(target_further_out ? Vec3(target.x(), at.y(), at.z()) : Vec3(at.x(), target.y(), at.z()));
        }
        leg(target);
        leg(channels[c] + Vec3(0, 0, up ? z_hi : z_lo));
        up = !up;
    }
    // The scene's own check: no wire node starts inside a grain or inside a
    // wire node it may touch (what went wrong before).
    const TranslationalState& grains = w.of(BodyKind::grain);
    const std::vector<Vec3>& nodes = w.of(BodyKind::wire).x[0];
    const double r_w = w.wire.radius_m;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        for (std::size_t g = 0; g < grains.size(); ++g)
            if ((nodes[i] - grains.x[0][g]).norm() < grains.radius_m[g] + r_w)
                throw std::logic_error("wire_membrane_column: wire node " + std::to_string(i) + " starts inside grain "
                                       + std::to_string(g));
        for (std::size_t j = i + w.wire_contact_skip; j < nodes.size(); ++j)
            if ((nodes[i] - nodes[j]).norm() < 2.0 * r_w)
                throw std::logic_error("wire_membrane_column: wire nodes " + std::to_string(i) + " and "
                                       + std::to_string(j) + " start inside each other");
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
    w.dt_s = stable_time_step(w).auto_s;
    return w;
}

/// The engine's name (integrator_names: string literals, so NUL-terminated).
const char* integrator_name(Integrator i) { return to_string(i).data(); }

/// The explicit SIMD paths the run uses (set_simd_kernels and the CPU).
const char* simd_name()
{
    switch (simd_isa()) {
    case SimdIsa::avx512: return "avx512";
    case SimdIsa::avx2: return "avx2";
    case SimdIsa::none: break;
    }
    return "scalar";
}

/// The per-stage profile as a JSON object: seconds per stage.
std::string stages_json(const StepProfile& p)
{
    std::string out = "{";
    for (std::size_t s = 0; s < stage_count; ++s) {
        char item[96];
        std::snprintf(item, sizeof item, "%s\"%s\":%.6f", s ? "," : "", stage_name(static_cast<Stage>(s)).data(),
            p.seconds[s]);
        out += item;
    }
    return out + "}";
}

void print_case_json(const Case& c, double dt)
{
    std::printf("{\"case\":\"%s\",\"integrator\":\"%s\",\"threads\":%u,\"bodies\":%zu,\"contacts\":%zu,\"list_pairs\":%zu,\"near_pairs\":%zu,\"rebuilds\":%llu,"
                "\"near_selections\":%llu,\"steps\":%llu,"
                "\"wall_time_s\":%.6f,\"cpu_time_s\":%.6f,\"time_step_s\":%.6g,\"body_steps_per_second\":%.6g,"
                "\"ns_per_contact\":%s,\"state_hash\":\"%016llx\",\"simd\":\"%s\",\"stage_s\":%s}\n",
        c.name.c_str(), integrator_name(c.integrator), c.threads, c.bodies, c.contacts, c.list_pairs, c.near_pairs,
        static_cast<unsigned long long>(c.rebuilds), static_cast<unsigned long long>(c.near_selections),
        static_cast<unsigned long long>(c.steps), c.wall_s, c.cpu_s, dt,
        c.body_steps_per_s(), c.contacts > 0 ? std::to_string(c.ns_per_contact()).c_str() : "null",
        static_cast<unsigned long long>(c.hash), simd_name(),
        stages_json(c.profile).c_str());
}

/// The cases as a table: throughput, the speed-up and bit-identity against
/// the first thread count of the same case, and the per-stage profile.
void print_table(const std::vector<Case>& cases)
{
    std::printf("\n%-16s %-7s %7s %7s %9s %7s %10s %9s %16s %14s %10s\n", "case", "method", "threads", "bodies",
        "contacts", "steps", "wall [s]", "cpu [s]", "body-steps/s", "ns/contact", "speed-up");
    // Speed-up and bit-identity against the first run of the same case.
    auto first_of = [&](const Case& c) -> const Case& {
        for (const Case& f : cases)
            if (f.name == c.name && f.integrator == c.integrator) return f;
        return c;
    };
    bool same = true;
    for (const Case& c : cases) {
        std::printf("%-16s %-7s %7u %7zu %9zu %7llu %10.3f %9.3f %16.4g %14.4g %9.2fx\n", c.name.c_str(),
            integrator_name(c.integrator), c.threads, c.bodies, c.contacts,
            static_cast<unsigned long long>(c.steps), c.wall_s, c.cpu_s, c.body_steps_per_s(), c.ns_per_contact(),
            first_of(c).wall_s / c.wall_s);
        same = same && c.hash == first_of(c).hash;
    }
    std::printf("final states %s across thread counts; SIMD paths: %s\n", same ? "bit-identical" : "DIFFER", simd_name());
    std::printf("\nper stage, seconds (share of the step):\n");
    for (const Case& c : cases) {
        std::printf("%-16s %-7s %2u:", c.name.c_str(), integrator_name(c.integrator), c.threads);
        const double total = c.profile.total_s();
        for (std::size_t s = 0; s < stage_count; ++s)
            std::printf(" %s %.3f (%.0f%%)", stage_name(static_cast<Stage>(s)).data(), c.profile.seconds[s],
                total > 0.0 ? 100.0 * c.profile.seconds[s] / total : 0.0);
        std::printf("\n");
    }
}

/// Times the World saved in a snapshot file: a prepared specimen or a test's
/// checkpoint. Its walls keep the velocities and the membrane the pressure
/// they had when it was saved (no driver runs), which is what a test step
/// costs; each integrator starts from the same saved state.
int time_specimen(const std::string& path, std::uint64_t steps, const std::vector<unsigned>& thread_counts,
    const std::vector<Integrator>& integrators, bool json)
{
    auto restored = restore_snapshot(path);
    if (!restored) {
        std::fprintf(stderr, "wiredem-bench: %s\n", restored.error().c_str());
        return 1;
    }
    const World& w = restored.value();
    std::vector<Case> cases;
    for (Integrator integrator : integrators) {
        const auto more = time_cases("specimen", w, steps, thread_counts, integrator);
        cases.insert(cases.end(), more.begin(), more.end());
    }
    if (json) {
        for (const Case& c : cases) print_case_json(c, w.dt_s);
        return 0;
    }
    std::printf("specimen %s: %zu grains, %zu wire nodes, %zu membrane nodes, %zu walls, δt = %.3g s, step %llu\n",
        path.c_str(), w.bodies[0].size(), w.bodies[1].size(), w.bodies[2].size(), w.walls.size(), w.dt_s,
        static_cast<unsigned long long>(w.step_count));
    print_table(cases);
    return 0;
}

/// Where a column test's timing starts: at its first step (the σ₃ ramp, the
/// piston consolidating the column) or when its loading starts (the plate
/// at constant speed).
enum class ColumnPhase { start, loading };

/// Times the column test users run: test `index` of the prepared job
/// directory `dir` (`wiredem prepare JOB -o DIR`), driven by run_triaxial as
/// `wiredem test` drives it (the membrane under σ₃, the plate, the wire, the
/// rows sampled), for `steps` steps from `phase` on, for each thread count,
/// each from the same specimen; the state hash where the timing ends shows
/// that the thread counts give the same bits.
int time_column_test(const std::filesystem::path& dir, std::size_t index, ColumnPhase phase, std::uint64_t steps,
    const std::vector<unsigned>& thread_counts, bool json)
{
    const campaign::JobDir job_dir{dir};
    const auto spec = campaign::read_job(job_dir);
    if (!spec.ok()) {
        std::fprintf(stderr, "wiredem-bench: %s\n", spec.error().c_str());
        return 1;
    }
    if (index >= spec.value().triaxial.confining_pressures_pa.size()) {
        std::fprintf(stderr, "wiredem-bench: --test-index %zu: the job has %zu tests\n", index,
            spec.value().triaxial.confining_pressures_pa.size());
        return 1;
    }
    const auto specimen = campaign::read_specimen(job_dir);
    if (!specimen.ok()) {
        std::fprintf(stderr, "wiredem-bench: %s\n", specimen.error().c_str());
        return 1;
    }
    const World& start = specimen.value().world;
    const TriaxialSettings settings = api::triaxial_settings(spec.value(), index);
    std::vector<Case> cases;
    for (unsigned threads : thread_counts) {
        Simulation sim(threads);
        sim.world = start;
        Case c;
        c.name = phase == ColumnPhase::start ? "column_test" : "column_loading";
        c.integrator = sim.world.integrator;
        c.threads = threads;
        c.bodies = sim.world.body_count();
        c.steps = steps;
        std::atomic<bool> stop{false};
        RunControl control;
        control.cancel = &stop;
        std::optional<std::chrono::steady_clock::time_point> t0;
        double cpu0 = 0.0;
        std::uint64_t first = 0, builds0 = 0, selections0 = 0;
        TriaxialContinuation continuation;
        continuation.between_steps = [&](const World& w, const TriaxialDriverState& st) {
            if (stop || (phase == ColumnPhase::loading && !st.loading)) return;
            if (!t0) {
                sim.profile = &c.profile;
                first = st.steps;
                builds0 = w.neighbour_builds;
                selections0 = w.near.selections;
                cpu0 = process_cpu_s();
                t0 = std::chrono::steady_clock::now();
                return;
            }
            if (st.steps - first < steps) return;
            c.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - *t0).count();
            c.cpu_s = process_cpu_s() - cpu0;
            sim.profile = nullptr;
            c.contacts = touching(w);
            c.list_pairs = w.contacts.size();
            c.near_pairs = w.near.pairs.size();
            c.near_selections = w.near.selections - selections0;
            c.rebuilds = w.neighbour_builds - builds0;
            c.hash = state_hash(w);
            stop = true;
        };
        const auto r = run_triaxial(sim, specimen.value().report.top_plate_wall, settings, control, std::move(continuation));
        if (!stop) {
            std::fprintf(stderr, "wiredem-bench: the test %s before %llu timed steps%s\n",
                r.ok() ? "ended" : ("stopped (" + r.error() + ")").c_str(), static_cast<unsigned long long>(steps),
                phase == ColumnPhase::loading ? " of loading" : "");
            return 1;
        }
        cases.push_back(std::move(c));
    }
    if (json) {
        for (const Case& c : cases) print_case_json(c, start.dt_s);
        return 0;
    }
    std::printf("column test %zu of %s (σ₃ = %g Pa): %zu grains, %zu wire nodes, %zu membrane nodes, δt = %.3g s, "
                "timed from the %s\n",
        index, dir.c_str(), settings.confining_pressure_pa, start.bodies[0].size(), start.bodies[1].size(),
        start.bodies[2].size(), start.dt_s, phase == ColumnPhase::start ? "test's first step" : "loading's start");
    print_table(cases);
    return 0;
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
    app.add_option("--seed", spec.seed, "seed of the lattice's jitter (the packing's randomness)");
    double tangential_stiffness = 0.0;
    app.add_option("--tangential-stiffness", tangential_stiffness,
           "k_t of the tangential law [1/m] for the settling and the timing (0: the law's default, 1e5)")
        ->check(CLI::Range(0.0, 1e12));
    app.add_option("--threads", thread_counts, "thread counts to time")->delimiter(',')->check(CLI::Range(1, 256));
    app.add_flag("--json", json, "one JSON object per line and case");
    std::vector<Integrator> integrators{Integrator::gear5, Integrator::verlet};
    app.add_option("--integrators", integrators, "integrators to time (gear5: the reference; verlet)")
        ->delimiter(',')
        ->transform(CLI::CheckedTransformer(
            std::map<std::string, Integrator>{{"gear5", Integrator::gear5}, {"verlet", Integrator::verlet}}));
    bool with_wire_membrane = true;
    std::size_t wire_nodes = 8000;
    app.add_flag("!--no-wire-membrane", with_wire_membrane, "skip the wire + membrane case");
    app.add_option("--wire-nodes", wire_nodes, "wire nodes in the wire + membrane case")->check(CLI::Range(2, 1000000));
    app.add_option("--liggghts-data", liggghts_data, "also write the settled packing as a LIGGGHTS data file");
    std::string packing;
    app.add_option("--packing", packing,
           "time a packing read from a data file written by --liggghts-data instead of settling one (grains at rest)")
        ->check(CLI::ExistingFile);
    std::string specimen;
    app.add_option("--specimen", specimen,
           "time the World saved in FILE (a prepared specimen.h5 or a test's checkpoint, `wiredem prepare` / "
           "`wiredem test`) instead of the built-in cases: the paper's column as the study runs it")
        ->check(CLI::ExistingFile);
    SimdKernels kernels = SimdKernels::automatic;
    app.add_option("--simd", kernels,
           "auto: the AVX-512 paths (contacts, grains' turn, wire, membrane) where the CPU has them, else the AVX2 "
           "contact kernels; avx2: the AVX2 contact kernels even where AVX-512 exists; scalar: the scalar code only "
           "(all give the same results)")
        ->transform(CLI::CheckedTransformer(std::map<std::string, SimdKernels>{
            {"auto", SimdKernels::automatic}, {"avx2", SimdKernels::avx2}, {"scalar", SimdKernels::scalar}}));
    std::string clumps;
    app.add_option("--clumps", clumps,
           "time a packing of clumps of this built-in shape (elongated, flat, tetrahedral, crushed; --grains of them, "
           "of volume-equivalent radius r_p, turned at random) instead of spheres; bodies then counts their spheres")
        ->check(CLI::IsMember(std::vector<std::string>(builtin_clump_names.begin(), builtin_clump_names.end())));
    double sphere_radius = 0.0;
    app.add_option("--grain-radius", sphere_radius, "grain radius r_p [m] (default: the paper's 1.23 mm)")
        ->check(CLI::Range(1e-5, 0.1));
    double rolling_friction = 0.0;
    app.add_option("--rolling-friction", rolling_friction,
           "time the settled packing with rolling resistance μ_r (engine/laws/rolling.hpp; f_r = 1, η_r = 0.3); 0: off")
        ->check(CLI::Range(0.0, 1.0));
    std::string clump_template;
    app.add_option("--clump-template", clump_template,
           "--clumps: also write the first clump's spheres as the engine holds them, one \"x y z r\" line each [m], "
           "in its body frame (origin at the centre of mass): the template a peer code's multisphere reads "
           "(bench/liggghts/clumps_side_by_side.sh)");
    app.add_option("--lattice-radius", spec.container_radius_m,
           "radius of the cylinder the grains' lattice fills [m] (default: 20 mm, the paper's column)")
        ->check(CLI::Range(3e-3, 0.1));
    bool heap = false;
    app.add_flag("--heap", heap,
        "pour a heap: the settling runs without the cylinder (the lattice column, its gaps 0.2 d and its offsets "
        "across the whole gap, falls onto the floor) and with the "
        "rolling law of --rolling-friction from the start, undamped (η_r = 0, as LIGGGHTS' epsd2); the data file's "
        "box is 0.2 m wide (bench/liggghts/heap_physics.sh)");
    double rough_base_m = 0.0;
    app.add_option("--rough-base", rough_base_m,
           "--heap: a layer of fixed grains of the grains' size on the floor, to this radius [m] (their ids follow the "
           "poured grains'); 0: the flat floor")
        ->check(CLI::Range(0.0, 0.09));
    bool tube = false;
    app.add_flag("--tube", tube,
        "--heap with --rough-base: the column settles inside its cylinder (kept) for --settle-time, and the data file "
        "also holds a tube of fixed spheres of the grains' size around it, to its top (their ids follow the base's): "
        "the start of a repose heap (bench/liggghts/repose_physics.sh); with --clumps the tube is there from the start "
        "and the clumps settle in it, without the cylinder (bench/liggghts/clump_repose.sh)");
    double lift_tube_m_per_s = 0.0;
    app.add_option("--lift-tube", lift_tube_m_per_s,
           "--heap with --packing (a file --tube wrote, with the same --grains and --rough-base): the file's grains "
           "after the poured and the base's are the tube, lifted at this speed [m/s] after --tube-hold, without the "
           "cylinder, for --settle-time in all")
        ->check(CLI::Range(1e-4, 10.0));
    double tube_hold_s = 0.0;
    app.add_option("--tube-hold", tube_hold_s, "--lift-tube: the tube stands still this long first [s]")
        ->check(CLI::Range(0.0, 10.0));
    double lift_time_s = 0.0;
    app.add_option("--lift-time", lift_time_s,
           "--clumps with --tube and --lift-tube (no --packing: a peer cannot read clumps from a data file): after "
           "--settle-time in the tube, the tube is held --tube-hold and lifted, this long in all [s] "
           "(bench/liggghts/clump_repose.sh)")
        ->check(CLI::Range(0.0, 10.0));
    std::string lifted_data;
    app.add_option("--lifted-data", lifted_data,
           "with --lift-time: also write the spheres at the lift's end as a LIGGGHTS data file (--liggghts-data "
           "holds them settled, before the lift)");
    std::string column_test;
    app.add_option("--column-test", column_test,
           "time the column test users run: a test of the prepared job directory DIR (`wiredem prepare JOB -o DIR`) "
           "driven as `wiredem test` drives it (membrane under the cell pressure, the plate, the wire, the rows), "
           "instead of the built-in cases")
        ->check(CLI::ExistingDirectory);
    std::size_t test_index = 0;
    app.add_option("--test-index", test_index, "--column-test: which test (an index into confining_pressures_pa)");
    ColumnPhase column_phase = ColumnPhase::start;
    app.add_option("--column-phase", column_phase,
           "--column-test: time from the test's first step (start: σ₃ ramp and consolidation) or from its loading")
        ->transform(CLI::CheckedTransformer(
            std::map<std::string, ColumnPhase>{{"start", ColumnPhase::start}, {"loading", ColumnPhase::loading}}));
    CLI11_PARSE(app, argc, argv);
    set_simd_kernels(kernels);

    if (!column_test.empty())
        return time_column_test(column_test, test_index, column_phase, steps, thread_counts, json);
    if (!specimen.empty()) return time_specimen(specimen, steps, thread_counts, integrators, json);

    // The paper's grains; plates and cylinder with E_b = 1 GPa; e_n = 0.5.
    Simulation settle(0);
    spec.lattice_gap = 0.02;
    if (heap) {
        // A heap's column: gaps of 0.2 d and offsets across the whole gap, so that its
        // layers, landing one on the other, do not stack into vertical chains.
        spec.lattice_gap = 0.2;
        spec.jitter = 1.0;
    }
    if (sphere_radius > 0.0) spec.grain_radius_m = sphere_radius;
    if (!clumps.empty()) spec.clump = unit_clump_shape(*builtin_clump_template(clumps));
    build_container(settle.world, spec);
    World& w = settle.world;
    // e_n = 0.5 for two grains (clumps: of the clump's mass) head-on.
    const double mass = clumps.empty() ? w.bodies[0].mass_kg[0] : w.clumps.mass_kg[0];
    const double e_star = effective_modulus_pa(spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio,
        spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio);
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.5, 0.5 * mass, 0.1, e_star, 0.5 * spec.grain_radius_m);
    if (tangential_stiffness > 0.0) w.contact.tangential.stiffness_per_m = tangential_stiffness;
    w.dt_s = stable_time_step(w).auto_s;
    const bool lift = lift_tube_m_per_s > 0.0;
    // Clumps in a tube: they settle in the tube of spheres itself and the same run lifts it.
    const bool clump_tube = tube && !clumps.empty();
    if (tube && (!heap || rough_base_m <= 0.0 || !packing.empty())) {
        std::fprintf(stderr, "wiredem-bench: --tube needs --heap and --rough-base, without --packing\n");
        return 2;
    }
    if ((lift_time_s > 0.0 || !lifted_data.empty()) != (clump_tube && lift)
        || (clump_tube && lift && lift_time_s <= 0.0)) {
        std::fprintf(stderr, "wiredem-bench: --clumps --tube --lift-tube needs --lift-time (and takes --lifted-data); "
                             "without them neither\n");
        return 2;
    }
    if (!clump_tube && lift != !packing.empty() && heap) {
        std::fprintf(stderr, "wiredem-bench: --heap --packing FILE needs --lift-tube (FILE written by --tube), and "
                             "--lift-tube needs --packing\n");
        return 2;
    }
    if (lift && (!heap || rough_base_m <= 0.0)) {
        std::fprintf(stderr, "wiredem-bench: --lift-tube needs --heap, --rough-base and --packing\n");
        return 2;
    }
    if (!packing.empty()) {
        read_liggghts_data(w, spec, packing);
        if (!lift) settle_s = 0.0;
    }
    std::size_t tube_first = 0; // --lift-tube: the tube's first id
    if (heap) {
        // The lattice's cylinder goes (build_container's second wall), but while a
        // repose heap's column settles in it (--tube); the rolling law acts while the heap forms.
        if (w.walls.size() < 2 || w.walls[1].shape != Wall::Shape::cylinder)
            throw std::logic_error("--heap: the container's second wall is not its cylinder");
        if (!tube) remove_wall(w, 1);
        w.contact.rolling = RollingParams{rolling_friction, 1.0, 0.0};
        if (lift && !clump_tube) {
            // The file's poured grains, its base (as --rough-base makes it) and its tube.
            const std::vector<Vec3> sites = rough_base_sites(spec, rough_base_m);
            tube_first = spec.grains + sites.size();
            const auto& x = w.bodies[0].x[0];
            bool same_base = x.size() > tube_first && std::abs(x[tube_first].z() - spec.grain_radius_m) > 1e-9;
            for (std::size_t k = 0; same_base && k < sites.size(); ++k)
                same_base = (x[spec.grains + k] - sites[k]).norm() < 1e-9;
            if (!same_base)
                throw std::runtime_error(packing + ": its spheres after the first " + std::to_string(spec.grains)
                                         + " are not --rough-base's base and then a tube (write it with --tube and the "
                                           "same --grains, --rough-base and --lattice-radius)");
            for (std::size_t i = spec.grains; i < w.bodies[0].size(); ++i)
                set_motion(w, BodyRef(BodyKind::grain, static_cast<std::uint32_t>(i)),
                    i < tube_first ? Motion::fixed : Motion::kinematic);
        } else if (rough_base_m > 0.0) {
            add_rough_base(w, spec, rough_base_m);
            if (clump_tube) {
                // A peer's multisphere cannot start from a data file of clumps, so each code
                // fills the tube with its own clumps: the tube is there from the start, the
                // cylinder (its inner tops) goes.
                tube_first = w.bodies[0].size();
                add_tube(w, spec);
                remove_wall(w, 1);
            }
        }
    } else if (rough_base_m > 0.0) {
        std::fprintf(stderr, "wiredem-bench: --rough-base needs --heap\n");
        return 2;
    }
    if (!clump_template.empty() && w.clumps.empty()) {
        std::fprintf(stderr, "wiredem-bench: --clump-template needs --clumps\n");
        return 2;
    }
    const auto t0 = std::chrono::steady_clock::now();
    if (lift && !clump_tube) {
        hold_then_lift(settle, tube_first, tube_hold_s, settle_s, lift_tube_m_per_s);
    } else {
        settle.run(static_cast<std::uint64_t>(settle_s / w.dt_s));
    }
    if (clump_tube) {
        const std::size_t base = rough_base_sites(spec, rough_base_m).size();
        std::fprintf(stderr, "tube: %zu poured spheres (%zu clumps), %zu base grains, %zu tube spheres\n",
            tube_first - base, w.clumps.size(), base, w.bodies[0].size() - tube_first);
    } else if (tube) {
        const std::size_t poured = spec.grains, base = rough_base_sites(spec, rough_base_m).size();
        std::fprintf(stderr, "tube: %zu poured grains, %zu base grains, %zu tube spheres\n", poured, base, add_tube(w, spec));
    }
    const double settle_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!json)
        std::printf("settled %zu grains for %.3f s simulated (δt = %.3g s, %llu steps) in %.1f s wall; "
                    "kinetic energy %.3g J\n",
            w.bodies[0].size(), settle_s, w.dt_s, static_cast<unsigned long long>(w.step_count), settle_wall,
            kinetic_energy_j(w, settle.pool()));
    if (heap)
        std::fprintf(stderr, "heap: %zu grains, kinetic energy %.6g J after %.6g s\n", w.bodies[0].size(),
            kinetic_energy_j(w, settle.pool()), settle_s);
    if (!liggghts_data.empty()) write_liggghts_data(w, spec, liggghts_data, heap, tube || lift_tube_m_per_s > 0.0);
    if (clump_tube && lift) {
        for (std::size_t i = tube_first; i < w.bodies[0].size(); ++i)
            set_motion(w, BodyRef(BodyKind::grain, static_cast<std::uint32_t>(i)), Motion::kinematic);
        hold_then_lift(settle, tube_first, tube_hold_s, lift_time_s, lift_tube_m_per_s);
        std::fprintf(stderr, "lifted: kinetic energy %.6g J after %.6g s more\n", kinetic_energy_j(w, settle.pool()),
            lift_time_s);
        if (!lifted_data.empty()) write_liggghts_data(w, spec, lifted_data, heap, true);
    }
    if (!clump_template.empty()) {
        std::ofstream out(clump_template);
        out.precision(17);
        for (std::uint32_t k = 0; k < w.clumps.member_count[0]; ++k) {
            const std::uint32_t g = w.clumps.first_member[0] + k;
            const Vec3& o = w.clumps.member_offset_m[g];
            out << o.x() << ' ' << o.y() << ' ' << o.z() << ' ' << w.bodies[0].radius_m[g] << '\n';
        }
        if (!out) {
            std::fprintf(stderr, "cannot write %s\n", clump_template.c_str());
            return 1;
        }
    }
    // Timed with the rolling law from here on (its springs start unwound).
    w.contact.rolling = RollingParams{rolling_friction, 1.0, rolling_friction > 0.0 ? 0.3 : 0.0};

    std::vector<Case> cases;
    for (Integrator integrator : integrators) {
        const auto more = time_cases(clumps.empty() ? "settled_packing" : "clump_packing", w, steps, thread_counts, integrator);
        cases.insert(cases.end(), more.begin(), more.end());
    }
    std::vector<double> dts(cases.size(), w.dt_s);
    if (with_wire_membrane) {
        const World column = wire_membrane_column(spec, wire_nodes);
        for (Integrator integrator : integrators) {
            const auto more = time_cases("wire_membrane", column, steps, thread_counts, integrator);
            cases.insert(cases.end(), more.begin(), more.end());
        }
        dts.insert(dts.end(), cases.size() - dts.size(), column.dt_s);
        if (!json)
            std::printf("wire_membrane: %zu grains, %zu wire nodes, %zu membrane nodes, δt = %.3g s (set by %s)\n",
                column.bodies[0].size(), column.bodies[1].size(), column.bodies[2].size(), column.dt_s,
                stable_time_step(column).limited_by.c_str());
    }
    if (json)
        for (std::size_t i = 0; i < cases.size(); ++i) print_case_json(cases[i], dts[i]);
    if (!json) print_table(cases);
    return 0;
}
