// Wire-deployment patterns (the model spec §5): the nozzle's horizontal
// trajectory, parametrised by path length so that the nozzle can move at the
// constant path speed ω R_a whatever the pattern. Besides the four built-in
// patterns, a toolpath: the robot's own path, a polyline per layer (issue 39).
#pragma once

#include "core/types.hpp"
#include "specimen/pattern_kind.hpp"
#include "specimen/pattern_params.hpp"

#include <string>
#include <vector>
#include <string_view>

namespace wiredem::engine {

/// Parses "none", "helix", "spiral_helix", "radial_helix", "toolpath".
[[nodiscard]] bool parse_pattern_kind(std::string_view name, PatternKind& out);
[[nodiscard]] std::string_view pattern_name(PatternKind kind);

/// The pattern's parameters: those a job gives as they are (PatternParams,
/// pattern_params.hpp; defaults fit a 20 mm-radius membrane), then a
/// toolpath's polyline.
struct PatternSpec : PatternParams {
    /// toolpath: one layer of the nozzle's path, a polyline of points (x, y)
    /// in the column's frame (z is ignored) [m], at least two of them apart.
    /// The nozzle walks it from the first point to the last, then straight on
    /// to the first point of the next layer, which is the same polyline
    /// turned about the axis by toolpath_rotation_per_layer_rad (layer k:
    /// turned by k times it). Every layer has the same length.
    std::vector<Vec3> toolpath_m;
    double toolpath_rotation_per_layer_rad = 0.0; ///< toolpath: the turn from one layer to the next [rad]
};

/// Largest distance of the pattern from the axis [m]: R_a, R_a + R_i for the
/// spiral helix, the farthest point of a toolpath (its legs and the turns of
/// its layers stay within that radius). The preparation and the job's checks
/// keep it r_w + clearance inside the membrane.
[[nodiscard]] double pattern_reach_m(const PatternSpec& p);

/// Horizontal nozzle trajectory, walked by path length.
class NozzlePath {
public:
    /// @param hairpin_gap_m  lateral distance between the in and out legs of a
    ///        radial excursion (they must not overlap: ≥ 2 r_w).
    NozzlePath(const PatternSpec& spec, double hairpin_gap_m);

    /// Position (x, y, 0) after `s` metres along the path.
    [[nodiscard]] Vec3 at(double s_m) const;
    /// The angle Θ travelled around the large circle after `s` metres
    /// (helix and spiral helix; the spiral's small circle is at ψ = 2πΘ/φ_rs).
    [[nodiscard]] double large_angle(double s_m) const
    {
        return spec_.pattern == PatternKind::spiral_helix ? spiral_angle(s_m) : s_m / spec_.helix_radius_m;
    }
    /// The path length of one layer of a toolpath [m] (0 for the other patterns).
    [[nodiscard]] double layer_length_m() const { return layer_m_; }
    /// Constant path speed ω R_a [m/s].
    [[nodiscard]] double speed_m_per_s() const { return spec_.angular_speed_rad_per_s * spec_.helix_radius_m; }

    /// Where the spiral's integration has reached (spiral_angle goes on from
    /// there): Θ(s) depends, in its last bits, on the queries before, so a
    /// path that is to give the same positions after a restart must be given
    /// this back (a preparation keeps it in its state).
    struct Integration {
        double s_m = 0.0;
        double theta_rad = 0.0;
    };
    [[nodiscard]] Integration integration() const { return {cached_s_, cached_theta_}; }
    void continue_from(const Integration& i) { cached_s_ = i.s_m, cached_theta_ = i.theta_rad; }

    /// Geometry of a radial excursion (radial_helix).
    struct Hairpin {
        double r_min_m = 0.0;   ///< closest approach to the axis
        double in_m = 0.0, out_m = 0.0; ///< leg lengths
        double beta_rad = 0.0;  ///< where the out leg meets the circle, behind the excursion
        double period_m = 0.0;  ///< path length of one period
    };
    [[nodiscard]] Hairpin hairpin() const;

private:
    /// Spiral helix: the large angle Θ reached after path length s, by
    /// integrating dΘ/ds = 1/|dP/dΘ| (RK4), cached for monotone queries.
    [[nodiscard]] double spiral_angle(double s_m) const;
    [[nodiscard]] Vec3 spiral_point(double theta) const;
    [[nodiscard]] double spiral_speed(double theta) const; ///< |dP/dΘ|

    /// toolpath: where each leg of a layer starts along it, and its length [m].
    [[nodiscard]] Vec3 toolpath_at(double s_m) const;
    std::vector<double> leg_start_m_, leg_m_;
    double layer_m_ = 0.0;

    PatternSpec spec_;
    double hairpin_gap_m_;
    mutable double cached_s_ = 0.0, cached_theta_ = 0.0;
};

} // namespace wiredem::engine
