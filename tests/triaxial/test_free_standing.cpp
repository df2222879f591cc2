// The free-standing test (engine/triaxial/free_standing.hpp) against physics:
// the formwork goes without a kick (a kinetic-energy bound from the removal
// speed), the bottom plate carries the column's weight at rest, the top
// plate's force is the force the contacts carry through the column, a fast
// plate is flagged as not quasi-static; the readings' pure functions on
// configurations with a known answer. Tiny columns (column_specimens.hpp).
#include "energy.hpp"
#include "state/state_hash.hpp"
#include "triaxial/formwork.hpp"
#include "triaxial/free_standing.hpp"

#include "column_collapse.hpp"
#include "column_specimens.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

/// Settings of the tests: short phases, a fast but quasi-static plate.
FreeStandingSettings quick_settings()
{
    FreeStandingSettings s;
    s.removal_time_s = 5e-3;
    s.removal_distance_m = 1e-3;
    s.escape_distance_m = 0.02;
    s.settle_kinetic_energy_per_grain_j = 1e-9;
    s.max_settling_time_s = 0.1;
    s.plate_speed_m_per_s = 0.01;
    s.target_axial_strain = 0.01;
    s.sample_interval_s = 0.2e-3;
    return s;
}

/// Total mass of the grains [kg].
double grain_mass_kg(const World& w)
{
    double m = 0.0;
    for (double mi : w.of(BodyKind::grain).mass_kg) m += mi;
    return m;
}

/// The lattice specimen without gravity, its membrane pushed `squeeze_m`
/// inwards (kinematically, slowly) and the column brought to rest inside it:
/// a column whose formwork holds elastic energy.
std::size_t squeezed_lattice(Simulation& sim, double squeeze_m)
{
    const std::size_t lid = build_lattice_specimen(sim, 3);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    const double squeeze_time_s = 5e-3;
    open_formwork(w, -squeeze_m / squeeze_time_s);
    for (double t = 0.0; t < squeeze_time_s; t += w.dt_s) sim.step();
    for (std::uint32_t i = 0; i < w.of(BodyKind::membrane).size(); ++i) set_motion(w, {BodyKind::membrane, i}, Motion::fixed);
    for (double t = 0.0; t < 10e-3; t += w.dt_s) sim.step();
    bring_to_rest(sim);
    return lid;
}

/// The largest kinetic energy of the rows of the removal and the settling
/// (gravity off: no motion but what the removal released) [J].
double largest_kinetic_energy_before_loading_j(const FreeStandingResult& r)
{
    double e = 0.0;
    for (std::size_t i = 0; i < r.series.size(); ++i)
        if (r.series.phase[i] <= static_cast<std::uint8_t>(FreeStandingPhase::settling))
            e = std::max(e, r.series.kinetic_energy_j[i]);
    return e;
}

} // namespace

// A membrane that squeezes the column stores elastic energy E in the
// contacts. Taken away in one step, it releases much of E as motion; opened
// at a speed v, every body follows a boundary that recedes at v: a body on a
// spring whose end starts moving at v has the speed v(1 − cos ωt) ≤ 2v (and a
// rod's free end the incident wave's v doubled), so the kinetic energy stays
// below ½ M (2v)² = 2 M v² (M the grains' mass) whatever E is.
TEST(FreeStanding, FormworkRemovalGivesNoKick)
{
    const double squeeze_m = 0.1 * grain_radius_m;
    FreeStandingSettings s = quick_settings();
    s.removal_distance_m = 2.0 * squeeze_m; // the squeezed column relaxes within the squeeze
    s.removal_time_s = 0.1;
    const double v = s.removal_distance_m / s.removal_time_s;

    Simulation slow_sim(1);
    const std::size_t lid = squeezed_lattice(slow_sim, squeeze_m);
    const double stored_j = elastic_energy(slow_sim.world, slow_sim.pool()).total_j();
    const double bound_j = 2.0 * grain_mass_kg(slow_sim.world) * v * v;
    ASSERT_GT(stored_j, 50.0 * bound_j) << "the squeeze must store far more than the bound for the test to mean anything";
    const auto slow = run_free_standing(slow_sim, lid, s);
    ASSERT_TRUE(slow.ok()) << slow.error();
    EXPECT_LE(slow.value().settling.max_removal_kinetic_energy_j, bound_j);
    EXPECT_LE(largest_kinetic_energy_before_loading_j(slow.value()), bound_j);

    // The same formwork gone in one step: a kick of a good part of E.
    Simulation fast_sim(1);
    const std::size_t fast_lid = squeezed_lattice(fast_sim, squeeze_m);
    s.removal_time_s = fast_sim.world.dt_s;
    const auto fast = run_free_standing(fast_sim, fast_lid, s);
    ASSERT_TRUE(fast.ok()) << fast.error();
    EXPECT_GT(largest_kinetic_energy_before_loading_j(fast.value()), 10.0 * bound_j);
}

