// JobSpec → engine inputs; see api/engine_settings.hpp.
#include "api/engine_settings.hpp"

#include "api/derived.hpp"

#include <array>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace wiredem::api {

engine::SieveCurve sieve_curve(const GrainSizesSpec& g)
{
    engine::SieveCurve c;
    c.basis = g.basis;  // the engine's own basis
    c.diameters_m = g.diameters_m;
    c.fraction_passing = g.fraction_passing;
    return c;
}

engine::ClumpBody grain_shape_body(const GrainShapeSpec& g)
{
    // A pure function of the shape, asked by every check that builds the
    // job's preparation geometry (about ten per validation): computed once
    // per shape and kept (a bounded cache; the same body, bit for bit).
    static std::mutex mutex;
    static std::map<std::pair<std::string, std::vector<std::array<double, 4>>>, engine::ClumpBody> cache;
    constexpr std::size_t max_cached = 64;
    const auto key = std::make_pair(g.template_name, g.spheres);
    {
        const std::lock_guard lock(mutex);
        if (const auto it = cache.find(key); it != cache.end()) return it->second;
    }
    engine::ClumpBody body;
    if (!g.template_name.empty()) {
        body = engine::unit_clump_shape(*engine::builtin_clump_template(g.template_name));
    } else {
        std::vector<engine::ClumpSphere> spheres;
        for (const auto& s : g.spheres) spheres.push_back({engine::Vec3(s[0], s[1], s[2]), s[3]});
        body = engine::unit_clump_shape(spheres);
    }
    const std::lock_guard lock(mutex);
    if (cache.size() >= max_cached) cache.clear();
    cache.emplace(key, body);
    return body;
}

double reference_grain_radius_m(const SpecimenSpec& s)
{
    if (!s.grain_sizes) return s.grain_radius_m;
    return 0.5 * engine::GrainSizeDistribution(sieve_curve(*s.grain_sizes)).diameter_at_mass_fraction(0.5);
}

namespace {

/// The preparation of a job; the normal damping resolved only when asked.
engine::PreparationSpec preparation(const JobSpec& spec, bool resolve_damping)
{
    const SpecimenSpec& s = spec.specimen;
    engine::PreparationSpec p;
    static_cast<engine::SpecimenSize&>(p) = s;  // the engine's own size, as given
    if (s.grain_sizes) p.grain_sizes = sieve_curve(*s.grain_sizes);
    if (s.grain_shape) p.grain_shape = grain_shape_body(*s.grain_shape);
    p.grain = s.grain;  // the engine's own material
    p.plate.youngs_modulus_pa = s.plate.youngs_modulus_pa;
    p.plate.poisson_ratio = s.plate.poisson_ratio;

    static_cast<engine::WireMaterial&>(p.wire) = s.wire;  // the engine's own material, as given
    p.wire.bending_yield_strain = s.wire.bending_yield_strain.value_or(std::numeric_limits<double>::infinity());
    p.wire.breaking_strain = s.wire.breaking_strain.value_or(std::numeric_limits<double>::infinity());
    p.wire.density_scale = spec.engine.density_scale * spec.engine.wire_mass_scale;

    p.pattern = pattern_spec(s.wire);
    p.clearance_m = s.wire.clearance_m;

    static_cast<engine::MembraneMaterial&>(p.membrane) = s.membrane;  // the engine's own material, as given
    p.membrane.contact_radius_m = membrane_contact_radius_m(s.membrane);
    p.membrane.density_scale = spec.engine.density_scale;

    p.contact.normal_damping_s = resolve_damping ? resolved_normal_damping_s(spec) : 0.0;
    p.contact.tangential = spec.contact.tangential;  // the engine's own laws
    p.contact.rolling = spec.contact.rolling;

    p.density_scale = spec.engine.density_scale;
    p.wire_mass_scale = spec.engine.wire_mass_scale;
    // The fill rate: given, or the one that lays the wire's given length,
    // or the engine's default.
    if (s.pouring.fill_rate_m_per_s)
        p.fill_rate_m_per_s = *s.pouring.fill_rate_m_per_s;
    else if (s.wire.length_m && p.pattern.pattern != engine::PatternKind::none)
        p.fill_rate_m_per_s = engine::fill_rate_for_wire_length_m_per_s(p, *s.wire.length_m);
    p.settle_kinetic_energy_per_grain_j = s.pouring.settle_kinetic_energy_per_grain_j;
    p.max_time_s = s.pouring.max_preparation_time_s;
    p.time_step_s = spec.engine.time_step_s.value_or(0.0);
    p.integrator = spec.engine.integrator;  // the engine's own integrator
    p.seed = spec.seed;
    return p;
}

} // namespace

