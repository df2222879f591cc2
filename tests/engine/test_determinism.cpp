// Bit-identical results whatever the number of threads.
#include "contact/pair_kernel_simd.hpp"
#include "helpers.hpp"
#include "scene.hpp"
#include "state/state_hash.hpp"
#include "timestep.hpp"
#include "wired_column.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>
#include <string>

using namespace wiredem::engine;

namespace {

/// A small column of grains falling into a cylinder, kicked so that
/// contacts form, slide and break early.
void build_column(Simulation& sim, Integrator integrator)
{
    sim.world.integrator = integrator;
    test::build_kicked_column(sim.world, 7, 3, 1.0);
}

/// That column's state hash every 250 steps.
std::vector<std::uint64_t> run_column(unsigned threads, Integrator integrator = Integrator::gear5)
{
    Simulation sim(threads);
    build_column(sim, integrator);
    std::vector<std::uint64_t> hashes;
    for (int block = 0; block < 8; ++block) {
        sim.run(250);
        hashes.push_back(state_hash(sim.world));
    }
    EXPECT_GT(sim.world.contacts.size(), 0u);
    return hashes;
}

/// A block of grains on a cubic lattice, each pressed 1 % of its radius
/// into its six neighbours: at rest, their contacts stick and hold. Every
/// fifth grain spins fast, so its contacts slide. `stats`, when given,
/// receives over the run the longest stretch of consecutive touching
/// contacts that all stick, and how many touching contacts slide.
struct StickSlideStats {
    std::size_t longest_sticking_run = 0, sliding = 0;
};
std::uint64_t run_lattice(unsigned threads, Integrator integrator, StickSlideStats* stats = nullptr)
{
    Simulation sim(threads);
    World& w = sim.world;
    // Built twice: a grain's spin is stored as ω δt, so δt comes first.
    double dt_s = 0.0;
    for (int pass = 0; pass < 2; ++pass) {
        test::reset_world(w, Material{1e8, 0.3, 2600.0}, dt_s, 1e-5);
        w.integrator = integrator;
        const double r = 1e-3, spacing = 1.98 * r;
        std::uint32_t i = 0;
        for (int z = 0; z < 4; ++z)
            for (int y = 0; y < 8; ++y)
                for (int x = 0; x < 8; ++x, ++i) {
                    const Vec3 spin = i % 5 == 0 ? Vec3(0.0, 0.0, 300.0) : Vec3::Zero();
                    add_grain(w, Vec3(x * spacing, y * spacing, z * spacing), r, 0, Vec3::Zero(), spin);
                }
        dt_s = stable_time_step(w).auto_s;
    }
    for (int s = 0; s < 200; ++s) {
        sim.step();
        if (stats == nullptr) continue;
        const ContactList& c = w.contacts;
        std::size_t run = 0;
        for (std::size_t p = 0; p < c.size(); ++p) {
            if (!c.touching[p]) continue;
            run = c.tangential[p].sticking ? run + 1 : 0;
            stats->longest_sticking_run = std::max(stats->longest_sticking_run, run);
            stats->sliding += !c.tangential[p].sticking;
        }
    }
    return state_hash(w);
}

} // namespace

TEST(Determinism, StateHashIdenticalFor1To4Threads)
{
    const auto reference = run_column(1);
    for (unsigned threads : {2u, 3u, 4u}) EXPECT_EQ(run_column(threads), reference) << threads << " threads";
}

TEST(Determinism, VerletStateHashIdenticalFor1And3Threads)
{
    const auto reference = run_column(1, Integrator::verlet);
    EXPECT_EQ(run_column(3, Integrator::verlet), reference);
    EXPECT_NE(reference, run_column(1)); // the integrator really changed
}

TEST(Determinism, SameSeedSameScene)
{
    EXPECT_EQ(run_column(2), run_column(2));
}

