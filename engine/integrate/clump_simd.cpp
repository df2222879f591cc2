// Compiled with -ffp-contract=off (as every file, CMakeLists.txt), like the
// grains' turn (rotation_simd.cpp): four clumps per AVX2 instruction, eight
// per AVX-512 one, each lane doing the scalar code's operations in Eigen's
// order.
#include "integrate/clump_simd.hpp"

#include "contact/pair_kernel_simd.hpp"
#include "integrate/rotation.hpp"

#include <array>

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

/// Clump i's spheres put at p.orientation[i], one by one (the lanes' scalar twin).
void place_one(const ClumpPlacement& p, std::size_t i)
{
    const Quat q = p.orientation[i];
    const Vec3 centre = p.centre[i], velocity = p.velocity[i];
    const Vec3 spin = q * p.omega1[i]; // δt ω in space
    const std::uint32_t end = p.first_member[i] + p.member_count[i];
    for (std::uint32_t g = p.first_member[i]; g < end; ++g) {
        const Vec3 arm = p.arms_in != nullptr ? p.arms_in[g] : Vec3(q * p.offset[g]);
        if (p.arms_out != nullptr) p.arms_out[g] = arm;
        p.x0[g] = centre + arm;
        p.x1[g] = velocity + spin.cross(arm); // δt (v + ω × r)
        p.theta1[g] = spin;
    }
}

#if defined(__x86_64__)

static_assert(sizeof(Quat) == 4 * sizeof(double), "a Quat is its coefficients x y z w");

// One kernel text, two instruction sets.
#define WIREDEM_LANES_KERNELS "integrate/clump_lanes.inc"
#include "contact/lanes_for_each_isa.inc"

template <std::size_t lanes>
void turn_blocks(std::uint32_t (*block)(const Quat*, const Vec3*, Quat*), const Quat* q, const Vec3* theta, Quat* out,
    std::size_t& i, std::size_t n)
{
    constexpr std::uint32_t all = (1u << lanes) - 1u;
    for (; i + lanes <= n; i += lanes) {
        const std::uint32_t done = block(q + i, theta + i, out + i);
        if (done != all)
            for (std::size_t l = 0; l < lanes; ++l)
                if (!(done >> l & 1u)) out[i + l] = (q[i + l] * rotation_quaternion(theta[i + l])).normalized();
    }
}

/// Clumps [i, e) placed `lanes` at a time where `lanes` consecutive clumps
/// have as many spheres each, the others one by one.
template <std::size_t lanes>
void place_blocks(void (*block)(const ClumpPlacement&, std::size_t, std::uint32_t), const ClumpPlacement& p,
    std::size_t& i, std::size_t e)
{
    while (i + lanes <= e) {
        const std::uint32_t count = p.member_count[i];
        bool same = true;
        for (std::size_t l = 1; l < lanes; ++l) same = same && p.member_count[i + l] == count;
        if (same) {
            block(p, i, count);
            i += lanes;
        } else {
            place_one(p, i);
            ++i;
        }
    }
}

#endif

} // namespace

void turn_clumps(const Quat* q, const Vec3* theta, Quat* out, std::size_t n)
{
    std::size_t i = 0;
    switch (simd_isa()) {
#if defined(__x86_64__)
    case SimdIsa::avx512: turn_blocks<with_avx512::lanes>(&with_avx512::turn_after_block, q, theta, out, i, n); break;
    case SimdIsa::avx2: turn_blocks<with_avx2::lanes>(&with_avx2::turn_after_block, q, theta, out, i, n); break;
#endif
    default: break;
    }
    for (; i < n; ++i) out[i] = (q[i] * rotation_quaternion(theta[i])).normalized();
}

void place_clumps(const ClumpPlacement& p, std::size_t b, std::size_t e)
{
    std::size_t i = b;
    switch (simd_isa()) {
#if defined(__x86_64__)
    case SimdIsa::avx512: place_blocks<with_avx512::lanes>(&with_avx512::place_block, p, i, e); break;
    case SimdIsa::avx2: place_blocks<with_avx2::lanes>(&with_avx2::place_block, p, i, e); break;
#endif
    default: break;
    }
    for (; i < e; ++i) place_one(p, i);
}

} // namespace wiredem::engine
