// Ready-made scenes shared by the demo, the benchmark and the tests: grains
// on a loose lattice inside a cylindrical container on a floor. (Pouring with
// a wire nozzle is the specimen preparation's job; this is the plain box.)
#pragma once

#include "state/world.hpp"
#include "triaxial/cuboid.hpp"

#include <array>
#include <cstdint>
#include <optional>

namespace wiredem::engine {

/// Deterministic 64-bit generator (splitmix64) with a portable uniform [0, 1):
/// the same seed gives the same numbers on every platform and library.
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : s_(seed) {}
    std::uint64_t next()
    {
        std::uint64_t z = (s_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1) with 53 random bits.
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
    /// The whole state: SplitMix64(state()) continues the same sequence.
    [[nodiscard]] std::uint64_t state() const { return s_; }

private:
    std::uint64_t s_;
};

/// A cylindrical container filled with grains.
struct ContainerSpec {
    double container_radius_m = 20e-3;
    double grain_radius_m = 1.23e-3;
    std::size_t grains = 8000;
    double lattice_gap = 0.1;       ///< gap between lattice neighbours, fraction of the diameter
    double jitter = 0.2;            ///< random offset, fraction of the gap
    std::uint64_t seed = 1;
    Material grain{};               ///< default: the paper's grains
    Material wall{1e9, 0.3, 7800.0}; ///< plates and cylinder (E_b)
    /// When set, each lattice site holds a clump of this shape (at a
    /// volume-equivalent radius of 1 m, scaled by grain_radius_m), turned to
    /// a random orientation, instead of a sphere; the lattice's pitch then
    /// follows the clump's bounding radius.
    std::optional<ClumpBody> clump;
};

/// Adds a floor at z = 0, the cylinder wall and `spec.grains` grains on a
/// simple cubic lattice (with jitter) inside it, at rest. Returns the height
/// of the top layer's centres [m].
double build_container(World& w, const ContainerSpec& spec);

/// A face-centred cubic array of equal spheres in a cuboid cell (Thornton,
/// Géotechnique 29, 1979): the cube axes along x, y, z, lattice constant
/// a = 2√2 r (nearest neighbours 2r apart, along the ⟨110⟩ directions).
struct FccArraySpec {
    std::array<int, 3> cells{2, 2, 2};  ///< unit cells along x, y, z, ≥ 1
    double grain_radius_m = 1.23e-3;
    Material grain{};
    Material wall{1e9, 0.3, 7800.0};
    /// The walls' friction coefficient (0: frictionless; nullopt: the contact law's).
    std::optional<double> wall_friction_coeff = 0.0;
};

/// Adds the spheres at (i, j, k) a/2 for 0 ≤ i ≤ 2 n_x, … with i + j + k
/// even, at rest, and the six walls of the cuboid cell touching the outer
/// spheres (add_cuboid_walls: the box [−r, n a + r] along each axis).
/// Returns the walls.
CuboidWalls build_fcc_array(World& w, const FccArraySpec& spec);

} // namespace wiredem::engine