/// The column with wire, membrane and a moving plate (wired_column.hpp):
/// its state hash every 100 steps on 1 to 4 threads, for both integrators.
TEST(Determinism, WiredColumnStateHashIdenticalFor1To4Threads)
{
    for (Integrator integrator : {Integrator::gear5, Integrator::verlet}) {
        std::vector<std::uint64_t> reference;
        for (unsigned threads : {1u, 2u, 3u, 4u}) {
            Simulation sim(threads);
            test::build_wired_column(sim.world, integrator);
            std::vector<std::uint64_t> hashes;
            for (int block = 0; block < 4; ++block) {
                ASSERT_EQ(sim.run(100).end, RunEnd::completed);
                hashes.push_back(state_hash(sim.world));
            }
            if (threads == 1) reference = hashes;
            else EXPECT_EQ(hashes, reference) << threads << " threads";
        }
    }
}

/// Gear-5's corrector predicts the next step's x₀ and x₁ while it holds the
/// corrected derivatives, and the next step takes them (Caches::
/// next_prediction). A run that drops that prediction before every step, so
/// that each step predicts from the stored derivatives, must give the same
/// bits: in the wired column (grains turning, wire, deformable membrane with
/// kinematic and fixed rows, a moving plate) on 1 and 3 threads, and across
/// every mutator that changes a body between steps. A mutator that left the
/// prediction in place would step the run that keeps it from stale values.
TEST(Determinism, GearsKeptPredictionGivesTheBitsOfAFreshOne)
{
    for (unsigned threads : {1u, 3u}) {
        Simulation kept(threads), fresh(threads);
        test::build_wired_column(kept.world, Integrator::gear5);
        test::build_wired_column(fresh.world, Integrator::gear5);
        // Between steps, each mutator of a body once, the same in both runs.
        const auto mutate = [](World& w, int at) {
            const std::uint32_t g = 5;
            switch (at) {
            case 100: set_velocity(w, {BodyKind::grain, g}, Vec3(0.01, 0.0, 0.02)); break;
            case 150:
                place_body(w, {BodyKind::grain, g + 1}, w.of(BodyKind::grain).x[0][g + 1] + Vec3(0, 0, 1e-6));
                break;
            case 200: set_motion(w, {BodyKind::grain, g + 2}, Motion::kinematic); break;
            case 220: set_velocity(w, {BodyKind::grain, g + 2}, Vec3(0.0, 0.0, -0.01)); break;
            case 250: set_motion(w, {BodyKind::grain, g + 2}, Motion::dynamic); break;
            case 280: set_time_step(w, 0.9 * w.dt_s); break;
            case 300: scale_velocities(w, 0.5); break;
            case 330: // outside the membrane
                (void)add_grain(w, Vec3(0.02, 0.0, 4e-3), 1e-3, 0, Vec3(0.0, 0.0, -0.1));
                break;
            case 360: set_integrator(w, Integrator::verlet); break;
            case 380: set_integrator(w, Integrator::gear5); break;
            default: break;
            }
            // At step 390 the membrane's fixed top row becomes kinematic;
            // from step 400 on its velocity is prescribed before every step,
            // as a column test carries its cap nodes with the plate
            // (carry_with_cap): that keeps the prediction (it holds the
            // dynamic bodies only), and must keep the bits.
            TranslationalState& nodes = w.of(BodyKind::membrane);
            double top_z = -std::numeric_limits<double>::infinity();
            for (const Vec3& x : nodes.x[0]) top_z = std::max(top_z, x.z());
            for (std::uint32_t i = 0; i < nodes.size(); ++i) {
                if (at == 390 && nodes.motion[i] == Motion::fixed && nodes.x[0][i].z() == top_z)
                    set_motion(w, {BodyKind::membrane, i}, Motion::kinematic);
                if (at >= 400 && nodes.motion[i] == Motion::kinematic)
                    set_velocity(w, {BodyKind::membrane, i}, Vec3(0.0, 0.0, -1e-5 * (at - 399)));
            }
        };
        for (int s = 0; s < 500; ++s) {
            mutate(kept.world, s);
            if (s >= 400) {
                const std::vector<Motion>& motion = kept.world.of(BodyKind::membrane).motion;
                ASSERT_NE(std::count(motion.begin(), motion.end(), Motion::kinematic), 0) << "a kinematic top row";
                ASSERT_EQ(kept.world.next_prediction.for_step, kept.world.step_count) << "step " << s;
            }
            mutate(fresh.world, s);
            invalidate_prediction(fresh.world);
            ASSERT_FALSE(kept.step().blew_up) << "step " << s;
            ASSERT_FALSE(fresh.step().blew_up);
            if (s % 50 == 49) {
                ASSERT_EQ(state_hash(kept.world), state_hash(fresh.world))
                    << "step " << s << ", " << threads << " threads";
            }
        }
        EXPECT_EQ(kept.world.next_prediction.for_step, kept.world.step_count) << "the last step left a prediction";
    }
}

