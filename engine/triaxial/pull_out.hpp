// Pulling the wire out (issue 39: the printed columns were taken apart by
// pulling their string out). One end node of the wire is driven
// kinematically at a constant velocity v d̂ (d̂ a unit direction, upward along
// the axis by default); the rest of the wire, the grains and the plates
// follow the model's laws. What it takes:
//
//   pull force  the force the drive exerts on the driven node along d̂. The
//               node moves at a constant velocity, so the drive balances
//               everything else on it: F = −F_node · d̂, F_node the force the
//               step gathered on the node (its segment and joint, its
//               contacts, its weight; a kinematic node's forces are still
//               gathered, Caches::body_force_n);
//   end tension the tension of the segment at the driven node,
//               k_elo (|Δx| − l_w) + its dashpot, the second way to measure
//               the same pull: F = T (û · d̂) − (contacts + weight + joint) · d̂,
//               so the two differ by what touches the driven node itself.
//
// The free-standing test runs it as its last phase instead of the
// unconfined compression (free_standing.hpp); the functions here are the
// phase's measurements and are usable on any World with a wire (the
// physics tests pull a wire lying on a plate). docs/model.md, "Pulling the
// wire out", derives the checks. Deterministic: serial reads of the step's
// outputs.
#pragma once

#include "state/world.hpp"
#include "triaxial/triaxial.hpp"
#include "triaxial/wire_end.hpp"

#include <cstdint>
#include <optional>
#include <vector>

namespace wiredem::engine {


/// How the wire is pulled out. All SI.
struct PullOutSettings {
    WireEnd end = WireEnd::last;                ///< the end pulled
    Vec3 direction = Vec3(0.0, 0.0, 1.0);       ///< d̂, normalised by the driver; |d| > 0
    double speed_m_per_s = 0.01;                ///< v [m/s], > 0
    /// The drive's speed rises over this time as v ½(1 − cos(π t/T)) [s],
    /// ≥ 0 (0: v from the first step). A wire set moving at v in one step
    /// takes the impulse of its axial wave, of order √(k_elo m_w) v, which
    /// for a mass-scaled wire dwarfs what the grains hold it with.
    double ramp_time_s = 0.01;
    /// Stop after this pulled length [m], > 0; nullopt: when the pulled
    /// piece of wire has left the column (no segment of it in the column).
    std::optional<double> length_m;
    /// Stop at this time at the latest [s], > 0 (a warning says so when the
    /// length or the wire's exit was not reached): no pull runs for ever.
    double max_time_s = 1.0;
};

/// The rules the settings obey on their own (fields as named above:
/// "end", "direction", "speed_m_per_s", "length_m", "max_time_s").
[[nodiscard]] std::optional<SettingsError> pull_out_settings_error(const PullOutSettings& s);

/// The node pulled at `end` of the chain (the wire must have nodes).
[[nodiscard]] std::uint32_t pulled_node(const World& w, WireEnd end);

/// The neighbour of the pulled node along the chain (the other node of the
/// end segment); the wire must have at least two nodes.
[[nodiscard]] std::uint32_t end_segment_other_node(const World& w, WireEnd end);

/// The drive's speed at time `t_s` after the pull began: v ½(1 − cos(π t/T))
/// during the ramp, then v [m/s].
[[nodiscard]] double pull_speed_m_per_s(const PullOutSettings& s, double t_s) noexcept;

/// Makes the pulled node kinematic at pull_speed_m_per_s(s, `t_s`) d̂ (d̂ =
/// direction normalised); called before every step of the pull with the
/// time at the step's end (a kinematic node keeps the velocity it was given).
void drive_pulled_node(World& w, const PullOutSettings& s, double t_s);

/// The pull as the last step left it.
struct PullForces {
    double pull_force_n = 0.0;   ///< the drive's force on the pulled node along d̂ [N]
    /// Tension of the end segment (its spring and dashpot along it; 0 when
    /// it is removed) [N], > 0 stretched.
    double end_tension_n = 0.0;
    /// The end segment's tension projected on d̂, T (û · d̂), û the unit
    /// vector from the pulled node to its neighbour reversed (along the pull) [N].
    double end_tension_along_n = 0.0;
};

/// Reads the pull from the last step's forces (`unit_direction` normalised).
[[nodiscard]] PullForces pull_forces(const World& w, WireEnd end, const Vec3& unit_direction);

/// A region of the column: the bodies within `escape_distance_m` of the axis
/// and at most `top_m` above the bottom plate at `bottom_m`.
struct ColumnRegion {
    double bottom_m = 0.0;
    double top_m = 0.0;
    double escape_distance_m = 0.0;
    [[nodiscard]] bool contains(const Vec3& x) const noexcept;
};

/// Rest length of the wire's whole segments with both nodes in `region` [m];
/// with `only_piece_of` a node, only the segments of that node's piece.
[[nodiscard]] double wire_in_region_m(const World& w, const ColumnRegion& region,
    std::optional<std::uint32_t> only_piece_of = std::nullopt);

/// The rows of a pull-out, one per row of the test's series in its pull-out
/// phase (the same times).
struct PullOutSeries {
    std::vector<double> time_s;            ///< [s]
    std::vector<double> pulled_length_m;   ///< the driven node's displacement along d̂ [m]
    /// PullForces::pull_force_n averaged over the steps since the row
    /// before (the steps of the sample interval) [N]
    std::vector<double> pull_force_n;
    std::vector<double> end_tension_n;     ///< PullForces::end_tension_along_n averaged alike [N]
    std::vector<double> wire_in_column_m;  ///< wire_in_region_m of the whole wire [m]
    std::vector<double> grains_in_column;  ///< grains within the escape distance
    [[nodiscard]] std::size_t size() const { return time_s.size(); }
};

/// Why the pull-out ended.
enum class PullOutEnd : std::uint8_t {
    length = 0,   ///< the pulled length was reached
    wire_out = 1, ///< the pulled piece has left the column
    time = 2,     ///< max_time_s
    host = 3,     ///< stopped by the host (RunControl::stop_loading)
};

/// "length", "wire_out", "time", "host".
[[nodiscard]] const char* to_string(PullOutEnd e) noexcept;

/// What the pull-out measured.
struct PullOutReading {
    std::uint32_t pulled_node = 0;         ///< the driven node
    /// The largest pull force of a row (averaged over its sample interval:
    /// a single step's force rattles with the contacts) [N]
    double peak_pull_force_n = 0.0;
    double pulled_length_at_peak_m = 0.0;  ///< the pulled length at that row [m]
    double pulled_length_m = 0.0;          ///< at the end [m]
    double wire_in_column_before_m = 0.0;  ///< wire in the column when the pull began [m]
    double wire_in_column_m = 0.0;         ///< at the end [m]
    std::size_t grains_in_column = 0;      ///< at the end
    bool wire_broke = false;               ///< a segment broke during the pull
    /// The force it takes to accelerate the whole wire (its masses as the
    /// World has them: mass scaling included) at the ramp's largest
    /// acceleration v π/(2T), M_w v π/(2T) [N] (∞ without a ramp): a peak
    /// during the ramp and of this order is the wire's inertia, not the
    /// grains' hold (a warning says so).
    double ramp_inertia_n = 0.0;
    PullOutEnd end = PullOutEnd::time;
    PullOutSeries series;
};

} // namespace wiredem::engine
