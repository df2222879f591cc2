#include "specimen/packing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace wiredem::engine {

GrainVolumes grain_volumes(const World& w)
{
    GrainVolumes out;
    const TranslationalState& g = w.of(BodyKind::grain);
    const ClumpState& c = w.clumps;
    for (std::size_t i = 0; i < g.size(); ++i) {
        if (c.is_member(i)) continue;
        const double r = g.radius_m[i];
        out.radius_m.push_back(r);
        out.volume_m3.push_back(4.0 / 3.0 * std::numbers::pi * r * r * r);
    }
    for (std::size_t k = 0; k < c.size(); ++k) {
        const double density = w.materials[g.material[c.first_member[k]]].density_kg_per_m3;
        out.radius_m.push_back(std::cbrt(3.0 * c.mass_kg[k] / (4.0 * std::numbers::pi * density)));
        out.volume_m3.push_back(c.mass_kg[k] / density);
    }
    for (const double v : out.volume_m3) out.total_volume_m3 += v;
    return out;
}

double mean_grain_radius_m(const World& w)
{
    const std::vector<double> radii = grain_volumes(w).radius_m;
    double sum_m = 0.0;
    for (const double r : radii) sum_m += r;
    return radii.empty() ? 0.0 : sum_m / static_cast<double>(radii.size());
}

namespace {

/// The share of the grid points of the box [lo, hi] (spacing h, points at
/// lo + (i + ½) h, i < ⌊(hi − lo)/h⌋ + 1 per axis) that lie inside some
/// grain sphere, among those for which `counts(point)` holds.
template <class Counts>
double grain_share_on_grid(const World& w, const Vec3& lo, const Vec3& hi, double h, Counts counts)
{
    std::array<int, 3> n{};
    for (int a = 0; a < 3; ++a) n[a] = static_cast<int>((hi[a] - lo[a]) / h) + 1;
    auto coord = [&](int i, int a) { return lo[a] + (i + 0.5) * h; };
    const auto cell = [&](int ix, int iy, int iz) {
        return (static_cast<std::size_t>(iz) * n[1] + iy) * n[0] + ix;
    };
    std::vector<std::uint8_t> filled(static_cast<std::size_t>(n[0]) * n[1] * n[2], 0);
    const TranslationalState& g = w.of(BodyKind::grain);
    for (std::size_t i = 0; i < g.size(); ++i) { // each grain marks the grid points inside it
        const Vec3& c = g.x[0][i];
        const double r = g.radius_m[i];
        auto range = [&](int a) {
            return std::pair(std::max(0, static_cast<int>(std::floor((c[a] - r - lo[a]) / h))),
                std::min(n[a] - 1, static_cast<int>(std::ceil((c[a] + r - lo[a]) / h))));
        };
        const auto [ix0, ix1] = range(0);
        const auto [iy0, iy1] = range(1);
        const auto [iz0, iz1] = range(2);
        for (int iz = iz0; iz <= iz1; ++iz)
            for (int iy = iy0; iy <= iy1; ++iy)
                for (int ix = ix0; ix <= ix1; ++ix)
                    if ((Vec3(coord(ix, 0), coord(iy, 1), coord(iz, 2)) - c).squaredNorm() < r * r)
                        filled[cell(ix, iy, iz)] = 1;
    }
    std::size_t inside = 0, total = 0;
    for (int iz = 0; iz < n[2]; ++iz)
        for (int iy = 0; iy < n[1]; ++iy)
            for (int ix = 0; ix < n[0]; ++ix) {
                if (!counts(Vec3(coord(ix, 0), coord(iy, 1), coord(iz, 2)))) continue;
                ++total;
                inside += filled[cell(ix, iy, iz)];
            }
    return total ? static_cast<double>(inside) / static_cast<double>(total) : 0.0;
}

} // namespace

CoreFractions core_volume_fractions(const World& w, double inner_radius_m, double bottom_z_m, double top_z_m,
    double margin_m, double grid_m)
{
    CoreFractions out;
    const double rc = inner_radius_m - margin_m, z0 = bottom_z_m + margin_m, z1 = top_z_m - margin_m;
    if (!(rc > 0.0 && z1 > z0 && grid_m > 0.0)) return out;
    out.volume_m3 = std::numbers::pi * rc * rc * (z1 - z0);
    out.grain = grain_share_on_grid(w, Vec3(-rc, -rc, z0), Vec3(rc, rc, z1), grid_m,
        [&](const Vec3& p) { return std::hypot(p.x(), p.y()) < rc && p.z() < z1; });

    const std::vector<Vec3>& x = w.of(BodyKind::wire).x[0];
    double wire_m3 = 0.0;
    for (std::size_t s = 0; s + 1 < x.size(); ++s) {
        const Vec3 mid = 0.5 * (x[s] + x[s + 1]);
        if (std::hypot(mid.x(), mid.y()) >= rc || mid.z() <= z0 || mid.z() >= z1) continue;
        wire_m3 += std::numbers::pi * w.wire.radius_m * w.wire.radius_m * (x[s + 1] - x[s]).norm();
    }
    out.wire = wire_m3 / out.volume_m3;
    return out;
}

CoreFractions box_core_volume_fractions(const World& w, const Vec3& lo_m, const Vec3& hi_m, double margin_m,
    double grid_m)
{
    CoreFractions out;
    const Vec3 lo = lo_m.array() + margin_m, hi = hi_m.array() - margin_m;
    if (!((hi - lo).minCoeff() > 0.0 && grid_m > 0.0)) return out;
    out.volume_m3 = (hi - lo).prod();
    out.grain = grain_share_on_grid(w, lo, hi, grid_m,
        [&](const Vec3& p) { return p.x() < hi.x() && p.y() < hi.y() && p.z() < hi.z(); });
    return out;
}

CoreSampling core_sampling(double largest_grain_radius_m, double grain_radius_m, const std::optional<SieveCurve>& grain_sizes)
{
    return {2.0 * largest_grain_radius_m,
        grain_sizes ? 0.05 * GrainSizeDistribution(*grain_sizes).diameter_at_mass_fraction(0.5) : 0.1 * grain_radius_m};
}

double largest_grain_radius_m(double grain_radius_m, double grain_radius_spread,
    const std::optional<SieveCurve>& grain_sizes, const std::optional<ClumpBody>& grain_shape)
{
    // A clump reaches its bounding radius from its centre (≥ its volume-equivalent radius).
    const double extent = grain_shape ? grain_shape->bounding_radius_m() : 1.0;
    if (grain_sizes) return extent * (0.5 * grain_sizes->diameters_m.back());
    return extent * (grain_radius_m * (1.0 + grain_radius_spread));
}

} // namespace wiredem::engine
