// Derived quantities of a job: the stability inputs, the body estimate and
// the damping time (see api/derived.hpp).
#include "api/derived.hpp"

#include "api/engine_settings.hpp"

#include "laws/hertz.hpp"
#include "laws/membrane_edge.hpp"
#include "laws/wire_bond.hpp"
#include "specimen/preparation.hpp"
#include "state/world.hpp"
#include "timestep.hpp"
#include "triaxial/sampling.hpp"
#include "triaxial/triaxial.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>

namespace wiredem::api {

namespace {

/// Mass of a wire node: ρ_w π r_w² l_w (the model spec §2), unscaled [kg].
double wire_node_mass_kg(const WireSpec& w)
{
    return w.density_kg_per_m3 * std::numbers::pi * w.radius_m * w.radius_m * w.segment_length_m;
}

/// Mass of a membrane node: (√3/2) l_m² ρ_m d (the model spec §2), unscaled [kg].
double membrane_node_mass_kg(const MembraneSpec& m)
{
    return 0.5 * std::numbers::sqrt3 * m.mesh_size_m * m.mesh_size_m * m.density_kg_per_m3 * m.thickness_m;
}

} // namespace

engine::StabilityInputs stability_inputs(const JobSpec& spec)
{
    const SpecimenSpec& s = spec.specimen;
    const double scale = spec.engine.density_scale;
    const double wire_scale = scale * spec.engine.wire_mass_scale;
    auto plane_modulus_pa = [](const auto& material) {
        return engine::plane_modulus_pa({material.youngs_modulus_pa, material.poisson_ratio});
    };
    engine::StabilityInputs in;
    // Density scaling multiplies every mass; the wire's once more. The
    // grains: the smallest one the preparation draws, a sphere or a clump
    // (its smallest sphere, the mass its contacts see), as the engine's
    // World holds it.
    in.kinds[0] = engine::smallest_grain_stability(preparation_geometry(spec));
    if (s.wire.pattern != WirePattern::none) {
        const double node_mass_kg = wire_node_mass_kg(s.wire) * wire_scale;
        in.kinds[1].include(node_mass_kg, false, s.wire.radius_m, plane_modulus_pa(s.wire));
        in.wire_segment_stiffness_n_per_m
            = engine::wire_axial_stiffness_n_per_m(s.wire.youngs_modulus_pa, s.wire.radius_m, s.wire.segment_length_m);
        in.wire_node_mass_kg = node_mass_kg;
    }
    // The contacts' damping when given as γ_n. From a restitution it is left
    // out: that γ_n is a fit of 50–250 ms (resolved_normal_damping_s), too
    // much for validating every submitted job. The run's own step includes
    // it (engine::stable_time_step of the World), so a heavily damped Gear-5
    // job runs up to 1/engine::min_damped_step_fraction times the steps
    // estimated here, and more is refused when it starts (docs/model.md,
    // "Integration and time step").
    if (const auto* given = std::get_if<NormalDampingTime>(&spec.contact.normal_damping))
        in.normal_damping_s = given->normal_damping_s;
    in.integrator = spec.engine.integrator;
    in.tangential_stiffness_per_m = spec.contact.tangential.stiffness_per_m;
    in.friction_coeff = spec.contact.tangential.friction_coeff;
    in.rolling_stiffness_factor = spec.contact.rolling.on() ? spec.contact.rolling.stiffness_factor : 0.0;
    const double membrane_node_kg = membrane_node_mass_kg(s.membrane) * scale;
    in.kinds[2].include(membrane_node_kg, false, membrane_contact_radius_m(s.membrane), plane_modulus_pa(s.membrane));
    in.membrane_edge_stiffness_n_per_m
        = engine::membrane_edge_stiffness_n_per_m(s.membrane.youngs_modulus_pa, s.membrane.thickness_m);
    in.membrane_node_mass_kg = membrane_node_kg;
    in.wall_plane_moduli_pa.push_back(plane_modulus_pa(s.plate));
    return in;
}

StableStep stable_time_step(const JobSpec& spec)
{
    return engine::stable_time_step(stability_inputs(spec));
}

namespace {

/// ⌈x⌉ as a count, saturating at the largest std::uint64_t (a hostile spec
/// can ask for more than any integer holds; the cast would be undefined).
std::uint64_t saturating_count(double x)
{
    constexpr double limit = 18446744073709549568.0; // the largest double below 2⁶⁴
    if (!(x < limit)) return std::numeric_limits<std::uint64_t>::max();
    return x > 0.0 ? static_cast<std::uint64_t>(std::ceil(x)) : 0;
}

} // namespace

BodyCounts estimated_body_counts(const JobSpec& spec)
{
    const SpecimenSpec& s = spec.specimen;
    BodyCounts n;
    n.grains = s.grain_count;
    if (s.wire.pattern != WirePattern::none) {
        // Laid at ω R_a while the grains are poured (fill height / fill rate),
        // as the preparation paces it.
        const double laid_length_m = engine::estimated_wire_length_m(preparation_geometry(spec));
        const std::uint64_t segments = saturating_count(laid_length_m / s.wire.segment_length_m);
        n.wire_nodes = segments == std::numeric_limits<std::uint64_t>::max() ? segments : segments + 1;
    }
    // Rows of a triangular mesh are l_m √3/2 apart.
    const double around = std::ceil(2.0 * std::numbers::pi * s.membrane_radius_m / s.membrane.mesh_size_m);
    const double rows = std::ceil(s.membrane_height_m / s.membrane.mesh_size_m * 2.0 / std::numbers::sqrt3) + 1.0;
    n.membrane_nodes = saturating_count(around * rows);
    return n;
}

ProgressShares progress_shares(const WorkEstimate& work)
{
    ProgressShares s;
    // The preparation's longest pour and settling against the tests' steps,
    // kept between 1 % and half so that neither stage's bar stands still.
    s.preparation = std::clamp(ProgressShares::tests_end * work.preparation_steps / work.total_steps(), 0.01, 0.5);
    // The tests share the rest in proportion to their steps (equally if
    // their estimates are not usable: a hostile spec's infinities).
    const double tests_steps = work.tests_total_steps();
    const bool by_steps = std::isfinite(tests_steps) && tests_steps > 0.0;
    const double parts = static_cast<double>(work.test_steps.size()) + (work.free_standing_steps > 0.0 ? 1.0 : 0.0);
    const auto share = [&](double steps) { return (ProgressShares::tests_end - s.preparation) * (by_steps ? steps / tests_steps : 1.0 / parts); };
    for (const double steps : work.test_steps) s.tests.push_back(share(steps));
    if (work.free_standing_steps > 0.0) s.free_standing = share(work.free_standing_steps);
    return s;
}

WorkEstimate estimated_work(const JobSpec& spec)
{
    WorkEstimate w;
    w.time_step_s = spec.engine.time_step_s ? *spec.engine.time_step_s : stable_time_step(spec).auto_s;
    const TriaxialSpec& t = spec.triaxial;
    const double height_m = engine::estimated_fill_height_m(preparation_geometry(spec));
    w.preparation_steps = spec.specimen.pouring.max_preparation_time_s / w.time_step_s;
    double longest = 0.0;
    for (std::size_t k = 0; k < t.confining_pressures_pa.size(); ++k) {
        const engine::TriaxialSettings test = triaxial_settings(spec, k);
        const double test_s =
            test.pressure_ramp_time_s + engine::longest_hold_s(test) + engine::loading_time_s(test, height_m);
        w.test_steps.push_back(test_s / w.time_step_s);
        longest = std::max(longest, w.test_steps.back());
    }
    if (spec.free_standing.enabled)
        w.free_standing_steps = engine::longest_free_standing_time_s(free_standing_settings(spec), height_m) / w.time_step_s;
    // A row every engine::steps_per_sample steps, and the last one.
    w.samples_per_test = longest / static_cast<double>(engine::steps_per_sample(t.sample_interval_s, w.time_step_s)) + 1.0;
    return w;
}

std::string work_field(const JobSpec& spec, const WorkEstimate& work)
{
    if (spec.engine.time_step_s) return "engine.time_step_s";
    const double tests = work.total_steps() - work.preparation_steps;
    return work.preparation_steps > tests ? "specimen.pouring.max_preparation_time_s" : "triaxial.plate_speed_m_per_s";
}

double resolved_normal_damping_s(const JobSpec& spec)
{
    if (const auto* given = std::get_if<NormalDampingTime>(&spec.contact.normal_damping))
        return given->normal_damping_s;
    const auto& e = std::get<NormalRestitution>(spec.contact.normal_damping);
    const SpecimenSpec& s = spec.specimen;
    const double r = reference_grain_radius_m(s);
    const double mass_kg = s.grain.density_kg_per_m3 * spec.engine.density_scale * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double e_star = engine::effective_modulus_pa(
        s.grain.youngs_modulus_pa, s.grain.poisson_ratio, s.grain.youngs_modulus_pa, s.grain.poisson_ratio);
    const std::array<double, 5> inputs{
        e.restitution, 0.5 * mass_kg, e.restitution_reference_speed_m_per_s, e_star, engine::effective_radius_m(r, r)};
    // The fit integrates a contact for every bisection step (50–250 ms): a
    // pure function of its inputs, remembered, so that the many jobs of a
    // study or a flood of submits with the same grains pay it once. Bounded:
    // a full table is emptied.
    if (!std::all_of(inputs.begin(), inputs.end(), [](double x) { return std::isfinite(x); }))
        return engine::hertz_damping_for_restitution_s(inputs[0], inputs[1], inputs[2], inputs[3], inputs[4]);
    static std::mutex mutex;
    static std::map<std::array<double, 5>, double> fits;
    constexpr std::size_t max_fits = 4096;
    {
        std::lock_guard lock(mutex);
        if (const auto it = fits.find(inputs); it != fits.end()) return it->second;
    }
    const double gamma = engine::hertz_damping_for_restitution_s(inputs[0], inputs[1], inputs[2], inputs[3], inputs[4]);
    std::lock_guard lock(mutex);
    if (fits.size() >= max_fits) fits.clear();
    fits.emplace(inputs, gamma);
    return gamma;
}

} // namespace wiredem::api
