// Explicit SIMD paths, chosen at run time: the body pairs and the body–wall
// contacts of the contact list several per instruction (here: eight per
// AVX-512 instruction, or four per AVX2 instruction on CPUs without AVX-512;
// one kernel text, contact/pair_kernel_lanes.inc, for both; one law, two
// geometries, as in the scalar pipeline), and with AVX-512 also the grains'
// turn (integrate/rotation_simd.cpp), the membrane (forces/membrane_simd.cpp)
// and the wire (forces/wire_simd.cpp). The pair kernel takes a list of
// pairs of any kinds (the near pairs, NearPairs; grains, wire nodes,
// membrane nodes: the same sphere–sphere law): it screens them `lanes` at a
// time for overlap, then runs the law on the overlapping ones packed
// `lanes` to a block (about a fifth of the near pairs of a packing at rest
// are apart, and a block of consecutive pairs would run the law on them
// too); it does the pairs that
// are apart or overlapping with a certain branch of the tangential law
// (sticking, sliding on, re-sticking, breaking), and returns the others (a
// NaN, a boundary case) to the scalar kernel of compute_contact_forces
// (engine/step.cpp). The wall kernel takes `lanes` consecutive contacts of
// one wall.
//
// Same bits as the scalar path. Each lane performs the scalar code's
// operations (contact/geometry.hpp, laws/hertz.hpp, laws/tangential.hpp) in
// the same order, on the same inputs (a body that does not turn has the
// scalar path's zero spin): IEEE additions, multiplications, divisions and
// square roots are correctly rounded whatever the vector width, and the files
// are compiled with -ffp-contract=off so that no multiply–add is fused (the
// baseline x86-64 build has no FMA, so the scalar path never fuses either). A
// lane is taken only when the vector path is sure of its branch (ordered
// comparisons). So states are the same with and without these paths, with
// either instruction set, and for any thread count
// (Determinism.SimdAndScalarKernelsGiveTheSameBits).
#pragma once

#include "contact/contact_list.hpp"
#include "laws/rolling.hpp"
#include "laws/tangential.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace wiredem::engine {

struct Wall;
struct World;

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
    /// Rolling resistance (laws/rolling.hpp) on the grain–grain and
    /// grain–wall contacts, worked out in the kernels with the force; off
    /// while inverse_inertia_about_contact is nullptr.
    RollingParams rolling;
    /// Per grain, 1/(I + m r²): its inverse inertia about a point of its
    /// surface (0 for a grain that does not turn); compute_contact_forces.
    const double* inverse_inertia_about_contact = nullptr;
    /// keep: an overlapping contact's spring and sliding flag are not
    /// written. What depends on the positions alone is written either way:
    /// a contact apart is released (spring reset, not touching), one that
    /// overlaps is marked touching; done twice at the same positions, these
    /// change nothing more.
    MemoryUpdate memory = MemoryUpdate::commit;
};

/// The inputs of the world's current state (valid until its bodies change).
[[nodiscard]] ContactInputs contact_inputs(const World& w);

/// Evaluates the body pairs ids[0 … n) of `c`, whose sides are first[k] and
/// second[k] (n a multiple of `lanes`; the near pairs, NearPairs), as the
/// scalar kernel would, save the ones whose indices it writes to `left` (it
/// returns how many; room for n is enough): the caller evaluates those.
using SimdPairKernel = std::size_t (*)(ContactList& c, const std::uint32_t* ids, const BodyRef* first,
    const BodyRef* second, std::size_t n, const ContactInputs& in, std::uint32_t* left);

/// Evaluates the contacts [p, p + lanes) of `c`, all of wall `wall` (plane
/// or cylinder; `lanes` that of the kernels in use, SimdContactKernels),
/// that it can (above), writing their slots exactly as the scalar kernel
/// would. Returns the lanes it did (bit l = contact p + l); the caller
/// evaluates the others.
using SimdWallKernel = std::uint32_t (*)(ContactList& c, std::size_t p, const Wall& wall, const ContactInputs& in);

/// Which explicit SIMD paths run. Every choice gives the scalar code's bits.
enum class SimdKernels : std::uint8_t {
    automatic, ///< AVX-512 (F, VL, BW) when the CPU has it, else AVX2 when it has that, else scalar
    avx2,      ///< the AVX2 contact kernels (where the CPU has AVX2), even on a CPU with AVX-512
    scalar,    ///< the scalar code only
};

/// Chooses for every later step (tests and the bench compare them).
void set_simd_kernels(SimdKernels kernels);

/// The instruction set the SIMD paths run with (chosen, and the CPU has it).
enum class SimdIsa : std::uint8_t { none, avx2, avx512 };
[[nodiscard]] SimdIsa simd_isa();

/// WIREDEM_WITH_SIMD_ISA(ns, statement): runs `statement` with `ns` naming
/// the namespace of the kernels of the instruction set in use — `with_avx512`
/// or `with_avx2`, which contact/lanes_for_each_isa.inc makes of a file's
/// kernel text — and does nothing on the scalar path (simd_isa() is none, or
/// not on x86-64), where the caller's scalar code follows. The one place
/// where an instruction set is matched to its kernels:
///
///     WIREDEM_WITH_SIMD_ISA(isa, return Kernels{isa::lanes, &isa::edges});
///     return Kernels{};                  // the scalar path
#if defined(__x86_64__)
#define WIREDEM_WITH_SIMD_ISA(ns, ...)                                                                                \
    do {                                                                                                              \
        switch (::wiredem::engine::simd_isa()) {                                                                      \
        case ::wiredem::engine::SimdIsa::avx512: {                                                                    \
            namespace ns = with_avx512;                                                                               \
            __VA_ARGS__;                                                                                              \
        } break;                                                                                                      \
        case ::wiredem::engine::SimdIsa::avx2: {                                                                      \
            namespace ns = with_avx2;                                                                                 \
            __VA_ARGS__;                                                                                              \
        } break;                                                                                                      \
        case ::wiredem::engine::SimdIsa::none: break;                                                                 \
        }                                                                                                             \
    } while (false)
#else
#define WIREDEM_WITH_SIMD_ISA(ns, ...) static_cast<void>(0)
#endif

/// The SIMD contact kernels in use: `lanes` contacts per call; none (lanes
/// 0, null kernels) for the scalar path only.
struct SimdContactKernels {
    std::size_t lanes = 0;
    SimdPairKernel pairs = nullptr;
    SimdWallKernel wall = nullptr;
};
[[nodiscard]] SimdContactKernels simd_contact_kernels();

} // namespace wiredem::engine