// At rest on the bottom plate, the column's weight goes into the plate: over
// the last millisecond of settling, mean F − W = ΔP/τ, and |P| ≤ √(2 M K)
// bounds it (base_force_tolerance_n). The driver's two numbers come from
// different places, the plate's contact forces and the bodies' masses. A
// stack of grains, which stands; at rest by a criterion strict enough for the
// bound to be 1 % of the weight: (√(2 M K₀) + √(2 M K₁))/τ ≈ 2 N √(2 m e)/τ
// for N grains of mass m at e per grain, against W = N m g, so e below
// (g τ / 2)² m / 2 · 10⁻⁴ (≈ 7.5·10⁻¹⁵ J for these grains); K₀, a check
// before the column came to rest, is above the criterion, so 10⁻¹⁶ J.
TEST(FreeStanding, TheBottomPlateCarriesTheColumnsWeightAtRest)
{
    Simulation sim(1);
    const std::size_t lid = build_grain_stack(sim, 0.0);
    FreeStandingSettings s = quick_settings();
    s.settle_kinetic_energy_per_grain_j = 1e-16;
    s.max_settling_time_s = 0.3;
    const auto r = run_free_standing(sim, lid, s);
    ASSERT_TRUE(r.ok()) << r.error();
    const SettlingReading& st = r.value().settling;
    ASSERT_TRUE(st.at_rest);
    EXPECT_TRUE(st.stands);
    const double weight_n = -grain_mass_kg(sim.world) * sim.world.gravity_m_per_s2.z();
    EXPECT_NEAR(st.weight_n, weight_n, 1e-12 * weight_n);
    EXPECT_LT(st.base_force_tolerance_n, 0.01 * weight_n) << "the bound must be tight enough to mean something";
    EXPECT_NEAR(st.base_force_n, weight_n, st.base_force_tolerance_n);
    EXPECT_EQ(st.escaped_grains, 0u);
    ASSERT_EQ(st.profile.grains.size(), static_cast<std::size_t>(stack_grains)); // one grain per slice of a diameter
    for (std::size_t k = 0; k < st.profile.radius_m.size(); ++k) EXPECT_NEAR(st.profile.radius_m[k], grain_radius_m, 1e-6);
}

// A grain that left the column is lost (escaped_grains), not part of the
// column that comes to rest: the same stack with a grain rolling away on the
// plate beyond the escape distance (rolling without slipping, ω = v/r: a
// sphere without rolling resistance loses nothing and rolls on for ever)
// comes to rest by the criterion of 10⁻¹⁶ J per grain of the column, while
// the rolling grain alone holds ½ m v² + ½ I ω² = 0.7 m v² (≈ 10⁻⁷ J) to the
// end. Counted over every grain, as before 2026-12-07, it never would.
TEST(FreeStanding, AGrainRollingAwayDoesNotKeepTheColumnFromRest)
{
    Simulation sim(1);
    const std::size_t lid = build_grain_stack(sim, 0.0);
    World& w = sim.world;
    FreeStandingSettings s = quick_settings();
    s.settle_kinetic_energy_per_grain_j = 1e-16;
    s.max_settling_time_s = 0.3;
    const double r = grain_radius_m, v0 = 0.05;
    const std::uint32_t rolling = add_grain(w, Vec3(s.escape_distance_m + 5e-3, 0, r), r, w.of(BodyKind::grain).material[0]);
    set_velocity(w, {BodyKind::grain, rolling}, Vec3(v0, 0, 0));
    w.grain_rotation.theta[1][rolling] = Vec3(0, v0 / r, 0) * w.dt_s; // about +y: rolling along +x, away from the axis
    const auto res = run_free_standing(sim, lid, s);
    ASSERT_TRUE(res.ok()) << res.error();
    const SettlingReading& st = res.value().settling;
    EXPECT_TRUE(st.at_rest);
    EXPECT_LT(st.time_to_rest_s, s.max_settling_time_s);
    EXPECT_EQ(st.escaped_grains, 1u);
    const double m = w.of(BodyKind::grain).mass_kg[rolling];
    EXPECT_GT(velocity_m_per_s(w, {BodyKind::grain, rolling}).x(), 0.9 * v0) << "it still rolls: the column's rest is its own";
    EXPECT_GT(0.7 * m * v0 * v0, 1e6 * s.settle_kinetic_energy_per_grain_j * (stack_grains + 1));
}

// The top plate is a plane over the whole bottom plate. Set on the standing
// column, it must not cut into a body that left the column and lies higher
// (the study's column without wire left a ridge of its runout 12 mm above
// its 8 mm heap, 131 mm from the axis, and the plate set on the heap
// overlapped it by 9.6 mm: the live check stopped the test). The stack, its
// plate 2 mm above it, and beside it beyond the escape distance a stack of
// larger grains 1.5 mm taller: the plate is set on the taller stack, the
// strain measured from there, and a warning says what it presses.
TEST(FreeStanding, TheTopPlateIsSetOnABodyThatLeftTheColumnAndLiesHigher)
{
    Simulation sim(1);
    const std::size_t lid = build_grain_stack(sim, -2e-3);
    World& w = sim.world;
    FreeStandingSettings s = quick_settings();
    const double r = grain_radius_m + 0.15e-3, rho = s.escape_distance_m + 5e-3;
    for (int k = 0; k < stack_grains; ++k) add_grain(w, Vec3(rho, 0, r + 2.0 * r * k), r, w.of(BodyKind::grain).material[0]);
    set_auto_time_step(w);
    const double column_top = 2.0 * grain_radius_m * stack_grains, beside_top = 2.0 * r * stack_grains;
    ASSERT_LT(beside_top, w.walls[lid].point_m.z()) << "the plate starts above both stacks";
    const auto res = run_free_standing(sim, lid, s);
    ASSERT_TRUE(res.ok()) << res.error();
    const FreeStandingResult& out = res.value();
    EXPECT_EQ(out.settling.escaped_grains, static_cast<std::size_t>(stack_grains));
    EXPECT_NEAR(out.settling.height_m, column_top, 0.02 * grain_radius_m) << "the standing column's top";
    ASSERT_TRUE(std::any_of(out.warnings.begin(), out.warnings.end(),
        [](const std::string& m) { return m.find("the top plate was set at") != std::string::npos; }));
    // The compression's first row: the plate on the taller stack (ε = 0 there), the strain from its top.
    const TriaxialSeries& ts = out.series;
    const std::size_t first = out.loading_start_sample;
    ASSERT_LT(first, ts.size());
    EXPECT_NEAR(ts.axial_strain[first], 0.0, 1e-12);
    EXPECT_GT(ts.axial_strain.back(), 0.0);
    // (The stack's settled top: its contacts' overlaps under its weight, microns.)
    EXPECT_NEAR(w.walls[lid].point_m.z(), beside_top * (1.0 - ts.axial_strain.back()), 0.01 * grain_radius_m)
        << "the strain is the plate's travel from the taller stack's top";
}

