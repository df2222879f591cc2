// The job spec: one JSON document describes a whole triaxial campaign (one
// specimen, tested at several confining pressures). Server and client share
// these structs, the parser (which validates) and the serializer (style §8).
//
// Invariants: every field is defaulted to the model's default (the model spec
// §2–§8), so `{}` is a valid job and `JobSpec{}` is its parse; field names
// carry SI units; parse_job_spec(to_json(s)) == s for every valid s. The
// schema with units, defaults and allowed ranges is in docs/job-spec.md; the
// ranges live in job_spec.cpp (one table per object) next to the reader.
// All functions are pure and thread-safe.
#pragma once

#include "api/grain_presets.hpp"
#include "core/result.hpp"
#include "forces/membrane_material.hpp"
#include "forces/wire_material.hpp"
#include "laws/rolling.hpp"
#include "laws/tangential.hpp"
#include "specimen/pattern_kind.hpp"
#include "specimen/pattern_params.hpp"
#include "specimen/sieve_basis.hpp"
#include "specimen/specimen_size.hpp"
#include "state/integrator.hpp"
#include "state/materials.hpp"
#include "state/membrane_edge_law.hpp"
#include "triaxial/consolidation_kind.hpp"
#include "triaxial/free_standing_params.hpp"
#include "triaxial/triaxial_params.hpp"
#include "triaxial/wire_end.hpp"

#include <boost/json/object.hpp>
#include <boost/json/value.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace wiredem::api {

// The enums of the spec are the engine's own, read into directly through
// the engine's one name table of each (engine/core/name_table.hpp): the JSON
// names are the engine's, and nothing translates them.

/// How the nozzle lays the wire (the model spec §5;
/// engine/specimen/pattern_kind.hpp). JSON: "none", "helix", "spiral_helix",
/// "radial_helix", "toolpath" (a toolpath's points: WireSpec::toolpath_x_m).
using WirePattern = engine::PatternKind;

/// Time integrator (the model spec §4; engine/state/integrator.hpp). JSON:
/// "gear5", "verlet".
using Integrator = engine::Integrator;

/// How a membrane edge acts when shorter than its rest length
/// (engine/state/membrane_edge_law.hpp). JSON: "tension_only" (the sheet
/// wrinkles: slack in compression; default), "linear".
using MembraneEdges = engine::MembraneEdgeLaw;

/// What the top plate consolidates the column to before loading
/// (engine/triaxial/consolidation_kind.hpp). JSON: "cell_pressure",
/// "effective" (default).
using Consolidation = engine::Consolidation;

/// The triaxial cell. JSON: "membrane", "cuboid". See
/// engine/triaxial/cuboid.hpp and engine/specimen/box_preparation.hpp.
enum class CellKind : std::uint8_t {
    membrane, ///< the poured column in the pressurised membrane (default; the model spec §6)
    cuboid,   ///< a box of six rigid walls, the specimen compacted in it by servo walls (issue 43)
};

/// What the fractions of a grain-size curve count
/// (engine/specimen/sieve_basis.hpp). JSON: "mass", "number".
using GrainSizeBasis = engine::SieveBasis;

/// A grain-size distribution (docs/model.md, "Size distribution"): the
/// fraction passing each size, linear in log D between sizes.
struct GrainSizesSpec {
    GrainSizeBasis basis = GrainSizeBasis::mass;
    /// D_k, grain diameters (sieve apertures) [m]: 2–64 entries, each in
    /// [2e-5, 0.2] (radii in grain_radius_m's range), strictly increasing.
    std::vector<double> diameters_m;
    /// P_k, the fraction passing D_k: one per diameter, each in [0, 1],
    /// nondecreasing, the first 0 and the last 1.
    std::vector<double> fraction_passing;
    friend bool operator==(const GrainSizesSpec&, const GrainSizesSpec&) = default;
};

