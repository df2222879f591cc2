// Compiled with -ffp-contract=off (engine/CMakeLists.txt), like the SIMD pair
// kernel (contact/pair_kernel_simd.hpp, which says why that gives the scalar
// code's bits): eight grains per AVX-512 instruction or four per AVX2
// instruction, each lane doing turn()'s operations in Eigen's order.
#include "integrate/rotation.hpp"

#include "contact/pair_kernel_simd.hpp"

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

#if defined(__x86_64__)

static_assert(sizeof(Quat) == 4 * sizeof(double), "a Quat is its coefficients x y z w");

// One kernel text, two instruction sets.
#define WIREDEM_LANES_KERNELS "integrate/rotation_lanes.inc"
#include "contact/lanes_for_each_isa.inc"

/// The grains [i, i + lanes) turned by `block`, the lanes it leaves by turn().
template <std::size_t lanes>
void turn_blocks(std::uint32_t (*block)(Quat*, const Vec3*), Quat* q, const Vec3* theta, std::size_t& i, std::size_t n)
{
    constexpr std::uint32_t all = (1u << lanes) - 1u;
    for (; i + lanes <= n; i += lanes) {
        const std::uint32_t done = block(q + i, theta + i);
        if (done != all)
            for (std::size_t l = 0; l < lanes; ++l)
                if (!(done >> l & 1u)) turn(q[i + l], theta[i + l]);
    }
}

#endif

} // namespace

void turn_all(Quat* q, const Vec3* theta, std::size_t n)
{
    std::size_t i = 0;
    WIREDEM_WITH_SIMD_ISA(isa, turn_blocks<isa::lanes>(&isa::turn_block, q, theta, i, n));
    for (; i < n; ++i) turn(q[i], theta[i]);
}

} // namespace wiredem::engine