// The force the top plate measures is the force the contacts carry through
// any horizontal plane of the column below it plus the weight between: for
// the grains above the plane, F_plane − F_top − W_above = dP_above/dt. A
// stack of grains on the axis compressed without confinement, the plane
// between its second and third grain; averaged over a window τ the identity
// holds with ΔP_above/τ from the grains' own momenta.
TEST(FreeStanding, ThePlatesForceIsTheForceThroughTheColumn)
{
    Simulation sim(1);
    const std::size_t lid = build_grain_stack(sim, 0.0);
    World& w = sim.world;
    FreeStandingSettings s = quick_settings();
    s.target_axial_strain = 0.01;
    s.plate_speed_m_per_s = 0.002;
    const double plane_z = 4.0 * grain_radius_m; // between grains 2 and 3 (centres at 3r and 5r)
    const TranslationalState& g = w.of(BodyKind::grain);
    auto momentum_above = [&] {
        double p = 0.0;
        for (std::size_t i = 0; i < g.size(); ++i)
            if (g.x[0][i].z() > plane_z) p += g.mass_kg[i] * g.x[1][i].z() / w.dt_s;
        return p;
    };
    auto weight_above = [&] {
        double m = 0.0;
        for (std::size_t i = 0; i < g.size(); ++i)
            if (g.x[0][i].z() > plane_z) m += g.mass_kg[i];
        return -m * w.gravity_m_per_s2.z();
    };
    double sum_n = 0.0, top_sum_n = 0.0, p0 = 0.0;
    std::uint64_t n = 0;
    RunControl rc;
    rc.after_step = [&](const World&, const StepReport&) {
        if (n == 0) p0 = momentum_above();
        else {
            sum_n += axial_force_through_plane_n(w, plane_z) - plate_compression_n(w, lid) - weight_above();
            top_sum_n += plate_compression_n(w, lid);
        }
        ++n;
        return true;
    };
    const auto r = run_free_standing(sim, lid, s, rc);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_GT(n, 100u);
    const double steps = static_cast<double>(n - 1);
    const double mean_top_n = top_sum_n / steps;
    ASSERT_GT(mean_top_n, 10.0 * weight_above()) << "the plate must load the stack";
    // dP/dt from the first to the last step of the window, over its steps.
    const double dp_dt_n = (momentum_above() - p0) / (steps * w.dt_s);
    EXPECT_NEAR(sum_n / steps, dp_dt_n, 1e-6 * mean_top_n);
}

// A plate fast enough to throw the grains is flagged; a slow one is not.
// The stack's σ₁ rows carry I = ε̇ d √(ρ/σ₁) from the bearing rows on.
TEST(FreeStanding, AFastPlateIsFlaggedAsNotQuasiStatic)
{
    for (const double speed : {0.0005, 1.0}) {
        Simulation sim(1);
        const std::size_t lid = build_grain_stack(sim, 0.0);
        FreeStandingSettings s = quick_settings();
        s.plate_speed_m_per_s = speed;
        s.target_axial_strain = 0.01;
        s.sample_interval_s = std::min(0.2e-3, 0.1 * s.target_axial_strain * 10 * grain_radius_m / speed);
        const auto r = run_free_standing(sim, lid, s);
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_EQ(r.value().verdict.quasi_static, speed < 0.1) << "plate at " << speed << " m/s: " << r.value().verdict.warning;
    }
}

// A test stopped between two steps in any phase and continued from the World
// and the driver's state saved there ends as the one never stopped, bit for
// bit (what a campaign's resume rests on).
TEST(FreeStanding, ATestContinuedFromAnyPhaseEndsBitIdentically)
{
    Simulation whole(2);
    const std::size_t top = build_grain_stack(whole, 0.0);
    FreeStandingSettings s = quick_settings();
    s.dead_load = DeadLoad{0.05, 2e-3, 3e-3};
    std::vector<std::pair<World, FreeStandingDriverState>> saved;
    FreeStandingContinuation c;
    c.between_steps = [&](const World& w, const FreeStandingDriverState& st) {
        if (saved.size() <= static_cast<std::size_t>(st.phase) && st.steps > st.phase_start_step + 5)
            saved.emplace_back(w, st);
    };
    const auto full = run_free_standing(whole, top, s, {}, c);
    ASSERT_TRUE(full.ok()) << full.error();
    ASSERT_EQ(saved.size(), 4u); // removal, settling, dead load, loading
    ASSERT_TRUE(full.value().dead_load.has_value());
    EXPECT_TRUE(full.value().dead_load->holds); // 0.05 N on a stack of elastic grains
    const std::uint64_t end_hash = state_hash(whole.world);
    for (std::size_t k = 0; k < saved.size(); ++k) {
        SCOPED_TRACE(std::string("continued in ") + to_string(saved[k].second.phase));
        Simulation rest(1 + k % 2);
        rest.world = saved[k].first;
        FreeStandingContinuation from;
        from.from = saved[k].second;
        const auto r = run_free_standing(rest, top, s, {}, from);
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_EQ(state_hash(rest.world), end_hash);
        const FreeStandingResult &a = r.value(), &b = full.value();
        EXPECT_EQ(a.steps, b.steps);
        EXPECT_EQ(a.settling.time_to_rest_s, b.settling.time_to_rest_s);
        EXPECT_EQ(a.settling.base_force_n, b.settling.base_force_n);
        EXPECT_EQ(a.dead_load->strain_at_load, b.dead_load->strain_at_load);
        EXPECT_EQ(a.dead_load->creep_strain, b.dead_load->creep_strain);
        ASSERT_EQ(a.series.size(), b.series.size());
        for (std::size_t i = 0; i < a.series.size(); ++i) {
            EXPECT_EQ(a.series.sigma1_pa[i], b.series.sigma1_pa[i]) << "row " << i;
            EXPECT_EQ(a.series.kinetic_energy_j[i], b.series.kinetic_energy_j[i]) << "row " << i;
        }
        ASSERT_TRUE(a.compression && b.compression);
        EXPECT_EQ(a.compression->strength.value, b.compression->strength.value);
    }
}

