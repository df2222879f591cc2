// Sampling, the phase every column test shares (engine/triaxial/triaxial.hpp,
// engine/triaxial/free_standing.hpp): one row of measurements of the column
// between two steps, the time series of rows, snapshots of the whole system
// at chosen axial strains, and the verdict whether the loading was
// quasi-static.
//
// Conventions: forces on the plates and stresses are positive in compression;
// ε_a = (h₀ − h)/h₀ with h the distance between the plates and h₀ its value
// when loading starts; ε_v = (V₀ − V)/V₀ > 0 when the column contracts, with
// V = π r² h from the measured column radius r.
//
// Determinism: every sum is either a reduce_blocks over canonical order or a
// serial loop in id order, so results are bit-identical for any thread count.
#pragma once

#include "core/format.hpp"
#include "simulation.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace wiredem::engine {

/// Quasi-static thresholds (the model spec §4). A test is flagged as not
/// quasi-static when, during loading, the inertial number exceeds
/// `max_quasi_static_inertial_number` (I ≲ 10⁻³ is the usual quasi-static
/// regime, GDR MiDi 2004; above it the stress depends on the loading rate) or
/// the kinetic energy, averaged over the loading, exceeds
/// `max_quasi_static_energy_ratio` times the stored elastic energy (1 %: the
/// stored energy, not the motion, carries the load). The average, not the
/// largest sample: a slip event (q drops as a force chain buckles) turns
/// stored energy into motion at any plate speed, and a slower plate does not
/// make it smaller (measured on examples/main.json: the largest sample went
/// from 0.003 to 0.0105 when the plate slowed from 1 to 0.6 mm/s, at a drop
/// of q from 35.4 to 28.8 kPa; the mean stayed at 0.0015).
inline constexpr double max_quasi_static_inertial_number = 1e-3;
inline constexpr double max_quasi_static_energy_ratio = 1e-2;

/// The phase a sample was taken in.
enum class TriaxialPhase : std::uint8_t { ramp = 0, hold = 1, loading = 2 };

/// One row of measurements (see the file comment for signs and references).
struct TriaxialSample {
    double time_s = 0.0;                  ///< time since the test started [s]
    TriaxialPhase phase = TriaxialPhase::ramp;
    double axial_strain = 0.0;            ///< ε_a
    double height_m = 0.0;                ///< h, top plate z − bottom plate z [m]
    double top_plate_force_n = 0.0;       ///< vertical force the column exerts on the top plate [N]
    double bottom_plate_force_n = 0.0;    ///< same on the bottom plate [N]
    /// Mean radial distance of the grains touching the membrane + mean grain
    /// radius; without any grain–membrane contact, the radius of the smallest
    /// axis-centred cylinder that encloses the grains [m].
    double column_radius_m = 0.0;
    double confining_pressure_pa = 0.0;   ///< σ₃ applied on the membrane at this time [Pa]
    double sigma1_pa = 0.0;               ///< top plate force / (π r²) [Pa]
    double sigma3_effective_pa = 0.0;     ///< Σ grain– and wire–membrane |F_n| / (2π r h) [Pa]
    double deviatoric_stress_pa = 0.0;    ///< q = σ₁ − σ₃,eff [Pa]
    double stress_ratio = 0.0;            ///< (σ₁ − σ₃,eff)/(σ₁ + σ₃,eff)
    double volume_m3 = 0.0;               ///< π r² h [m³]
    double kinetic_energy_j = 0.0;        ///< translational + rotational, moving bodies [J]
    /// Hertz energy of the contacts that exert force (pairs, moving bodies on
    /// walls) + wire + membrane springs [J]
    double elastic_energy_j = 0.0;
    std::uint64_t contacts = 0;           ///< touching pairs + body–wall contacts
    std::uint64_t sliding_contacts = 0;   ///< of those, the ones not sticking
    std::uint64_t membrane_contacts = 0;  ///< touching grain– and wire–membrane pairs
    double wire_strain_mean = 0.0;        ///< mean segment strain (0 without wire)
    double wire_strain_max = 0.0;         ///< largest segment strain (0 without wire)
    /// I = ε̇ · 2 r_p · √(ρ_p/σ₃) with the applied σ₃; 0 while the plate is still.
    double inertial_number = 0.0;
};

