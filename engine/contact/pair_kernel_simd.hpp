// Explicit SIMD paths, chosen at run time: the body pairs and the body–wall
// contacts of the contact list eight per AVX-512 instruction (here; one law,
// two geometries, as in the scalar pipeline), and the grains' turn
// (integrate/rotation_simd.cpp). The pair kernel takes any eight consecutive
// pairs, of any kinds (grains, wire nodes, membrane nodes: the same
// sphere–sphere law), and of those the lanes that are apart or overlapping
// with a certain branch of the tangential law (sticking, sliding on,
// re-sticking, breaking); the other lanes (a NaN, a boundary case) go to the
// scalar kernel of compute_contact_forces (engine/step.cpp).
//
// Same bits as the scalar path. Each lane performs the scalar code's
// operations (contact/geometry.hpp, laws/hertz.hpp, laws/tangential.hpp) in
// the same order, on the same inputs (a body that does not turn has the
// scalar path's zero spin): IEEE additions, multiplications, divisions and
// square roots are correctly rounded whatever the vector width, and the files
// are compiled with -ffp-contract=off so that no multiply–add is fused (the
// baseline x86-64 build has no FMA, so the scalar path never fuses either). A
// lane is taken only when the vector path is sure of its branch (ordered
// comparisons). So states are the same with and without these paths, and the
// same for any thread count (Determinism.SimdAndScalarKernelsGiveTheSameBits).
#pragma once

#include "contact/contact_list.hpp"
#include "laws/tangential.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace wiredem::engine {

struct Wall;
struct World;

/// Lanes of one call of the SIMD pair kernel.
inline constexpr std::size_t simd_pair_lanes = 8;

/// What the contact kernels (compute_contact_forces' scalar one and these)
/// read besides the contact list: per body kind the positions x₀, scaled
/// velocities x₁ = δt v and radii; the grains' scaled spins δt ω (the other
/// kinds do not turn); and the contact law.
struct ContactInputs {
    std::array<const Vec3*, body_kind_count> x{};
    std::array<const Vec3*, body_kind_count> v_dt{};
    std::array<const double*, body_kind_count> radius{};
    const Vec3* spin_dt = nullptr; ///< grains only
    double inv_dt = 0.0;
    double dt = 0.0;
    double damping_s = 0.0; ///< γ_n
    TangentialParams tangential;
    /// keep: an overlapping contact's spring and sliding flag are not
    /// written. What depends on the positions alone is written either way:
    /// a contact apart is released (spring reset, not touching), one that
    /// overlaps is marked touching; done twice at the same positions, these
    /// change nothing more.
    MemoryUpdate memory = MemoryUpdate::commit;
};

/// The inputs of the world's current state (valid until its bodies change).
[[nodiscard]] ContactInputs contact_inputs(const World& w);

/// Evaluates the contacts [p, p + simd_pair_lanes) of `c` (all body pairs)
/// that it can (above), writing their slots exactly as the scalar kernel
/// would. Returns the lanes it did (bit l = contact p + l); the caller
/// evaluates the others.
using SimdPairKernel = std::uint32_t (*)(ContactList& c, std::size_t p, const ContactInputs& in);


/// The same for the contacts [p, p + simd_pair_lanes), all of wall `wall`
/// (plane or cylinder): the lanes whose branch is certain.
using SimdWallKernel = std::uint32_t (*)(ContactList& c, std::size_t p, const Wall& wall, const ContactInputs& in);

/// Whether the explicit SIMD paths run: this pair kernel and the grains'
/// turn (integrate/rotation.hpp, turn_all). Both give the scalar code's bits.
enum class SimdKernels : std::uint8_t {
    automatic, ///< AVX-512 (F, VL, BW) when the CPU has it, else scalar
    scalar,    ///< the scalar code only
};

/// Chooses for every later step (tests and the bench compare the two).
void set_simd_kernels(SimdKernels kernels);

/// Whether the AVX-512 paths run (chosen, and the CPU has them).
[[nodiscard]] bool simd_kernels_in_use();

/// The SIMD pair kernel in use, or nullptr for the scalar path only.
[[nodiscard]] SimdPairKernel simd_pair_kernel();
/// The SIMD wall kernel in use, or nullptr for the scalar path only.
[[nodiscard]] SimdWallKernel simd_wall_kernel();

} // namespace wiredem::engine