/// The shape of every grain: a rigid clump of overlapping spheres
/// (docs/model.md, "Clumps"), a built-in template or the given spheres.
/// Exactly one of the two is set. A grain of radius r (from grain_radius_m
/// and its spread, or a curve) is the clump scaled to a volume-equivalent
/// radius r.
struct GrainShapeSpec {
    /// A built-in template: "elongated", "flat", "tetrahedral" or "crushed"; empty when spheres are given.
    std::string template_name;
    /// Spheres (x, y, z, radius) in any length unit (only the shape counts):
    /// 2–32, radii > 0 and at least a tenth of the largest, the union connected.
    std::vector<std::array<double, 4>> spheres;
    friend bool operator==(const GrainShapeSpec&, const GrainShapeSpec&) = default;
};

/// Elastic properties of the grains (the model spec §2): the engine's own
/// material (engine/state/materials.hpp), whose defaults are the model's
/// grains. JSON ranges: E_p (0, 1e13] Pa, ν_p (-1, 0.5], ρ_p (0, 1e5] kg/m³.
using GrainMaterialSpec = engine::Material;

/// Elastic properties of both plates (the model spec §2). Plates do not move
/// freely, so they have no density.
struct PlateMaterialSpec {
    double youngs_modulus_pa = 1e9;      ///< E_b [Pa], (0, 1e13]
    double poisson_ratio = 0.3;          ///< ν_b, (-1, 0.5]
    friend bool operator==(const PlateMaterialSpec&, const PlateMaterialSpec&) = default;
};

/// The wire and how the nozzle lays it (the model spec §2, §5). Its
/// material and the nozzle's pattern are the engine's own
/// (engine/forces/wire_material.hpp: radius_m, segment_length_m,
/// youngs_modulus_pa, poisson_ratio, density_kg_per_m3;
/// engine/specimen/pattern_params.hpp: pattern, nozzle_rise_speed_m_per_s,
/// angular_speed_rad_per_s, helix_radius_m, inner_radius_m,
/// period_angle_rad; with their defaults), read into directly. The pattern
/// parameters that a pattern does not use are kept (and validated) but ignored.
struct WireSpec : engine::WireMaterial, engine::PatternParams {
    double clearance_m = 1e-3;                 ///< gap kept to the membrane beyond r_w [m], [0, 0.1]
    /// ε_y = σ_y/E_w, yield strain of the wire in bending, (0, 1]: every joint is an
    /// elastic–perfectly-plastic hinge that yields at ζ_y = ε_y l_w / r_w, so the
    /// nozzle forms the wire plastically (docs/model.md, "Wire"). nullopt
    /// ("elastic" in JSON): the model spec's elastic wire, straight at rest.
    std::optional<double> bending_yield_strain = engine::default_bending_yield_strain;
    /// L, the length of wire to lay [m], (0, 1e4]; the fill rate then follows
    /// from it (the wire is laid at ω R_a while the fill rises: see
    /// fill_rate_m_per_s below). nullopt: the fill rate sets the length. The
    /// paper's column has about 10 m (the model spec §9).
    std::optional<double> length_m;
    /// ε_b, the strain past which a segment breaks (the chain then has two
    /// free ends there), (0, 10]; nullopt ("unbreakable" in JSON, the
    /// default): the model spec's wire (docs/model.md, "A wire that breaks").
    /// Written to job.json only when set, so other jobs' files stay as they were.
    std::optional<double> breaking_strain;
    /// Where the laid wire is cut once the specimen is prepared, before any
    /// test: positions along the wire (rest length from its first node) [m],
    /// strictly increasing, each in (0, 1e4]; the segment that holds a
    /// position is removed. Written only when not empty.
    std::vector<double> cuts_at_m;
    /// Cut the prepared wire after every this many loops around the column's
    /// axis (the winding angle of its nodes), [0, 1e6]; 0: no such cuts.
    /// Written only when not 0.
    std::uint64_t cut_every_loops = 0;
    /// The toolpath pattern's polyline of one layer: the points' x and y in
    /// the column's frame [m], as many of each, 2 to 10 000, each in [−1, 1];
    /// the nozzle walks it at the path speed ω R_a, then on to the next
    /// layer's first point (engine/specimen/pattern.hpp). Only with the
    /// pattern "toolpath" (and written only then).
    std::vector<double> toolpath_x_m, toolpath_y_m;
    /// The turn of the toolpath about the axis from one layer to the next
    /// [rad], [−2π, 2π]. Written only with the pattern "toolpath".
    double toolpath_rotation_per_layer_rad = 0.0;
    friend bool operator==(const WireSpec&, const WireSpec&) = default;
};