/// The time series: one entry per sample in every vector, in time order.
struct TriaxialSeries {
    std::vector<double> time_s;
    std::vector<std::uint8_t> phase;               ///< TriaxialPhase values
    std::vector<double> axial_strain;
    std::vector<double> height_m;
    std::vector<double> top_plate_force_n;
    std::vector<double> bottom_plate_force_n;
    std::vector<double> column_radius_m;
    std::vector<double> confining_pressure_pa;     ///< applied σ₃
    std::vector<double> sigma1_pa;
    std::vector<double> sigma3_effective_pa;
    std::vector<double> deviatoric_stress_pa;
    std::vector<double> stress_ratio;
    /// ε_v relative to the volume at the start of loading (also for the
    /// samples before it, which then show the consolidation under σ₃).
    /// Derived from column_radius_m and height_m when the test ends
    /// (volumetric_strains); empty while it runs.
    std::vector<double> volumetric_strain;
    std::vector<double> kinetic_energy_j;
    std::vector<double> elastic_energy_j;
    std::vector<std::uint64_t> contacts;
    std::vector<std::uint64_t> sliding_contacts;
    std::vector<std::uint64_t> membrane_contacts;
    std::vector<double> wire_strain_mean;
    std::vector<double> wire_strain_max;
    std::vector<double> inertial_number;

    [[nodiscard]] std::size_t size() const { return time_s.size(); }
    /// Appends a row (every series but volumetric_strain).
    void push_back(const TriaxialSample& s);
};

/// ε_v = (V₀ − V)/V₀ of every row, V = π r² h from column_radius_m and height_m.
[[nodiscard]] std::vector<double> volumetric_strains(const TriaxialSeries& s, double initial_volume_m3);

/// Contacts of one instant: every touching body pair and every body–wall contact.
struct ForceNetwork {
    std::vector<BodyRef> first, second;   ///< body pairs, (kind, index), first < second
    std::vector<Vec3> force_n;            ///< force on `first` (−force on `second`) [N]
    std::vector<double> normal_force_n;   ///< |F_n| [N]
    std::vector<std::uint32_t> wall;      ///< body–wall contacts: wall index …
    std::vector<BodyRef> wall_body;       ///< … the body …
    std::vector<Vec3> wall_force_n;       ///< … and the wall's force on it [N]
};

/// The whole system at one instant.
struct TriaxialSnapshot {
    double requested_axial_strain = 0.0;  ///< the strain asked for
    double axial_strain = 0.0;            ///< the strain when taken (first step at or past it)
    double time_s = 0.0;                  ///< since the test started [s]
    std::vector<Vec3> grain_position_m;
    std::vector<double> grain_radius_m;
    std::vector<Vec3> grain_velocity_m_per_s;
    std::vector<Vec3> wire_node_position_m;
    std::vector<double> wire_segment_strain;
    std::vector<Vec3> membrane_node_position_m;
    std::vector<std::array<std::uint32_t, 3>> membrane_triangles; ///< node indices, (b−a)×(c−a) inwards
    ForceNetwork forces;
};

/// A segment of the wire that broke during a test (state/wire.hpp), and where
/// the test was then.
struct TestWireBreak {
    WireBreak event;                      ///< as the World recorded it (time_s: the World's clock)
    double test_time_s = 0.0;             ///< since the test started [s]
    double axial_strain = 0.0;            ///< ε_a of the test after that step
    double position_m = 0.0;              ///< along the wire, rest length to the segment's middle [m]
};

/// Appends to `recorded` the breaks `w` has recorded beyond the first
/// `breaks_before_test + recorded.size()` (those of the test's last step),
/// with the test's time and axial strain now. A test calls it after every step.
void record_wire_breaks(const World& w, std::size_t breaks_before_test, double test_time_s, double axial_strain,
    std::vector<TestWireBreak>& recorded);

