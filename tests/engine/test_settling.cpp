// A pile of a few hundred grains settles at the auto time step (issue 5).
// Slow (≈ 3·10⁴ steps of 300 grains and a 1 300-node rigid membrane: several
// seconds in Release), so it is its own executable, labelled physics_long
// (tests/CMakeLists.txt), which the sanitizer runs can leave out.
//
// At this size, before the sliding-reversal test of the tangential law
// (engine/laws/tangential.hpp), the pile never settled at the auto δt: the
// kinetic energy per grain stayed at 1–9·10⁻⁷ J against the 10⁻⁷ J
// threshold with ~90 % of the resting contacts chattering in the sliding
// state, and one run blew up. The 100–120-grain preparation tests did not
// see it: under fewer grains' weight fewer contacts reach the normal force
// (≈ 0.2 N) from which one step of Coulomb friction overshoots the stick
// window.
#include "small_column.hpp"
#include "specimen/preparation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace wiredem::engine;
using wiredem::engine::test::small_column;

TEST(Settling, APileOfThreeHundredGrainsSettlesAtTheAutoTimeStep)
{
    PreparationSpec spec = small_column(PatternKind::none, 300);
    // Poured in ~0.07 s (fill ≈ 20 mm at 0.3 m/s); measured settled by 0.2 s
    // (both settling phases). Without the fix it ran to max_time_s unsettled:
    // stop it at 0.6 s rather than 1.5 s.
    spec.max_time_s = 0.6;
    ASSERT_EQ(spec.time_step_s, 0.0); // auto
    Simulation sim(1);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_TRUE(r.ok()) << r.error(); // no blow-up
    const PreparationReport& rep = r.value();
    // Both settling phases (before the lid and under it) reached the
    // threshold: kinetic energy per grain below 10⁻⁹ J × s.
    EXPECT_TRUE(rep.settled) << "t = " << rep.simulated_time_s << " s";
    EXPECT_EQ(rep.grains, 300u);

    const World& w = sim.world;
    const TranslationalState& g = w.of(BodyKind::grain);
    const double lid = w.walls[rep.top_plate_wall].point_m.z();
    double kinetic_j = 0.0;
    for (std::size_t i = 0; i < g.size(); ++i) {
        const Vec3& x = g.x[0][i];
        ASSERT_TRUE(x.allFinite() && g.x[1][i].allFinite()) << "grain " << i;
        EXPECT_LT(std::hypot(x.x(), x.y()) + g.radius_m[i], spec.membrane_radius_m) << "grain " << i << " escaped";
        EXPECT_GT(x.z(), 0.95 * g.radius_m[i]) << "grain " << i << " below the floor";
        EXPECT_LT(x.z(), lid) << "grain " << i << " above the lid";
        // Translation and rotation (w₁ = δt ω), with the unscaled masses.
        const Vec3 v = g.x[1][i] / w.dt_s, omega = w.grain_rotation.theta[1][i] / w.dt_s;
        kinetic_j += (0.5 * g.mass_kg[i] * v.squaredNorm()
                         + 0.5 * omega.squaredNorm() / w.grain_rotation.inv_inertia_per_kg_m2[i])
                   / spec.density_scale;
    }
    EXPECT_LT(kinetic_j / 300.0, spec.settle_kinetic_energy_per_grain_j);
    // At rest, contacts stick unless they carry a tangential load at the
    // Coulomb bound; a chattering pile had ~90 % of them sliding (measured
    // with the fix: 0–5 %).
    std::size_t touching = 0, sliding = 0;
    for (std::size_t p = 0; p < w.contacts.pair_count(); ++p) {
        if (!w.contacts.touching[p]) continue;
        ++touching;
        sliding += !w.contacts.tangential[p].sticking;
    }
    ASSERT_GT(touching, 300u);
    EXPECT_LT(static_cast<double>(sliding), 0.2 * static_cast<double>(touching));
}