TEST(FreeStanding, RejectsSettingsOutOfRangeNamingTheField)
{
    Simulation sim(1);
    const std::size_t lid = build_grain_stack(sim, 0.0);
    FreeStandingSettings s = quick_settings();
    s.removal_time_s = 0.0;
    auto r = run_free_standing(sim, lid, s);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("removal_time_s"), std::string::npos) << r.error();
    s = quick_settings();
    s.dead_load = DeadLoad{-1.0, 0.01, 0.01};
    r = run_free_standing(sim, lid, s);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("dead_load.force_n"), std::string::npos) << r.error();
}

// The compression's first row is taken with the plate set on the column (at
// h₀: ε = 0) and with that plate's forces, not the settling's last row, taken
// while the plate was still where the removal had lifted it (ε < 0 by the
// removal distance over h₀, and the forces of grains that touched it there).
// The stack stands; the plate is set on its top grain without overlap, and
// in one step the grain's leftover motion presses it by a trace: σ₁ is
// below 5 % of the stack's weight over the cross-section (it touches; it
// does not load).
TEST(FreeStanding, TheCompressionsFirstRowHasThePlateOnTheColumn)
{
    Simulation sim(1);
    const std::size_t lid = build_grain_stack(sim, 0.0);
    const auto r = run_free_standing(sim, lid, quick_settings());
    ASSERT_TRUE(r.ok()) << r.error();
    const FreeStandingResult& f = r.value();
    const std::size_t first = f.loading_start_sample;
    ASSERT_GT(first, 0u);
    EXPECT_EQ(f.series.phase[first], static_cast<std::uint8_t>(FreeStandingPhase::loading));
    EXPECT_EQ(f.series.phase[first - 1], static_cast<std::uint8_t>(FreeStandingPhase::settling));
    EXPECT_EQ(f.series.axial_strain[first], 0.0);
    const double weight_stress_pa = f.settling.weight_n / (std::numbers::pi * f.settling.radius_m * f.settling.radius_m);
    EXPECT_LT(std::abs(f.series.sigma1_pa[first]), 0.05 * weight_stress_pa);
    EXPECT_GT(f.series.time_s[first], f.series.time_s[first - 1]);
}

// Without a dead load, the compression begins with one step of the plate at
// rest on the column. A host checkpoints before a step: a test continued
// from the checkpoint before that step (the plate set, the compression not
// begun) and from the one after it (its first row taken) ends bit-identically.
TEST(FreeStanding, ATestContinuedAroundThePlatesFirstStepEndsBitIdentically)
{
    Simulation whole(1);
    const std::size_t top = build_grain_stack(whole, 0.0);
    const FreeStandingSettings s = quick_settings();
    std::vector<std::pair<World, FreeStandingDriverState>> saved;
    FreeStandingContinuation c;
    c.between_steps = [&](const World& w, const FreeStandingDriverState& st) {
        if (st.phase == FreeStandingPhase::loading && st.steps <= st.phase_start_step + 1) saved.emplace_back(w, st);
    };
    const auto full = run_free_standing(whole, top, s, {}, c);
    ASSERT_TRUE(full.ok()) << full.error();
    ASSERT_EQ(saved.size(), 2u);
    EXPECT_FALSE(saved[0].second.loading_begun);
    EXPECT_TRUE(saved[1].second.loading_begun);
    for (std::size_t k = 0; k < saved.size(); ++k) {
        SCOPED_TRACE("continued from checkpoint " + std::to_string(k));
        Simulation rest(2);
        rest.world = saved[k].first;
        FreeStandingContinuation from;
        from.from = saved[k].second;
        const auto r = run_free_standing(rest, top, s, {}, from);
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_EQ(state_hash(rest.world), state_hash(whole.world));
        const FreeStandingResult &a = r.value(), &b = full.value();
        EXPECT_EQ(a.steps, b.steps);
        EXPECT_EQ(a.loading_start_sample, b.loading_start_sample);
        ASSERT_EQ(a.series.size(), b.series.size());
        for (std::size_t i = 0; i < a.series.size(); ++i) {
            EXPECT_EQ(a.series.axial_strain[i], b.series.axial_strain[i]) << "row " << i;
            EXPECT_EQ(a.series.sigma1_pa[i], b.series.sigma1_pa[i]) << "row " << i;
        }
    }
}