/// The membrane (the model spec §2, §3). Its material and mesh are the
/// engine's own (engine/forces/membrane_material.hpp: thickness_m,
/// mesh_size_m, youngs_modulus_pa, poisson_ratio, density_kg_per_m3, edges,
/// with their defaults), read into directly.
struct MembraneSpec : engine::MembraneMaterial {
    /// r_m, contact radius of a node [m], (0, 0.01]; nullopt (JSON null or
    /// absent): thickness_m / 2, following the thickness. See
    /// membrane_contact_radius_m.
    std::optional<double> contact_radius_m;
    friend bool operator==(const MembraneSpec&, const MembraneSpec&) = default;
};

/// The effective membrane contact radius r_m [m]: the given one, or d/2.
[[nodiscard]] inline double membrane_contact_radius_m(const MembraneSpec& m)
{
    return m.contact_radius_m ? *m.contact_radius_m : 0.5 * m.thickness_m;
}

/// When the preparation (the model spec §5) ends.
struct PouringSpec {
    /// Speed at which the pile's fill height rises while pouring [m/s],
    /// (0, 100], and at most 0.6 v_z^w when a wire is laid (the nozzle must
    /// be able to follow the pile's uneven top). With the wire laid at ω R_a
    /// it sets the wire per height of column: a helix's pitch is 2π v_fill / ω.
    /// nullopt: from specimen.wire.length_m when a wire of given length is
    /// laid, otherwise 0.25 m/s = v_z^w/2 (pitch 5.2 mm at ω = 300 rad/s).
    /// Setting both this and the wire's length is an error. Use
    /// fill_rate_m_per_s(const JobSpec&) for the value in force.
    std::optional<double> fill_rate_m_per_s;
    /// Settled when the mean kinetic energy per grain falls below this [J], (0, 1].
    double settle_kinetic_energy_per_grain_j = 1e-9;
    /// The preparation fails if not settled after this much simulated time [s], (0, 1e4].
    double max_preparation_time_s = 2.0;
    friend bool operator==(const PouringSpec&, const PouringSpec&) = default;
};

/// The specimen: membrane, grains, wire and how they are poured. Its size
/// is the engine's own (engine/specimen/specimen_size.hpp: membrane_radius_m,
/// membrane_height_m, grain_count, grain_radius_m, grain_radius_spread, with
/// their defaults), read into directly.
struct SpecimenSpec : engine::SpecimenSize {
    /// Grain sizes from a curve instead of r_p and s (which must then be
    /// left out of the JSON; reference_grain_radius_m stands for r_p).
    std::optional<GrainSizesSpec> grain_sizes;
    /// Every grain a clump of this shape; none: spheres (the model spec's grains).
    std::optional<GrainShapeSpec> grain_shape;
    /// A named grain preset (api/grain_presets.hpp). The reader fills
    /// grain_sizes (the preset's sieve curve scaled to D50 = 2 grain_radius_m),
    /// grain_shape and the contact's friction_coeff, rolling_friction_coeff and
    /// rolling_damping_ratio from it and refuses those fields (and
    /// grain_radius_spread) beside it; to_json writes the name instead of them.
    GrainPreset grain_preset = GrainPreset::none;
    GrainMaterialSpec grain;                   ///< grain material
    PlateMaterialSpec plate;                   ///< plate material
    WireSpec wire;                             ///< the wire and its deployment
    MembraneSpec membrane;                     ///< the membrane
    PouringSpec pouring;                       ///< end of the preparation
    friend bool operator==(const SpecimenSpec&, const SpecimenSpec&) = default;
};

