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
#include "laws/hertz.hpp"
#include "specimen/preparation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace wiredem::engine;

namespace {

/// The small column of tests/engine/test_preparation.cpp (`small_column`):
/// R = 8 mm, masses × 100 and wire nodes × 400 more, e_n = 0.3 at 0.1 m/s.
PreparationSpec small_column(PatternKind kind, std::size_t grains)
{
    PreparationSpec s;
    s.membrane_radius_m = 8e-3;
    s.membrane_height_m = 0.04;
    s.grain_count = grains;
    s.pattern.kind = kind;
    s.pattern.helix_radius_m = 4e-3;
    s.pattern.inner_radius_m = 1.5e-3;
    s.density_scale = 100.0;
    s.wire_mass_scale = 400.0;
    s.fill_rate_m_per_s = 0.3;
    s.max_time_s = 1.5;
    const double grain_mass = s.density_scale * s.grain.density_kg_per_m3 * 4.0 / 3.0 * std::numbers::pi
                            * std::pow(s.grain_radius_m, 3);
    const double e_star = effective_modulus_pa(s.grain.youngs_modulus_pa, s.grain.poisson_ratio,
        s.grain.youngs_modulus_pa, s.grain.poisson_ratio);
    s.contact.normal_damping_s = hertz_damping_for_restitution_s(0.3, 0.5 * grain_mass, 0.1, e_star, 0.5 * s.grain_radius_m);
    return s;
}

} // namespace

TEST(Settling, APileOfThreeHundredGrainsSettlesAtTheAutoTimeStep)
{
    PreparationSpec spec = small_column(PatternKind::none, 300);
    // Poured in 0.08 s (fill ≈ 25 mm at 0.3 m/s); measured settled by 0.2 s
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
        const Vec3 v = g.x[1][i] / w.dt_s, omega = w.grain_rotation.w[1][i] / w.dt_s;
        kinetic_j += (0.5 * g.mass_kg[i] * v.squaredNorm()
                         + 0.5 * omega.squaredNorm() / w.grain_rotation.inv_inertia_per_kg_m2[i])
                   / spec.density_scale;
    }
    EXPECT_LT(kinetic_j / 300.0, spec.settle_kinetic_energy_per_grain_j);
    // At rest, contacts stick unless they carry a tangential load at the
    // Coulomb bound; a chattering pile had ~90 % of them sliding (measured
    // with the fix: 0–5 %).
    std::size_t touching = 0, sliding = 0;
    for (std::size_t p = 0; p < w.contacts.size(); ++p) {
        if (!w.contacts.touching[p]) continue;
        ++touching;
        sliding += !w.contacts.tangential[p].sticking;
    }
    ASSERT_GT(touching, 300u);
    EXPECT_LT(static_cast<double>(sliding), 0.2 * static_cast<double>(touching));
}