/// Point loads (World::point_loads; a column test's wire weight under mass
/// scaling) are added in the gather's blocks, each block its own bodies'
/// (the list is in body order: state/point_loads.hpp): a load on every wire
/// node and every 7th grain gives the same bits on 1 and 3 threads, set in
/// body order and in reverse, and moves the bodies.
TEST(Determinism, PointLoadsGiveTheSameBitsOnAnyThreadCount)
{
    std::vector<std::uint64_t> hashes;
    for (bool in_body_order : {true, false})
        for (unsigned threads : {1u, 3u}) {
            Simulation sim(threads);
            test::build_wired_column(sim.world, Integrator::gear5);
            World& w = sim.world;
            std::vector<PointLoads::Load> loads;
            for (std::uint32_t i = 0; i < w.of(BodyKind::grain).size(); i += 7)
                loads.emplace_back(BodyRef(BodyKind::grain, i), Vec3(1e-4, 0.0, -2e-4));
            for (std::uint32_t i = 0; i < w.of(BodyKind::wire).size(); ++i)
                loads.emplace_back(BodyRef(BodyKind::wire, i), Vec3(0.0, 3e-5, -1e-4));
            if (!in_body_order) std::reverse(loads.begin(), loads.end());
            for (const auto& [body, f] : loads) w.point_loads.set(body, f);
            ASSERT_EQ(w.point_loads.size(), loads.size());
            ASSERT_EQ(sim.run(300).end, RunEnd::completed);
            hashes.push_back(state_hash(w));
        }
    EXPECT_EQ(hashes, std::vector<std::uint64_t>(4, hashes[0]));
    Simulation unloaded(1);
    test::build_wired_column(unloaded.world, Integrator::gear5);
    ASSERT_EQ(unloaded.run(300).end, RunEnd::completed);
    EXPECT_NE(state_hash(unloaded.world), hashes[0]) << "the loads act";
}

namespace {
/// What the blocks of the list's rebuild and of the near pairs' selection
/// must add up to, worked out here one item at a time: the contacts in
/// contact_key order; the near pairs ascending, with their sides; each
/// body's near incidences those of the list on near pairs and walls, in its
/// order.
void expect_list_and_selection_whole(const World& w)
{
    const ContactList& c = w.contacts;
    for (std::size_t p = 1; p < c.size(); ++p)
        ASSERT_LT(contact_key(c.first[p - 1], c.second[p - 1]), contact_key(c.first[p], c.second[p])) << "contact " << p;
    const NearPairs& near = w.near;
    if (near.all) return;
    std::vector<std::uint8_t> is_near(c.size(), 1);
    std::fill(is_near.begin(), is_near.begin() + static_cast<std::ptrdiff_t>(c.pair_count()), 0);
    for (std::size_t k = 0; k < near.pairs.size(); ++k) {
        const std::uint32_t p = near.pairs[k];
        ASSERT_TRUE(k == 0 || near.pairs[k - 1] < p) << "near pair " << k;
        ASSERT_LT(p, c.pair_count());
        ASSERT_TRUE(near.first[k] == c.first[p] && near.second[k] == c.second[p]) << "near pair " << k;
        is_near[p] = 1;
    }
    const std::size_t n = w.body_count();
    ASSERT_EQ(near.incidence_start.size(), n + 1);
    std::vector<std::uint32_t> expected;
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(near.incidence_start[i], expected.size()) << "body " << i;
        for (std::uint32_t e = c.incidence_start[i]; e < c.incidence_start[i + 1]; ++e)
            if (is_near[c.incidence[e].contact()]) expected.push_back(c.incidence[e].bits);
    }
    ASSERT_EQ(near.incidence_start[n], expected.size());
    ASSERT_EQ(near.incidence.size(), expected.size());
    for (std::size_t e = 0; e < expected.size(); ++e) ASSERT_EQ(near.incidence[e].bits, expected[e]) << "incidence " << e;
}
} // namespace

