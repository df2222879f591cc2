// Bit-identical results whatever the number of threads.
#include "helpers.hpp"
#include "scene.hpp"
#include "state/state_hash.hpp"
#include "timestep.hpp"
#include "wired_column.hpp"

#include <gtest/gtest.h>

using namespace wiredem::engine;

namespace {

/// A small column of grains falling into a cylinder, hashed every 250 steps.
std::vector<std::uint64_t> run_column(unsigned threads, Integrator integrator = Integrator::gear5)
{
    Simulation sim(threads);
    sim.world.integrator = integrator;
    ContainerSpec spec;
    spec.container_radius_m = 6e-3;
    spec.grains = 400;
    spec.grain.youngs_modulus_pa = 1e8; // soft grains: large δt, same code paths
    spec.seed = 7;
    build_container(sim.world, spec);
    sim.world.contact.normal_damping_s = 1e-5;
    sim.world.dt_s = stable_time_step(sim.world).auto_s;
    // Kick the grains so that contacts form, slide and break early.
    SplitMix64 rng(3);
    for (std::uint32_t i = 0; i < sim.world.bodies[0].size(); ++i)
        set_velocity(sim.world, {BodyKind::grain, i}, Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, -1.0));
    std::vector<std::uint64_t> hashes;
    for (int block = 0; block < 8; ++block) {
        sim.run(250);
        hashes.push_back(state_hash(sim.world));
    }
    EXPECT_GT(sim.world.contacts.size(), 0u);
    return hashes;
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
