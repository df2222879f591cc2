// Explicit SIMD paths, chosen at run time: the grain–grain pairs and the
// grain–wall contacts of the contact list eight per AVX-512 instruction
// (here; one law, two geometries, as in the scalar pipeline), and the grains' turn
// (integrate/rotation_simd.cpp). The pair kernel takes eight consecutive
// pairs when all are grain–grain, and of those the lanes that are apart or
// overlapping with a certain branch of the tangential law (sticking, sliding
// on, re-sticking, breaking); everything else (wire or membrane sides, walls,
// a NaN, a boundary case) goes to the scalar kernel of compute_contact_forces
// (engine/step.cpp).
//
// Same bits as the scalar path. Each lane performs the scalar code's
// operations (contact/geometry.hpp, laws/hertz.hpp, laws/tangential.hpp) in
// the same order: IEEE additions, multiplications, divisions and square roots
// are correctly rounded whatever the vector width, and the files are compiled
// with -ffp-contract=off so that no multiply–add is fused (the baseline
// x86-64 build has no FMA, so the scalar path never fuses either). A lane is
// taken only when the vector path is sure of its branch (ordered
// comparisons). So states are the same with and without these paths, and the
// same for any thread count (Determinism.SimdAndScalarKernelsGiveTheSameBits).
#pragma once

#include "contact/contact_list.hpp"
#include "laws/tangential.hpp"

#include <cstddef>
#include <cstdint>

namespace wiredem::engine {

/// Lanes of one call of the SIMD pair kernel.
inline constexpr std::size_t simd_pair_lanes = 8;

/// What the SIMD pair kernel reads besides the contact list: the grains'
/// positions x₀, scaled velocities x₁ = δt v, radii and scaled spins δt ω,
/// and the contact law.
struct GrainPairInputs {
    const Vec3* x = nullptr;
    const Vec3* v_dt = nullptr;
    const double* radius = nullptr;
    const Vec3* spin_dt = nullptr;
    double inv_dt = 0.0;
    double dt = 0.0;
    double damping_s = 0.0; ///< γ_n
    TangentialParams tangential;
};

/// Evaluates the contacts [p, p + simd_pair_lanes) of `c` (all body pairs)
/// that it can (above), writing their slots exactly as the scalar kernel
/// would. Returns the lanes it did (bit l = contact p + l); the caller
/// evaluates the others.
using SimdPairKernel = std::uint32_t (*)(ContactList& c, std::size_t p, const GrainPairInputs& in);

struct Wall;

/// The same for the contacts [p, p + simd_pair_lanes), all of wall `wall`
/// (plane or cylinder): the lanes whose first side is a grain and whose
/// branch is certain.
using SimdWallKernel = std::uint32_t (*)(ContactList& c, std::size_t p, const Wall& wall, const GrainPairInputs& in);

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