/// Normal damping given as a coefficient of restitution e_n; γ_n is derived
/// from it for a head-on grain–grain collision at the reference speed
/// (resolved_normal_damping_s in api/derived.hpp).
struct NormalRestitution {
    double restitution = 0.5;                          ///< e_n, (0, 1]
    double restitution_reference_speed_m_per_s = 0.1;  ///< impact speed for e_n [m/s], (0, 100]
    friend bool operator==(const NormalRestitution&, const NormalRestitution&) = default;
};

/// Normal damping given directly as γ_n in seconds (the model spec §3).
struct NormalDampingTime {
    double normal_damping_s = 0.0;  ///< γ_n [s], [0, 1]
    friend bool operator==(const NormalDampingTime&, const NormalDampingTime&) = default;
};

/// The contact law shared by every pair (the model spec §3).
struct ContactSpec {
    /// Exactly one of the two forms; JSON: either `restitution` (+
    /// `restitution_reference_speed_m_per_s`) or `normal_damping_s`.
    std::variant<NormalRestitution, NormalDampingTime> normal_damping = NormalRestitution{};
    /// The tangential law (engine/laws/tangential.hpp), its fields read by
    /// the JSON names tangential_stiffness_per_m (k_t), friction_coeff (μ),
    /// critical_slip_m (d_cr) and tangential_damping_s_per_m (γ_t).
    engine::TangentialParams tangential;
    /// Rolling resistance (engine/laws/rolling.hpp; docs/model.md, "Rolling
    /// resistance"), its fields read by the JSON names
    /// rolling_friction_coeff (μ_r; 0 = off), rolling_stiffness_factor (f_r)
    /// and rolling_damping_ratio (η_r).
    engine::RollingParams rolling;
    friend bool operator==(const ContactSpec&, const ContactSpec&) = default;
};

/// The triaxial tests (the model spec §6), one per confining pressure.
/// The engine's own parameters of a test (engine/triaxial/triaxial_params.hpp:
/// target, ramp, hold, consolidation, sampling and snapshots, with their
/// defaults), read into directly; then the pressures and speeds each test
/// takes one of, and the cell (api/engine_settings.cpp, triaxial_settings).
struct TriaxialSpec : engine::TriaxialParams {
    /// σ_3 of each test [Pa]: 1–16 entries, each in (0, 1e7], strictly increasing.
    std::vector<double> confining_pressures_pa{20e3, 40e3, 60e3, 80e3};
    /// Top plate speed v_z [m/s], each in (0, 10]: one entry for every test
    /// (a number in the JSON), or one per confining pressure (an array), so
    /// that the low pressures can load slower (docs/model.md, "Quasi-static
    /// scaling").
    std::vector<double> plate_speeds_m_per_s{2e-4};
    /// The cell. to_json writes it (and `cuboid`) only for the cuboid cell,
    /// so that the job files and results of membrane jobs stay as they were.
    CellKind cell = CellKind::membrane;
    /// The cuboid cell's box and walls (read with cell = cuboid only).
    struct Cuboid {
        double aspect_ratio = 2.0;                 ///< height/width of the box, [0.25, 4]
        double wall_friction_coeff = 0.0;          ///< μ_w of the six walls, [0, 10]
        /// μ_c while the box is compacted (sets the density), [0, 10];
        /// nullopt: contact.friction_coeff.
        std::optional<double> compaction_friction_coeff;
        friend bool operator==(const Cuboid&, const Cuboid&) = default;
    } cuboid;
    /// v_z of test `test` (an index into confining_pressures_pa).
    [[nodiscard]] double plate_speed_m_per_s(std::size_t test) const
    {
        return plate_speeds_m_per_s.size() == 1 ? plate_speeds_m_per_s.front() : plate_speeds_m_per_s.at(test);
    }
    friend bool operator==(const TriaxialSpec&, const TriaxialSpec&) = default;
};

/// Which end of the wire a pull-out pulls (engine/triaxial/wire_end.hpp).
/// JSON: "last", "first".
using WireEndSpec = engine::WireEnd;