/// The contact list's rebuild and the near pairs' selection
/// (update_neighbours) run over fixed blocks of pairs and of bodies on the
/// pool's threads, each block writing, from offsets summed in block order,
/// what one serial loop would. A cylinder of 2500 grains on a tight lattice,
/// kicked (several blocks of bodies and of pairs, floor and cylinder
/// contacts, rebuilds and selections while the grains fall), has the same
/// list, near pairs, incidences and selection positions, bit for bit, on 1
/// and 3 threads after every step, and they are whole (the list sorted, the
/// near pairs and incidences those of the list: above).
TEST(Determinism, NeighbourListAndNearPairsAreTheSameOnAnyThreadCount)
{
    const auto build = [](Simulation& sim) {
        World& w = sim.world;
        ContainerSpec spec;
        spec.container_radius_m = 12e-3;
        spec.grains = 2500;
        spec.lattice_gap = 0.05;
        spec.grain.youngs_modulus_pa = 1e8;
        spec.seed = 3;
        build_container(w, spec);
        w.contact.normal_damping_s = 1e-5;
        w.dt_s = stable_time_step(w).auto_s;
        SplitMix64 rng(5);
        for (std::uint32_t i = 0; i < w.bodies[0].size(); ++i) {
            const double vy = rng.uniform() - 0.5; // drawn y first: one scene for every compiler
            const double vx = rng.uniform() - 0.5;
            set_velocity(w, {BodyKind::grain, i}, 0.1 * Vec3(vx, vy, -1.0));
        }
    };
    Simulation one(1), three(3);
    build(one);
    build(three);
    const auto bits = [](const std::vector<Incidence>& v) {
        std::vector<std::uint32_t> out;
        for (const Incidence& e : v) out.push_back(e.bits);
        return out;
    };
    std::size_t most_pairs = 0, wall_contacts = 0;
    // 1.6 ms of the fall, for a rebuild besides the first (it comes at
    // 0.97 ms): the 300 steps of 5.24 µs (1.57 ms) this ran before the
    // springs' step became a packing's (springs_critical_step_s) are 499
    // of its 3.21 µs.
    const auto steps = static_cast<int>(std::ceil(1.6e-3 / one.world.dt_s));
    for (int s = 0; s < steps; ++s) {
        one.step();
        three.step();
        const World& a = one.world;
        const World& b = three.world;
        ASSERT_NO_FATAL_FAILURE(expect_list_and_selection_whole(b)) << "step " << s;
        ASSERT_EQ(a.neighbour_builds, b.neighbour_builds) << "step " << s;
        ASSERT_EQ(a.near.selections, b.near.selections) << "step " << s;
        ASSERT_TRUE(a.contacts.first == b.contacts.first && a.contacts.second == b.contacts.second) << "step " << s;
        ASSERT_EQ(a.contacts.hertz_coefficient, b.contacts.hertz_coefficient) << "step " << s;
        ASSERT_EQ(bits(a.contacts.incidence), bits(b.contacts.incidence)) << "step " << s;
        ASSERT_EQ(a.near.all, b.near.all) << "step " << s;
        ASSERT_EQ(a.near.pairs, b.near.pairs) << "step " << s;
        ASSERT_TRUE(a.near.first == b.near.first && a.near.second == b.near.second) << "step " << s;
        ASSERT_EQ(a.near.incidence_start, b.near.incidence_start) << "step " << s;
        ASSERT_EQ(bits(a.near.incidence), bits(b.near.incidence)) << "step " << s;
        ASSERT_TRUE(a.near.position_m == b.near.position_m) << "step " << s;
        ASSERT_EQ(a.near.drift_m, b.near.drift_m) << "step " << s;
        ASSERT_EQ(state_hash(a), state_hash(b)) << "step " << s;
        most_pairs = std::max(most_pairs, a.contacts.pair_count());
        wall_contacts = std::max(wall_contacts, a.contacts.size() - a.contacts.pair_count());
    }
    const World& w = one.world;
    EXPECT_GT(w.bodies[0].size(), 2 * reduction_block) << "several blocks of bodies";
    EXPECT_GT(most_pairs, 4 * reduction_block) << "several blocks of pairs";
    EXPECT_GT(wall_contacts, 100u);
    EXPECT_GE(w.neighbour_builds, 2u) << "a rebuild while the grains fall, besides the first";
    EXPECT_GE(w.near.selections, 5u);
    std::printf("[ info ] %zu list pairs at most, %zu wall contacts, %llu builds, %llu selections\n", most_pairs,
        wall_contacts, static_cast<unsigned long long>(w.neighbour_builds), static_cast<unsigned long long>(w.near.selections));
}