engine::PreparationSpec preparation_spec(const JobSpec& spec) { return preparation(spec, true); }

engine::PreparationSpec preparation_geometry(const JobSpec& spec) { return preparation(spec, false); }

engine::TriaxialSettings triaxial_settings(const JobSpec& spec, std::size_t test)
{
    engine::TriaxialSettings t;
    static_cast<engine::TriaxialParams&>(t) = spec.triaxial;  // the engine's own parameters, as given
    t.confining_pressure_pa = spec.triaxial.confining_pressures_pa.at(test);
    t.plate_speed_m_per_s = spec.triaxial.plate_speed_m_per_s(test);
    // The prepared specimen carries weights scaled like its masses; the test
    // gives it its real weight back (engine/specimen/preparation.hpp).
    t.real_weights = engine::TriaxialSettings::MassScaling{spec.engine.density_scale, spec.engine.wire_mass_scale};
    return t;
}

engine::FreeStandingSettings free_standing_settings(const JobSpec& spec)
{
    const FreeStandingSpec& f = spec.free_standing;
    engine::FreeStandingSettings s;
    static_cast<engine::FreeStandingParams&>(s) = f;  // the engine's own parameters, as given
    s.escape_distance_m = escape_distance_m(spec);
    if (f.dead_load_n) s.dead_load = engine::DeadLoad{*f.dead_load_n, f.dead_load_ramp_time_s, f.dead_load_hold_time_s};
    if (f.pull_out_speed_m_per_s) {
        engine::PullOutSettings p;
        p.end = f.pull_out_end;  // the engine's own end
        if (f.pull_out_direction.size() == 3)
            p.direction = engine::Vec3(f.pull_out_direction[0], f.pull_out_direction[1], f.pull_out_direction[2]);
        p.speed_m_per_s = *f.pull_out_speed_m_per_s;
        p.ramp_time_s = f.pull_out_ramp_time_s;
        p.length_m = f.pull_out_length_m;
        p.max_time_s = f.pull_out_max_time_s;
        s.pull_out = p;
    }
    s.snapshot_strains = {0.5 * f.target_axial_strain};
    s.real_weights = engine::TriaxialSettings::MassScaling{spec.engine.density_scale, spec.engine.wire_mass_scale};
    return s;
}

engine::WireCuts wire_cuts(const JobSpec& spec)
{
    return {.at_m = spec.specimen.wire.cuts_at_m, .every_loops = spec.specimen.wire.cut_every_loops};
}

engine::PatternSpec pattern_spec(const WireSpec& w)
{
    engine::PatternSpec p;
    static_cast<engine::PatternParams&>(p) = w;  // the engine's own parameters, as given
    if (w.pattern == WirePattern::toolpath) {
        for (std::size_t i = 0; i < std::min(w.toolpath_x_m.size(), w.toolpath_y_m.size()); ++i)
            p.toolpath_m.emplace_back(w.toolpath_x_m[i], w.toolpath_y_m[i], 0.0);
        p.toolpath_rotation_per_layer_rad = w.toolpath_rotation_per_layer_rad;
    }
    return p;
}

namespace {

/// The box of the poured specimen `poured` with the job's cuboid settings.
engine::Result<engine::BoxPreparationSpec, std::string> box_of(const JobSpec& spec, const engine::PreparationSpec& poured)
{
    const TriaxialSpec& t = spec.triaxial;
    auto box = engine::box_preparation_from(poured, t.confining_pressures_pa.front(), t.cuboid.wall_friction_coeff);
    if (!box.ok()) return box;
    box.value().aspect_ratio = t.cuboid.aspect_ratio;
    box.value().compaction_friction_coeff = t.cuboid.compaction_friction_coeff;
    return box;
}

} // namespace

engine::Result<engine::BoxPreparationSpec, std::string> box_preparation_spec(const JobSpec& spec)
{
    return box_of(spec, preparation_spec(spec));
}

engine::Result<engine::BoxPreparationSpec, std::string> box_preparation_geometry(const JobSpec& spec)
{
    return box_of(spec, preparation_geometry(spec));
}

} // namespace wiredem::api