/// The free-standing test (issue 39; engine/triaxial/free_standing.hpp):
/// after the triaxial tests, the prepared column's formwork is removed, the
/// column settles on the bottom plate, optionally carries a dead load, and is
/// compressed unconfined. Not run unless `enabled`.
/// The engine's own parameters (engine/triaxial/free_standing_params.hpp:
/// removal, settling, standing, compression and sampling, with their
/// defaults and ranges), read into directly, then what the engine gets
/// derived (api/engine_settings.cpp, free_standing_settings).
struct FreeStandingSpec : engine::FreeStandingParams {
    bool enabled = false;                      ///< run the test
    /// A grain farther than this from the axis has left the column [m],
    /// (0, 100], more than specimen.membrane_radius_m; nullopt: 1.5 × it.
    std::optional<double> escape_distance_m;
    /// A dead load on the top plate after settling [N], (0, 1e9]; nullopt: none.
    std::optional<double> dead_load_n;
    double dead_load_ramp_time_s = 0.01;       ///< the load rises over this [s], [0, 1e3]
    double dead_load_hold_time_s = 0.05;       ///< then is held this long [s], (0, 1e3]
    /// Pull the wire out after settling, instead of the compression, at this
    /// speed [m/s], (0, 10]; nullopt: no pull-out (engine/triaxial/pull_out.hpp).
    std::optional<double> pull_out_speed_m_per_s;
    WireEndSpec pull_out_end = WireEndSpec::last; ///< the end pulled: the last node laid (top) or the first
    std::vector<double> pull_out_direction{0.0, 0.0, 1.0}; ///< d, 3 numbers in [−1, 1], not all 0
    double pull_out_ramp_time_s = 0.01;        ///< the speed rises over this [s], [0, 1e3]
    /// Stop after pulling this far [m], (0, 1e3]; nullopt: when the pulled
    /// piece of wire has left the settled column.
    std::optional<double> pull_out_length_m;
    double pull_out_max_time_s = 1.0;          ///< the pull ends here at the latest [s], (0, 1e4]
    friend bool operator==(const FreeStandingSpec&, const FreeStandingSpec&) = default;
};

/// Numerical settings.
struct EngineSpec {
    /// δt [s]: nullopt = "auto" (auto_s of stable_time_step); a number must be
    /// in (0, 1e-3] and at most the stable limit.
    std::optional<double> time_step_s;
    Integrator integrator = Integrator::gear5; ///< time integrator
    std::uint32_t threads = 0;                 ///< worker threads, 0 = all cores, [0, 256]
    /// Mass scaling s of every body, [1, 1e6]: inertia only, weights stay
    /// real (gravity acts as g/s on the scaled masses; docs/model.md).
    double density_scale = 1.0;
    /// Extra inertia M of the wire nodes on top of density_scale, [1, 1e6]:
    /// their masses are s·M times the model's, their weights stay real.
    /// Lifts the time step set by the wire's axial springs. The membrane's
    /// nodes are scaled by s only (docs/model.md, "Quasi-static scaling").
    double wire_mass_scale = 1.0;
    /// Cap on grains + wire nodes + membrane nodes (estimated), [1, 1e9].
    std::uint64_t max_bodies = 200000;
    friend bool operator==(const EngineSpec&, const EngineSpec&) = default;
};

/// A comment is a note, not a document: every copy of the job (the store,
/// job.json, the result file) carries it, and a study's its document.
inline constexpr std::size_t max_comment_chars = 10'000;

/// One job: a specimen prepared once and tested at every confining pressure.
struct JobSpec {
    std::string name = "job";                  ///< ≤ 200 characters, no control characters
    std::string comment;                       ///< free text, at most 10 000 characters
    std::uint64_t seed = 1;                    ///< seed of the pouring (the model spec §5)
    SpecimenSpec specimen;                     ///< what is prepared
    ContactSpec contact;                       ///< the contact law
    TriaxialSpec triaxial;                     ///< how it is tested
    /// The free-standing test. to_json writes it only when it differs from
    /// the default (no test), so that the job files and results of jobs
    /// without it stay as they were.
    FreeStandingSpec free_standing;
    EngineSpec engine;                         ///< numerical settings
    friend bool operator==(const JobSpec&, const JobSpec&) = default;
};