// How the compression failed, read from constructed signs: the wire breaking
// at the peak decides first, then the grains lost beyond max_lost_fraction,
// then the widest slice's gain beyond max_radius_gain × r₀; each bound is
// strict (at the bound the next rule reads), and with none of them the
// record does not resolve the mode.
TEST(FailureMode, TheWireAtThePeakThenTheGrainsLostThenTheBulgeDecide)
{
    const double max_lost = 0.1, max_gain = 0.25, r0 = 0.02; // bulge bound 0.25 × 0.02 = 0.005 m exactly
    const auto mode = [&](bool wire, double spilled, double bulge) {
        return failure_mode(FailureSigns{wire, spilled, bulge, r0}, max_lost, max_gain);
    };
    EXPECT_EQ(mode(true, 0.5, 0.01), FailureMode::wire_break);
    EXPECT_EQ(mode(true, 0.0, 0.0), FailureMode::wire_break);
    EXPECT_EQ(mode(false, 0.11, 0.01), FailureMode::grains_spilling);
    EXPECT_EQ(mode(false, 0.1, 0.0051), FailureMode::bulging) << "at max_lost_fraction the grains lost do not decide";
    EXPECT_EQ(mode(false, 0.1, 0.005), FailureMode::unresolved) << "at the bulge bound it does not decide";
    EXPECT_EQ(mode(false, 0.0, 0.0050001), FailureMode::bulging);
    EXPECT_EQ(mode(false, -0.02, -0.001), FailureMode::unresolved) << "grains come back, the column narrows";
    EXPECT_EQ(failure_mode(FailureSigns{false, 0.05, 0.003, 0.01}, 0.04, 0.25), FailureMode::grains_spilling)
        << "the settings' bounds, not defaults";
    EXPECT_EQ(failure_mode(FailureSigns{false, 0.05, 0.003, 0.01}, 0.1, 0.5), FailureMode::unresolved);
    EXPECT_STREQ(to_string(FailureMode::wire_break), "wire_break");
    EXPECT_STREQ(to_string(FailureMode::grains_spilling), "grains_spilling");
    EXPECT_STREQ(to_string(FailureMode::bulging), "bulging");
    EXPECT_STREQ(to_string(FailureMode::unresolved), "unresolved");
}

// The bulge is the widest slice's gain, wherever along the height the widest
// slices are: a column that narrowed reads a negative gain, an empty profile 0.
TEST(ColumnBulge, IsTheWidestSlicesGainWhereverItIs)
{
    const RadiusProfile settled{{0.001, 0.003, 0.005}, {0.010, 0.0105, 0.010}, {5, 5, 5}};
    const RadiusProfile barrel{{0.001, 0.003, 0.005}, {0.0101, 0.0125, 0.0102}, {5, 5, 5}};
    const RadiusProfile foot{{0.001, 0.003}, {0.0131, 0.010}, {9, 5}};
    const RadiusProfile narrowed{{0.001, 0.003, 0.005}, {0.009, 0.0095, 0.009}, {5, 5, 5}};
    EXPECT_DOUBLE_EQ(column_bulge_m(settled, barrel), 0.0125 - 0.0105);
    EXPECT_DOUBLE_EQ(column_bulge_m(settled, foot), 0.0131 - 0.0105);
    EXPECT_DOUBLE_EQ(column_bulge_m(settled, narrowed), 0.0095 - 0.0105);
    EXPECT_EQ(column_bulge_m(settled, RadiusProfile{}), 0.0);
    EXPECT_EQ(column_bulge_m(RadiusProfile{}, barrel), 0.0);
}

// A compression's reading carries the mode the rule gives on what it read:
// the grains lost from the settled column to the end, the widest slice's gain
// from the settled profile to the one at the end, r₀ and the settings' bounds.
// The stack of grains loses none in a 1 % compression.
TEST(FreeStanding, TheCompressionReportsTheFailureModeOfWhatItRead)
{
    Simulation sim(1);
    const std::size_t lid = build_grain_stack(sim, 0.0);
    const FreeStandingSettings s = quick_settings();
    const auto r = run_free_standing(sim, lid, s);
    ASSERT_TRUE(r.ok()) << r.error();
    const FreeStandingResult& f = r.value();
    ASSERT_TRUE(f.compression && f.compression->failure_mode);
    const CompressionReading& c = *f.compression;
    const StandingColumn end = standing_column(sim.world, s.escape_distance_m, s.bulk_fraction);
    EXPECT_EQ(c.spilled_fraction, end.lost_fraction - f.settling.lost_fraction);
    EXPECT_EQ(c.spilled_fraction, 0.0);
    EXPECT_EQ(c.bulge_m, column_bulge_m(f.settling.profile, c.profile_at_end));
    EXPECT_EQ(*c.failure_mode, failure_mode(FailureSigns{false, c.spilled_fraction, c.bulge_m, f.settling.radius_m},
                                   s.max_lost_fraction, s.max_height_loss));
}

// A radius profile of a filled cylinder of radius R: its grain centres fill
// a disc of radius R − r uniformly, so ⟨ρ²⟩ = (R − r)²/2 and the equivalent
// radius √(2⟨ρ²⟩) + r is R (to the sampling of the disc).
TEST(RadiusProfile, AFilledCylinderHasItsRadiusInEverySlice)
{
    const double r = 1e-3, R = 10e-3;
    std::vector<Vec3> x;
    std::vector<double> radius;
    // Centres on a fine polar grid with equal area per point.
    for (int layer = 0; layer < 4; ++layer)
        for (int k = 0; k < 400; ++k) {
            const double rho = (R - r) * std::sqrt((k + 0.5) / 400.0);
            const double phi = 2.399963 * k; // golden angle
            x.emplace_back(rho * std::cos(phi), rho * std::sin(phi), r + 2.0 * r * layer);
            radius.push_back(r);
        }
    const RadiusProfile p = radius_profile(x, radius, 0.0, 1.0);
    ASSERT_EQ(p.radius_m.size(), 4u);
    for (std::size_t k = 0; k < 4; ++k) {
        EXPECT_NEAR(p.radius_m[k], R, 1e-3 * R);
        EXPECT_NEAR(p.height_m[k], r + 2.0 * r * static_cast<double>(k), 1e-12);
        EXPECT_EQ(p.grains[k], 400u);
    }
    // A grain beyond the escape distance is not in the profile.
    x.emplace_back(0.5, 0.0, r);
    radius.push_back(r);
    EXPECT_EQ(radius_profile(x, radius, 0.0, 0.1).grains[0], 400u);
}