/// The SIMD contact kernels (contact/pair_kernel_simd.hpp; AVX-512 and
/// AVX2, whichever the CPU has) take the lanes they are sure of and give the
/// scalar law's bits: the kicked column (contacts forming, sliding,
/// breaking, grains against the cylinder and the floor) hashes the same with
/// them and without them, on 1 and 3 threads, and so does the wired column
/// (grain–wire and grain–membrane pairs in the list).
namespace {
/// Which body pairs of `c` the SIMD pair kernel evaluated itself (it
/// returns the others to its caller), run once over the whole list.
std::vector<bool> pairs_taken(const SimdContactKernels& simd, ContactList& c, const ContactInputs& in)
{
    const std::size_t end = c.pair_count() / simd.lanes * simd.lanes;
    std::vector<std::uint32_t> ids(end), left(end);
    std::iota(ids.begin(), ids.end(), 0u);
    const std::size_t n_left = simd.pairs(c, ids.data(), c.first.data(), c.second.data(), end, in, left.data());
    std::vector<bool> taken(end, true);
    for (std::size_t i = 0; i < n_left; ++i) taken[left[i]] = false;
    return taken;
}
} // namespace

TEST(Determinism, SimdAndScalarKernelsGiveTheSameBits)
{
    const std::vector<SimdKernels> choices = test::simd_choices();
    if (choices.empty()) GTEST_SKIP() << "neither AVX-512 nor AVX2 on this CPU: the scalar path is the only one";
    const test::RestoreSimdKernels restore;
    // The wired column for 0.82 ms, until grains press on the wire and the
    // membrane: 300 steps of its 2.73 µs before the springs' step became a
    // packing's (springs_critical_step_s), 492 of its 1.67 µs now.
    const auto wired_steps = [](const World& w) { return static_cast<std::uint64_t>(std::ceil(0.82e-3 / w.dt_s)); };
    auto wired = [&](SimdKernels kernel) {
        set_simd_kernels(kernel);
        Simulation sim(2);
        test::build_wired_column(sim.world, Integrator::gear5);
        EXPECT_EQ(sim.run(wired_steps(sim.world)).end, RunEnd::completed);
        return state_hash(sim.world);
    };
    const std::uint64_t wired_scalar = wired(SimdKernels::scalar);
    std::map<Integrator, std::vector<std::uint64_t>> scalar;
    for (Integrator integrator : {Integrator::gear5, Integrator::verlet}) {
        set_simd_kernels(SimdKernels::scalar);
        scalar[integrator] = run_column(1, integrator);
    }
    for (SimdKernels choice : choices) {
        set_simd_kernels(choice);
        const std::size_t lanes = simd_contact_kernels().lanes;
        SCOPED_TRACE(testing::Message() << lanes << " lanes");
        for (Integrator integrator : {Integrator::gear5, Integrator::verlet}) {
            set_simd_kernels(choice);
            EXPECT_EQ(run_column(1, integrator), scalar[integrator]);
            EXPECT_EQ(run_column(3, integrator), scalar[integrator]);
        }
        EXPECT_EQ(wired(choice), wired_scalar);

        // The SIMD path took touching lanes of every kind of pair in the wired
        // column (grain–grain, grain–wire, grain–membrane), not only apart ones.
        set_simd_kernels(choice);
        {
            Simulation wired_sim(1);
            test::build_wired_column(wired_sim.world, Integrator::gear5);
            ASSERT_EQ(wired_sim.run(wired_steps(wired_sim.world)).end, RunEnd::completed);
            World& w = wired_sim.world;
            const ContactInputs in = contact_inputs(w);
            const SimdContactKernels simd = simd_contact_kernels();
            std::map<std::pair<BodyKind, BodyKind>, std::size_t> taken_by_kinds;
            const std::vector<bool> taken = pairs_taken(simd, w.contacts, in);
            for (std::size_t p = 0; p < taken.size(); ++p)
                if (taken[p] && w.contacts.touching[p])
                    ++taken_by_kinds[{w.contacts.first[p].kind(), w.contacts.second[p].kind()}];
            EXPECT_GT((taken_by_kinds[{BodyKind::grain, BodyKind::grain}]), 0u);
            EXPECT_GT((taken_by_kinds[{BodyKind::grain, BodyKind::wire}]), 0u);
            EXPECT_GT((taken_by_kinds[{BodyKind::grain, BodyKind::membrane}]), 0u);
        }
        // And touching wall contacts in the kicked column.
        Simulation sim(1);
        build_column(sim, Integrator::gear5);
        ASSERT_EQ(sim.run(2000).end, RunEnd::completed);
        World& w = sim.world;
        const ContactInputs in = contact_inputs(w);
        const SimdContactKernels simd = simd_contact_kernels();
        std::size_t touching_taken = 0, wall_touching_taken = 0;
        const std::vector<bool> taken = pairs_taken(simd, w.contacts, in);
        for (std::size_t p = 0; p < taken.size(); ++p) touching_taken += taken[p] && w.contacts.touching[p];
        for (std::size_t wall = 0; wall < w.walls.size(); ++wall)
            for (std::size_t p = w.contacts.wall_start[wall]; p + lanes <= w.contacts.wall_start[wall + 1]; p += lanes) {
                const std::uint32_t taken = simd.wall(w.contacts, p, w.walls[wall], in);
                for (std::size_t l = 0; l < lanes; ++l)
                    wall_touching_taken += (taken >> l & 1u) && w.contacts.touching[p + l];
            }
        EXPECT_GT(touching_taken, 0u);
        EXPECT_GT(wall_touching_taken, 0u);
    }
}

