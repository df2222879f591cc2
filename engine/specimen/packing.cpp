#include "specimen/packing.hpp"

#include <algorithm>
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

CoreFractions core_volume_fractions(const World& w, double inner_radius_m, double bottom_z_m, double top_z_m,
    double margin_m, double grid_m)
{
    CoreFractions out;
    const double rc = inner_radius_m - margin_m, z0 = bottom_z_m + margin_m, z1 = top_z_m - margin_m;
    if (!(rc > 0.0 && z1 > z0 && grid_m > 0.0)) return out;
    out.volume_m3 = std::numbers::pi * rc * rc * (z1 - z0);
    const double h = grid_m;
    const int nxy = static_cast<int>(2.0 * rc / h) + 1, nz = static_cast<int>((z1 - z0) / h) + 1;
    auto coord = [&](int i, double lo) { return lo + (i + 0.5) * h; };
    std::vector<std::uint8_t> filled(static_cast<std::size_t>(nxy) * nxy * nz, 0);
    const TranslationalState& g = w.of(BodyKind::grain);
    for (std::size_t i = 0; i < g.size(); ++i) { // each grain marks the grid points inside it
        const Vec3& c = g.x[0][i];
        const double r = g.radius_m[i];
        auto range = [&](double centre, double lo, int n) {
            return std::pair(std::max(0, static_cast<int>(std::floor((centre - r - lo) / h))),
                std::min(n - 1, static_cast<int>(std::ceil((centre + r - lo) / h))));
        };
        const auto [ix0, ix1] = range(c.x(), -rc, nxy);
        const auto [iy0, iy1] = range(c.y(), -rc, nxy);
        const auto [iz0, iz1] = range(c.z(), z0, nz);
        for (int iz = iz0; iz <= iz1; ++iz)
            for (int iy = iy0; iy <= iy1; ++iy)
                for (int ix = ix0; ix <= ix1; ++ix)
                    if ((Vec3(coord(ix, -rc), coord(iy, -rc), coord(iz, z0)) - c).squaredNorm() < r * r)
                        filled[(static_cast<std::size_t>(iz) * nxy + iy) * nxy + ix] = 1;
    }
    std::size_t inside = 0, total = 0;
    for (int iz = 0; iz < nz; ++iz)
        for (int iy = 0; iy < nxy; ++iy)
            for (int ix = 0; ix < nxy; ++ix) {
                if (std::hypot(coord(ix, -rc), coord(iy, -rc)) >= rc || coord(iz, z0) >= z1) continue;
                ++total;
                inside += filled[(static_cast<std::size_t>(iz) * nxy + iy) * nxy + ix];
            }
    out.grain = total ? static_cast<double>(inside) / static_cast<double>(total) : 0.0;

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

} // namespace wiredem::engine