// A deposit of known shape: N grains on rings of radii 1…N mm (one per ring)
// and a tall grain on the axis. The edge that holds f N grains is the
// ⌈f N⌉-th ring's plus r; the height is the highest grain within it.
TEST(Deposit, TheRunoutHoldsItsFractionOfTheGrainsAndTheHeightIsWithinIt)
{
    const double r = 0.5e-3;
    std::vector<Vec3> x;
    std::vector<double> radius;
    for (int k = 1; k <= 20; ++k) {
        x.emplace_back(1e-3 * k * std::cos(k), 1e-3 * k * std::sin(k), 0.2 + r);  // bottom plate at z = 0.2
        radius.push_back(r);
    }
    x.emplace_back(0.0, 0.0, 0.2 + 7e-3);
    radius.push_back(r);
    x.emplace_back(30e-3, 0.0, 0.2 + 9e-3);  // a grain that flew off, high up
    radius.push_back(r);
    const Deposit d = deposit(x, radius, 0.2, 0.9);  // ⌈0.9 · 22⌉ = 20: the 19th ring's edge
    EXPECT_NEAR(d.runout_radius_m, 19e-3 + r, 1e-12);
    EXPECT_NEAR(d.max_radius_m, 30e-3 + r, 1e-12);
    EXPECT_NEAR(d.height_m, 7e-3 + r, 1e-12) << "the flown-off grain is beyond r∞";
    EXPECT_NEAR(deposit(x, radius, 0.2, 1.0).height_m, 9e-3 + r, 1e-12);
    EXPECT_EQ(deposit({}, {}, 0.0, 0.9).runout_radius_m, 0.0);
}

// The collapse of a column without wire (docs/validation.md, "Collapse of a
// column without wire"): the tests' lattice column, 9 layers in an 8 mm
// formwork (Hᵢ = 19 mm, Rᵢ = 7.6 mm: a = 2.5, three grain diameters in
// radius), released at 5 √(g Hᵢ), faster than it falls, as the experiments
// lift their tube. The published laws (Lube et al. 2004, lube_runout and
// lube_final_height: at a = 2.5, (r∞ − Rᵢ)/Rᵢ = 2.53 and H∞/Rᵢ = 1.03) are
// for sand, whose grains slide but do not roll. What a deposit of so few
// grains can be held to: r∞ and H∞ are edges and tops of grains, so each is
// known to a grain diameter d, d/Rᵢ = 0.32 of the scaled figures.
namespace {

/// d/Rᵢ of a collapse: the resolution of its scaled runout and height.
double resolution(const CollapseOutcome& o) { return 2.0 * grain_radius_m / o.initial_radius_m; }

} // namespace

// The model's spheres (no rolling resistance) roll on the flat plate: the
// column does not stand, it spreads into a layer one grain high (H∞ = the
// largest grain diameter, 2r) and runs out far beyond the sand's runout, more
// than a grain beyond it, and is still moving when the settling ends.
TEST(ColumnCollapse, WithoutRollingResistanceTheSpheresSpreadIntoOneLayerFarBeyondSandsRunout)
{
    const auto r = run_collapse(CollapseCase{});
    ASSERT_TRUE(r.ok()) << r.error();
    const CollapseOutcome& o = r.value();
    const double a = o.aspect_ratio();
    ASSERT_NEAR(a, 2.5, 0.1);
    EXPECT_FALSE(o.settling.stands);
    EXPECT_LE(o.deposit.height_m, 2.0 * grain_radius_m) << "one layer of grains";
    EXPECT_GT(o.runout(), lube_runout(a) + resolution(o));
    EXPECT_LT(o.final_height(), lube_final_height(a) - resolution(o));
}

// Rolling resistance stands for the angular grains' (model §10): grains that
// hardly roll (μ_r = 0.3) stop short of the sand's runout, grains that roll
// easily (μ_r = 0.1) run past it, each by more than a grain; the law lies
// between them. The deposit of the grains that hardly roll comes to rest, its
// height within a grain of the law's.
TEST(ColumnCollapse, SandsRunoutLiesBetweenGrainsThatRollEasilyAndHardlyAndItsHeightWithinAGrain)
{
    CollapseCase hardly;
    hardly.rolling_friction_coeff = 0.3;
    CollapseCase easily;
    easily.rolling_friction_coeff = 0.1;
    const auto h = run_collapse(hardly);
    const auto e = run_collapse(easily);
    ASSERT_TRUE(h.ok()) << h.error();
    ASSERT_TRUE(e.ok()) << e.error();
    const double a = h.value().aspect_ratio();
    EXPECT_FALSE(h.value().settling.stands);
    EXPECT_TRUE(h.value().settling.at_rest);
    EXPECT_LT(h.value().runout() + resolution(h.value()), lube_runout(a));
    EXPECT_GT(e.value().runout() - resolution(e.value()), lube_runout(a));
    EXPECT_NEAR(h.value().final_height(), lube_final_height(a), resolution(h.value()));
}