/// What failed at a test's peak, for a wire that can break (issue 39; Brown et
/// al., PRL 2012: packings of chains do not yield until the chain breaks).
enum class PeakFailure : std::uint8_t {
    grains,          ///< the wire was whole at the peak: the grains gave way
    wire,            ///< a segment broke within a row of the peak: the wire gave way
    grains_after_break, ///< the wire had broken before: the grains gave way on a broken wire
};

/// The text of a PeakFailure: "grains", "wire", "grains_after_break".
[[nodiscard]] const char* to_string(PeakFailure f);

/// What failed at row `peak` of `series`: the first break of `breaks` after
/// the row before the peak and no later than the row after it (test time) is
/// the wire's failure; a break before that, a broken wire's; none up to the row
/// after the peak, the grains'.
[[nodiscard]] PeakFailure peak_failure(const TriaxialSeries& series, std::size_t peak, const std::vector<TestWireBreak>& breaks);

/// Whether the loading was slow enough to be called quasi-static.
struct QuasiStaticVerdict {
    bool quasi_static = true;
    double max_inertial_number = 0.0;     ///< over the loading samples
    double mean_kinetic_to_elastic = 0.0; ///< mean KE / elastic energy over the loading samples (the criterion)
    double max_kinetic_to_elastic = 0.0;  ///< its largest sample (slip events; not a criterion)
    std::string warning;                  ///< empty when quasi-static; otherwise what was exceeded
};

/// The quasi-static verdict over the rows from `loading_start` on (rows
/// evenly spaced in time): the largest inertial number, and the mean and
/// largest kinetic/elastic energy ratio (a row without elastic energy counts
/// as ∞). Flags the test when I or the mean ratio is above its threshold.
[[nodiscard]] QuasiStaticVerdict quasi_static_verdict(const TriaxialSeries& s, std::size_t loading_start);

/// Takes one row of measurements of `w` as it is after its last step (the
/// contact and wall forces of that step). time_s, phase, confining_pressure_pa
/// and inertial_number are left for the caller. Reads only; deterministic.
/// @param top_plate_wall    index of the top plate (a plane whose normal points down)
/// @param bottom_plate_wall index of the bottom plate (a plane whose normal points up)
/// @param initial_height_m  h₀ for ε_a [m], > 0
[[nodiscard]] TriaxialSample measure_triaxial_sample(const World& w, ThreadPool& pool, std::size_t top_plate_wall,
    std::size_t bottom_plate_wall, double initial_height_m);

/// The part of a row every cell measures the same way: kinetic and elastic
/// energy, touching and sliding contacts, the wire's segment strain. Reads
/// only; deterministic.
void measure_energies_and_contacts(const World& w, ThreadPool& pool, TriaxialSample& s);

/// Copies the system into a snapshot (forces of the last step).
[[nodiscard]] TriaxialSnapshot take_triaxial_snapshot(const World& w);

/// Force the column exerts on plate `wall` along the plate's inward normal,
/// > 0 in compression (the wall's load is the force the bodies exert on it) [N].
[[nodiscard]] double plate_compression_n(const World& w, std::size_t wall);

/// The axial strains at which a test takes snapshots: `requested` clamped to
/// [0, target], with 0 (loading start) and the target, sorted, each once.
[[nodiscard]] std::vector<double> snapshot_plan(double target_axial_strain, const std::vector<double>& requested);

/// Takes the snapshots of `plan` from `next` on that the axial strain
/// `axial_strain` has reached (taken at time `time_s` of the test), each
/// labelled with the strain it was asked for; advances `next` past them.
void take_due_snapshots(const World& w, const std::vector<double>& plan, std::size_t& next, double axial_strain,
    double time_s, std::vector<TriaxialSnapshot>& out);

/// Steps between two rows of a record sampled every `sample_interval_s` at
/// the time step `dt_s`: the interval rounded to whole steps, at least one.
[[nodiscard]] std::uint64_t steps_per_sample(double sample_interval_s, double dt_s);

/// The warning a record carries when its sample interval is shorter than
/// half a step, so that it samples every step instead (job validation
/// refuses an interval below the step it estimates; the run's own step can
/// differ from that estimate); empty otherwise.
[[nodiscard]] std::optional<std::string> sample_interval_warning(double sample_interval_s, double dt_s);


} // namespace wiredem::engine