// The kernels leave out the slip speed |v_t| (a square root and a division)
// for a block of contacts that all stick and hold, and work it out for a
// block with a sliding contact: both kinds of block, on every SIMD path,
// give the scalar law's bits.
TEST(Determinism, SimdKernelsGiveTheScalarBitsWhereContactsStickAndWhereTheySlide)
{
    const std::vector<SimdKernels> choices = test::simd_choices();
    if (choices.empty()) GTEST_SKIP() << "neither AVX-512 nor AVX2 on this CPU: the scalar path is the only one";
    const test::RestoreSimdKernels restore;
    for (Integrator integrator : {Integrator::gear5, Integrator::verlet}) {
        set_simd_kernels(SimdKernels::scalar);
        StickSlideStats stats;
        const std::uint64_t scalar = run_lattice(1, integrator, &stats);
        // Packed blocks are of 8 touching contacts at most: a run of 16 holds a whole one.
        EXPECT_GE(stats.longest_sticking_run, 16u);
        EXPECT_GT(stats.sliding, 0u);
        for (SimdKernels choice : choices) {
            set_simd_kernels(choice);
            SCOPED_TRACE(testing::Message() << simd_contact_kernels().lanes << " lanes");
            EXPECT_EQ(run_lattice(1, integrator), scalar);
            EXPECT_EQ(run_lattice(3, integrator), scalar);
        }
    }
}

