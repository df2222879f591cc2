// How densely a prepared column is filled, away from its walls (docs/model.md,
// "What a sound specimen is"). Reads only; deterministic; no threads.
#pragma once

#include "specimen/grain_sizes.hpp"
#include "state/clump_shape.hpp"
#include "state/world.hpp"

#include <optional>

namespace wiredem::engine {

/// Volume fractions of the core of a column: the cylinder `margin_m` inside
/// `inner_radius_m` around the z axis, between `margin_m` above `bottom_z_m`
/// and `margin_m` below `top_z_m`. The layers next to the membrane and the
/// plates are ordered by the walls and looser; inside, a poured random packing
/// fills 0.55–0.64 (random loose to random close packing).
struct CoreFractions {
    double grain = 0.0;       ///< space inside grains, sampled on a grid
    double wire = 0.0;        ///< wire as cylinders of radius r_w along its segments, over the core's volume
    double volume_m3 = 0.0;   ///< π r_c² h_c of the core
};

/// The grains' fraction samples the core on a cubic grid of spacing
/// `grid_m` (each point inside some grain or not: exact to the grid's
/// resolution, ~1 % at 0.1 r_p); the wire's counts the segments whose
/// midpoints lie in the core, each π r_w² times its length (a cylinder: the
/// node spheres alone would miss half the wire's volume between them).
/// Zero fractions for an empty core.
/// The grains of a World as grains, not spheres: each free sphere, and each
/// clump as one grain. Free spheres first, in id order, then the clumps in
/// clump order.
struct GrainVolumes {
    /// A sphere's radius, or a clump's volume-equivalent radius (3V/4π)^{1/3} [m]
    std::vector<double> radius_m;
    /// A sphere's (4/3) π r³; a clump's volume, that of the union of its
    /// spheres (union_mass_properties: add_clump gives it the mass ρ V, so V
    /// is its mass over its density), not the sum of its overlapping spheres' [m³]
    std::vector<double> volume_m3;
    double total_volume_m3 = 0.0;  ///< Σ volume_m3, in that order [m³]
};

/// The grains of `w` (grain_body_count of them) and their volumes.
[[nodiscard]] GrainVolumes grain_volumes(const World& w);

/// The mean of grain_volumes' radii: a sphere's radius, a clump's
/// volume-equivalent one, each grain once (the grain size of the tests'
/// inertial number) [m]; 0 without grains.
[[nodiscard]] double mean_grain_radius_m(const World& w);

[[nodiscard]] CoreFractions core_volume_fractions(const World& w, double inner_radius_m, double bottom_z_m,
    double top_z_m, double margin_m, double grid_m);

/// The same for the rigid-wall cell's box [lo, hi]: the box `margin_m`
/// inside all six walls, its grains sampled on the same grid (no wire).
[[nodiscard]] CoreFractions box_core_volume_fractions(const World& w, const Vec3& lo_m, const Vec3& hi_m,
    double margin_m, double grid_m);

/// How both cells measure their core: `margin_m`, a diameter of the largest
/// grain inside every wall, and `grid_m`, the sampling grid: 0.1 r_p, or with
/// a grain-size curve 0.05 D50 (by mass).
struct CoreSampling {
    double margin_m = 0.0;
    double grid_m = 0.0;
};
[[nodiscard]] CoreSampling core_sampling(double largest_grain_radius_m, double grain_radius_m,
    const std::optional<SieveCurve>& grain_sizes);

/// The largest grain's reach from its centre: the largest radius the
/// grains are drawn with (r_p (1 + spread), or the curve's largest D/2),
/// times a clump's bounding radius (≥ its volume-equivalent radius, 1).
[[nodiscard]] double largest_grain_radius_m(double grain_radius_m, double grain_radius_spread,
    const std::optional<SieveCurve>& grain_sizes, const std::optional<ClumpBody>& grain_shape);

} // namespace wiredem::engine