// What stands (docs/model.md, "What stands"): the verdict reads the grains'
// bulk height and the grains lost, not the top of the highest grain or wire
// node, where a wire left standing as a spring keeps the height. Columns laid
// out directly: grains on equal-area discs (golden angle), a helix of wire.
namespace {

constexpr double stands_r = 1e-3;       // grain radius [m]
constexpr double stands_R = 20e-3;      // the column's radius [m]
constexpr int stands_layers = 12;       // H = 24 r … 24 mm
constexpr int stands_per_layer = 100;   // grains per layer of the column
constexpr double stands_escape = 30e-3; // 1.5 R

/// `count` grain centres filling a disc of radius `rho_m` (centres within
/// rho_m − r) evenly at height z, from `rho_min_m` out.
void disc_layer(std::vector<Vec3>& x, int count, double rho_m, double z_m, double rho_min_m = 0.0)
{
    const double a = rho_min_m * rho_min_m, b = (rho_m - stands_r) * (rho_m - stands_r);
    for (int k = 0; k < count; ++k) {
        const double rho = std::sqrt(a + (b - a) * (k + 0.5) / count), phi = 2.399963 * k;
        x.emplace_back(rho * std::cos(phi), rho * std::sin(phi), z_m);
    }
}

double layer_z(int k) { return stands_r + 2.0 * stands_r * k; }

/// The column as built: stands_layers full layers.
std::vector<Vec3> built_column()
{
    std::vector<Vec3> x;
    for (int k = 0; k < stands_layers; ++k) disc_layer(x, stands_per_layer, stands_R, layer_z(k));
    return x;
}

/// A World of the grains at `x` (radius stands_r) on a bottom plate at z = 0,
/// with a helix of wire of radius 15 mm from the plate to 2.5 mm above the
/// built column's top, which stands whatever the grains did.
World column_world(const std::vector<Vec3>& x)
{
    World w;
    const std::uint8_t mat = add_material(w, soft_grain);
    add_wall(w, make_plate(0.0, +1.0, mat));
    for (const Vec3& p : x) add_grain(w, p, stands_r, mat);
    const double top_m = 2.0 * stands_r * stands_layers + 2.5e-3;
    for (int i = 0; i <= 200; ++i) {
        const double t = i / 200.0;
        add_node(w, BodyKind::wire, Vec3(15e-3 * std::cos(40.0 * t), 15e-3 * std::sin(40.0 * t), 0.5e-3 + t * (top_m - 1e-3)),
            0.5e-3, 1e-6, mat);
    }
    return w;
}

FreeStandingSettings stands_settings()
{
    FreeStandingSettings s;
    s.escape_distance_m = stands_escape;
    return s;
}

/// The settling's reading of a column built as built_column() that settled
/// into `after`, at rest.
SettlingReading judged(const std::vector<Vec3>& after, bool at_rest = true)
{
    const FreeStandingSettings s = stands_settings();
    const StandingColumn before = standing_column(column_world(built_column()), s.escape_distance_m, s.bulk_fraction);
    SettlingReading r;
    r.at_rest = at_rest;
    r.height_before_m = before.top_m;
    r.bulk_height_before_m = before.bulk_height_m;
    judge_settled_column(r, standing_column(column_world(after), s.escape_distance_m, s.bulk_fraction), s);
    return r;
}

} // namespace

// The bulk height of grains filling a cylinder from the plate to H in n
// layers of centres 2r apart: V(z) rises by a layer's volume over each layer,
// as the sphere's cap t²(3 − 2t) (t the fraction of its diameter below z)
// where an even fill rises as t; the two differ by at most 0.096 (at t =
// 0.211), so z_q is q H within 0.096 × 2r and H_b = z_q/q is H within
// 0.2 r/q. With q = 1, H_b is the top of the highest grain, to what the
// rounding of the summed volume leaves near a cap's top, where V(z) is flat
// (δ ~ √(ε V / (π r n_top)), 10⁻¹⁰ m here): 10⁻⁵ r. Grains beyond the escape
// distance do not count.
TEST(BulkHeight, OfAFilledCylinderIsItsHeightWithinAFifthOfAGrainRadius)
{
    const double q = FreeStandingSettings{}.bulk_fraction;
    for (int n = 4; n <= 30; ++n) {
        std::vector<Vec3> x;
        for (int k = 0; k < n; ++k) disc_layer(x, 50, 10e-3, layer_z(k));
        const std::vector<double> radius(x.size(), stands_r);
        const double h = 2.0 * stands_r * n;
        EXPECT_NEAR(bulk_height_m(x, radius, 0.0, 1.0, q), h, 0.2 * stands_r / q) << n << " layers";
        EXPECT_NEAR(bulk_height_m(x, radius, 0.0, 1.0, 1.0), h, 1e-5 * stands_r) << n << " layers";
        // The same column on a plate 0.1 m up, with grains far out at its top: the same height.
        for (Vec3& p : x) p.z() += 0.1;
        std::vector<Vec3> more = x;
        std::vector<double> more_radius = radius;
        for (int k = 0; k < 100; ++k) {
            more.emplace_back(0.5, 0.0, 0.1 + h + 10e-3);
            more_radius.push_back(stands_r);
        }
        EXPECT_NEAR(bulk_height_m(more, more_radius, 0.1, 0.2, q), bulk_height_m(x, radius, 0.1, 1.0, q), 1e-12);
    }
    EXPECT_EQ(bulk_height_m({}, {}, 0.0, 1.0, q), 0.0);
}

// A heap (a cone of height H_c, even areal density) reads H_c (1 − (1 −
// q)^{1/3})/q: the volume below z is 1 − (1 − z/H_c)³ of it. Stepped into
// 40 layers, the heap is known to a layer.
TEST(BulkHeight, OfAHeapIsTheConesHeightTimesItsVolumeLaw)
{
    const double q = 0.95, hc = 80.0 * stands_r, rb = 60e-3;
    std::vector<Vec3> x;
    for (int k = 0; k < 40; ++k) {
        const double z = layer_z(k), rho = rb * (1.0 - z / hc);
        disc_layer(x, static_cast<int>(std::lround(4000.0 * (rho / rb) * (rho / rb))), rho + stands_r, z);
    }
    const std::vector<double> radius(x.size(), stands_r);
    EXPECT_NEAR(bulk_height_m(x, radius, 0.0, 1.0, q), hc * (1.0 - std::cbrt(1.0 - q)) / q, 2.0 * stands_r);
}

// The column at rest with all its grains, a little settled, stands; the same
// not at rest does not.
TEST(WhatStands, AColumnAtRestWithAllItsGrainsStands)
{
    std::vector<Vec3> after = built_column();
    for (Vec3& p : after) p.z() *= 0.98;
    const SettlingReading r = judged(after);
    EXPECT_EQ(r.grains, static_cast<std::size_t>(stands_layers * stands_per_layer));
    EXPECT_EQ(r.escaped_grains, 0u);
    EXPECT_EQ(r.lost_fraction, 0.0);
    EXPECT_NEAR(r.bulk_height_before_m, 2.0 * stands_r * stands_layers, 0.2 * stands_r / 0.95);
    EXPECT_NEAR(r.bulk_height_loss, 0.02, 2.0 * 0.2 * stands_r / 0.95 / r.bulk_height_before_m); // each H_b within 0.2 r/q
    EXPECT_TRUE(r.stands);
    EXPECT_FALSE(judged(after, false).stands);
}