/// The free-standing test's escape distance in force [m]: the given one, or
/// 1.5 × the membrane's radius.
[[nodiscard]] inline double escape_distance_m(const JobSpec& spec)
{
    return spec.free_standing.escape_distance_m.value_or(1.5 * spec.specimen.membrane_radius_m);
}

/// One problem in a job document.
struct FieldError {
    /// JSON path of the field, e.g. `specimen.wire.helix_radius_m` or
    /// `triaxial.confining_pressures_pa[2]`; "" for the whole document.
    std::string path;
    /// What is wrong, with the offending value and the limit, e.g.
    /// `-5 is out of range (0, 1e+07]`. Shown to users as "path: message".
    std::string message;
    friend bool operator==(const FieldError&, const FieldError&) = default;
};

/// The version of the job document's format, written first by to_json as
/// `schema_version`. Version 1 is every document written before the field
/// existed (until 2026-12-06): a document without it is read as version 1.
/// A reader refuses a version above its own (a newer wiredem wrote it). Raise
/// it when a field's meaning changes so that a reader must tell old documents
/// from new; a new field whose default keeps the old behaviour needs no new
/// version.
inline constexpr std::uint64_t job_spec_schema_version = 2;

/// Parses and validates a job document. Reports every problem it finds
/// (unknown keys, wrong types, values out of range, then the cross-field
/// checks whose inputs are valid), each with its field path; never throws on
/// bad input.
[[nodiscard]] engine::Result<JobSpec, std::vector<FieldError>> parse_job_spec(const boost::json::value& doc);

/// Parses JSON text, then validates it as above. Malformed JSON gives one
/// FieldError with path "" and the parser's message with line and column.
/// Numbers are read correctly rounded, so the text round trip is exact too.
[[nodiscard]] engine::Result<JobSpec, std::vector<FieldError>> parse_job_spec(std::string_view text);

/// Parses a job as wiredem itself wrote it (to_json: every field present):
/// a job directory's job.json, a job the server stored. A field missing there
/// was written before the field existed, and is read as wiredem ran then:
/// triaxial.consolidation as cell_pressure (the default until 2026-12-03,
/// effective since). A job from a user keeps parse_job_spec's defaults.
/// It is read as trusted data: judged when it was accepted, it is not judged
/// again against today's rules (no range or cross-field check; a wrong type,
/// an unknown key or malformed JSON is still an error), so that tightening a
/// rule leaves every stored job readable. What the engine cannot run, it
/// refuses when the job runs (engine::preparation_error, settings_error).
[[nodiscard]] engine::Result<JobSpec, std::vector<FieldError>> parse_written_job_spec(std::string_view text);

/// Overload for string literals (a `const char*` converts to both
/// string_view and boost::json::value): parses it as JSON text.
[[nodiscard]] engine::Result<JobSpec, std::vector<FieldError>> parse_job_spec(const char* text);

/// The complete document for a spec: every field, defaults included (an
/// unset optional as null or "auto"). parse_job_spec(to_json(s)) == s.
[[nodiscard]] boost::json::value to_json(const JobSpec& spec);

/// The job spec as a JSON Schema (draft 2020-12), made by the reader itself
/// walking an empty spec: every field it takes, with its type, allowed range
/// or values and default (served at GET /v1/job-spec/schema). The checks
/// across fields are not in it.
[[nodiscard]] boost::json::object job_spec_json_schema();

/// JSON names of the engine's enums: the engine's own to_string (one table
/// per enum, engine/core/name_table.hpp).
using engine::to_string;
/// The JSON name of a cell.
[[nodiscard]] std::string_view to_string(CellKind c);
[[nodiscard]] std::string_view to_string(GrainPreset p);

} // namespace wiredem::api