// The engine's reference states, as golden values: the kicked column
// (8 × 250 steps, both integrators) and the wired column (wire, membrane,
// moving plate; 300 Gear-5 steps and 300 Verlet steps). A change to the
// engine that changes a bit of any of them fails here. When the change is
// meant (a new summation order, a law corrected), update the values below
// in the same commit and say in its message why the bits changed, as
// bench/README.md's history does ("The one hash change"); a change that
// was not meant is a bug to find, not a value to update.
// Changed 2026-12-07 (issue 42 item 4): the auto step counts the sticking
// tangential and rolling springs at ξ_ref's load (docs/model.md, "The
// tangential and rolling springs in the step"). Both columns' grain–wall
// springs were beyond it (ω_t δt = 0.36 at the old auto step, past the
// harmonic oscillator's 0.35), so their step fell: the kicked column's
// 6.274 → 5.237 µs, the wired column's to 2.726 µs (half its undamped
// step is 2.945 µs), and every bit with it. Were 24f452c5075b2bee,
// e994eaff8f5afe85, c0699b3e643a2019, f1f4ca8d0c8748ed.
// Changed again 2026-12-07 (issue 39's building-scale column, which blew
// up in its pour): the springs' step is a packing's, six contacts on one
// body at ω δt = 0.45 (springs_critical_step_s, 0.184/ω of one contact
// against 0.3/ω), so both columns' springs-bound steps fell by 0.612: the
// kicked column's 5.237 → 3.207 µs, the wired column's 2.726 → 1.669 µs.
// Were af1cad5b2deef8ce, 825b67a1dbb847b0, 2511795210b8cf36, 3357fa60bc7e2d20.
TEST(Determinism, ReferenceCasesKeepTheirGoldenHashes)
{
    const auto hex = [](std::uint64_t h) {
        std::ostringstream s;
        s << std::hex << std::setw(16) << std::setfill('0') << h;
        return s.str();
    };
    const auto wired = [](Integrator integrator) {
        Simulation sim(2);
        test::build_wired_column(sim.world, integrator);
        EXPECT_EQ(sim.run(300).end, RunEnd::completed);
        return state_hash(sim.world);
    };
    EXPECT_EQ(hex(run_column(2, Integrator::gear5).back()), "6672c3ae574d7d40");
    EXPECT_EQ(hex(run_column(2, Integrator::verlet).back()), "2b1511dcdbce6b94");
    EXPECT_EQ(hex(wired(Integrator::gear5)), "29085be615e60e0f");
    EXPECT_EQ(hex(wired(Integrator::verlet)), "15e881753931096d");
}

// The SIMD paths a run must test, named by WIREDEM_REQUIRE_SIMD ("avx2",
// "avx2,avx512"; scripts/test.sh reads them from /proc/cpuinfo): each must be
// among the paths the SIMD tests compare with the scalar one, so that a CPU
// the engine fails to recognise fails here instead of skipping those tests.
TEST(Simd, EveryPathTheCpuHasIsTested)
{
    const char* required = std::getenv("WIREDEM_REQUIRE_SIMD");
    if (required == nullptr) GTEST_SKIP() << "WIREDEM_REQUIRE_SIMD is not set (scripts/test.sh sets it)";
    std::vector<std::string> tested;
    const test::RestoreSimdKernels restore;
    for (SimdKernels k : test::simd_choices()) {
        set_simd_kernels(k);
        tested.push_back(simd_isa() == SimdIsa::avx512 ? "avx512" : "avx2");
    }
    std::istringstream names(required);
    for (std::string name; std::getline(names, name, ',');) {
        if (name.empty()) continue;
        ASSERT_TRUE(name == "avx2" || name == "avx512") << "WIREDEM_REQUIRE_SIMD names " << name;
        EXPECT_NE(std::find(tested.begin(), tested.end(), name), tested.end())
            << name << " is required but the SIMD tests would not run it";
    }
}
