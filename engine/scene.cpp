#include "scene.hpp"

#include <cmath>

namespace wiredem::engine {

double build_container(World& w, const ContainerSpec& spec)
{
    const std::uint8_t grain_mat = add_material(w, spec.grain);
    const std::uint8_t wall_mat = add_material(w, spec.wall);
    add_wall(w, make_plate(0.0, +1.0, wall_mat));
    add_wall(w, make_cylinder(spec.container_radius_m, wall_mat));

    SplitMix64 rng(spec.seed);
    const std::optional<ClumpBody> clump
        = spec.clump ? std::optional<ClumpBody>(scaled_clump(*spec.clump, spec.grain_radius_m)) : std::nullopt;
    const double r = clump ? clump->bounding_radius_m() : spec.grain_radius_m;
    const double pitch = 2.0 * r * (1.0 + spec.lattice_gap);
    const double gap = pitch - 2.0 * r;
    const double reach = spec.container_radius_m - r - 0.5 * gap; // centre must stay inside
    const int half = static_cast<int>(std::floor(reach / pitch));
    double top = 0.0;
    std::size_t placed = 0;
    for (int layer = 0; placed < spec.grains; ++layer) {
        const double z = r + 0.5 * gap + layer * pitch;
        for (int iy = -half; iy <= half && placed < spec.grains; ++iy)
            for (int ix = -half; ix <= half && placed < spec.grains; ++ix) {
                const double x = ix * pitch, y = iy * pitch;
                if (std::hypot(x, y) > reach) continue;
                // Drawn z, y, x, one statement each: C++ leaves the order in
                // which a call's arguments are evaluated open (GCC went right
                // to left, clang left to right: the same seed gave two
                // scenes). z first is GCC's order, the scenes' so far.
                const double jz = rng.uniform() - 0.5;
                const double jy = rng.uniform() - 0.5;
                const double jx = rng.uniform() - 0.5;
                const Vec3 jitter(jx, jy, jz);
                if (clump) {
                    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
                    add_clump(w, *clump, Vec3(x, y, z) + spec.jitter * gap * jitter, uniform_orientation(u1, u2, u3), grain_mat);
                } else {
                    add_grain(w, Vec3(x, y, z) + spec.jitter * gap * jitter, r, grain_mat);
                }
                ++placed;
                top = z;
            }
    }
    return top;
}

CuboidWalls build_fcc_array(World& w, const FccArraySpec& spec)
{
    const std::uint8_t grain_mat = add_material(w, spec.grain);
    const std::uint8_t wall_mat = add_material(w, spec.wall);
    const double r = spec.grain_radius_m;
    const double half_a = std::sqrt(2.0) * r; // a/2: (1, 1, 0) a/2 is 2r long
    for (int k = 0; k <= 2 * spec.cells[2]; ++k)
        for (int j = 0; j <= 2 * spec.cells[1]; ++j)
            for (int i = 0; i <= 2 * spec.cells[0]; ++i)
                if ((i + j + k) % 2 == 0) add_grain(w, Vec3(i, j, k) * half_a, r, grain_mat);
    const Vec3 hi(2 * spec.cells[0] * half_a + r, 2 * spec.cells[1] * half_a + r, 2 * spec.cells[2] * half_a + r);
    return add_cuboid_walls(w, Vec3::Constant(-r), hi, wall_mat, spec.wall_friction_coeff);
}

} // namespace wiredem::engine