// A column that ran out into a heap, its wire still standing to its old top:
// the top of the highest grain or wire node did not move (the reading before
// 2026-12-06 called it standing), the grains' bulk fell to a third and a
// quarter of them left.
TEST(WhatStands, AColumnThatRanOutIntoAHeapDoesNotStandThoughItsWireStands)
{
    std::vector<Vec3> heap;
    const int total = stands_layers * stands_per_layer, layers = 6;
    const double base_m = 45e-3;
    double sum = 0.0;
    for (int k = 0; k < layers; ++k) sum += (1.0 - double(k) / layers) * (1.0 - double(k) / layers);
    int placed = 0;
    for (int k = layers - 1; k >= 0; --k) { // the bottom layer takes what rounding leaves
        const double f = 1.0 - double(k) / layers;
        const int n = k == 0 ? total - placed : static_cast<int>(std::lround(total * f * f / sum));
        disc_layer(heap, n, base_m * f, layer_z(k));
        placed += n;
    }
    ASSERT_EQ(heap.size(), static_cast<std::size_t>(total));
    const SettlingReading r = judged(heap);
    EXPECT_LE(r.height_loss, 0.0) << "the wire keeps the top";
    EXPECT_GT(r.bulk_height_loss, 0.5);
    EXPECT_GT(r.lost_fraction, 0.2);
    EXPECT_FALSE(r.stands);
    // The same heap gathered within the escape distance (nothing lost): the bulk alone says no.
    for (Vec3& p : heap) p.head<2>() *= 0.6;
    const SettlingReading inside = judged(heap);
    EXPECT_EQ(inside.lost_fraction, 0.0);
    EXPECT_FALSE(inside.stands);
}

// The study's case (docs/study.md, "The free-standing column"): a core
// inside the wire stands to two thirds of the height, a few grains are
// caught in the wire above it, more than half the grains lie in a skirt
// beyond the escape distance. Not standing, by its bulk and by the grains
// lost; and a core that keeps its full height but shed more than the bound
// of grains does not stand either.
TEST(WhatStands, ACoreStandingInsideTheWireWithMostGrainsGoneDoesNotStand)
{
    const int total = stands_layers * stands_per_layer;
    std::vector<Vec3> x;
    for (int k = 0; k < 8; ++k) disc_layer(x, 70, 14e-3, layer_z(k));
    for (int k = 8; k < stands_layers; ++k) disc_layer(x, 4, 15e-3, layer_z(k), 13.5e-3);
    disc_layer(x, total - static_cast<int>(x.size()), 45e-3, layer_z(0), 31e-3);
    const SettlingReading r = judged(x);
    EXPECT_LE(r.height_loss, 0.0);
    EXPECT_GT(r.bulk_height_loss, 0.25);
    EXPECT_GT(r.lost_fraction, 0.5);
    EXPECT_FALSE(r.stands);

    std::vector<Vec3> shed;
    for (int k = 0; k < stands_layers; ++k) disc_layer(shed, 80, 16e-3, layer_z(k));
    disc_layer(shed, total - static_cast<int>(shed.size()), 45e-3, layer_z(0), 31e-3);
    const SettlingReading s = judged(shed);
    EXPECT_LE(s.bulk_height_loss, 0.0 + 0.2 * stands_r / s.bulk_height_before_m);
    EXPECT_NEAR(s.lost_fraction, 0.2, 1e-12);
    EXPECT_FALSE(s.stands);
}

// Clumps count as grains: once each, at their centre of mass with their
// volume-equivalent radius, in the escaped count, the lost volume and the
// profile (not as their spheres).
TEST(WhatStands, AClumpCountsOnceAsAGrain)
{
    World w;
    const std::uint8_t mat = add_material(w, soft_grain);
    add_wall(w, make_plate(0.0, +1.0, mat));
    const ClumpBody unit = unit_clump_shape(*builtin_clump_template("elongated"));
    const ClumpBody body = scaled_clump(unit, stands_r);
    add_grain(w, Vec3(0.0, 0.0, stands_r), stands_r, mat);
    add_clump(w, body, Vec3(5e-3, 0.0, 3.0 * stands_r), Quat::Identity(), mat);
    add_clump(w, body, Vec3(-5e-3, 0.0, 3.0 * stands_r), Quat::Identity(), mat);
    add_clump(w, body, Vec3(50e-3, 0.0, stands_r), Quat::Identity(), mat); // escaped
    ASSERT_EQ(w.of(BodyKind::grain).size(), 10u);
    const ColumnGrains g = column_grains(w);
    ASSERT_EQ(g.position_m.size(), 4u);
    EXPECT_EQ(g.position_m[1], Vec3(5e-3, 0.0, 3.0 * stands_r));
    EXPECT_NEAR(g.radius_m[1], stands_r, 1e-9 * stands_r);
    const StandingColumn c = standing_column(w, stands_escape, 0.95);
    EXPECT_EQ(c.grains, 4u);
    EXPECT_EQ(c.escaped_grains, 1u);
    EXPECT_NEAR(c.lost_fraction, 0.25, 1e-9); // four grains of one volume
    const RadiusProfile p = radius_profile(g.position_m, g.radius_m, 0.0, stands_escape);
    std::uint32_t counted = 0;
    for (std::uint32_t n : p.grains) counted += n;
    EXPECT_EQ(counted, 3u);
}
