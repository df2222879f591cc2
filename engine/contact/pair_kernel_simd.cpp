// Compiled with -ffp-contract=off (engine/CMakeLists.txt): see the header for
// why the lanes give the scalar law's bits.
#include "contact/pair_kernel_simd.hpp"

#include "state/world.hpp"

#include <array>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <limits>

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

std::atomic<SimdKernels> chosen_kernels{SimdKernels::automatic};

#if defined(__x86_64__)

// The loads read Vec3 arrays as doubles with a stride of 3, the contact
// list's ids as 32-bit words and its springs with a stride of 4.
static_assert(sizeof(Vec3) == 3 * sizeof(double));
static_assert(sizeof(BodyRef) == sizeof(std::uint32_t));
static_assert(sizeof(TangentialState) == 4 * sizeof(double) && offsetof(TangentialState, spring_m) == 0);

/// The spin of a body that does not turn: the scalar path's zero vector.
constexpr double no_spin[3] = {0.0, 0.0, 0.0};

// One kernel text, two instruction sets.
#define WIREDEM_LANES_KERNELS "contact/pair_kernel_lanes.inc"
#include "contact/lanes_for_each_isa.inc"

#endif

} // namespace

ContactInputs contact_inputs(const World& w)
{
    ContactInputs in;
    for (int k = 0; k < body_kind_count; ++k) {
        in.x[k] = w.bodies[k].x[0].data();
        in.v_dt[k] = w.bodies[k].x[1].data();
        in.radius[k] = w.bodies[k].radius_m.data();
    }
    in.spin_dt = w.grain_rotation.theta[1].data();
    in.inv_dt = 1.0 / w.dt_s;
    in.dt = w.dt_s;
    in.damping_s = w.contact.normal_damping_s;
    in.tangential = w.contact.tangential;
    return in;
}

void set_simd_kernels(SimdKernels kernels) { chosen_kernels.store(kernels, std::memory_order_relaxed); }

SimdIsa simd_isa()
{
#if defined(__x86_64__)
    static const bool has_avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl")
                                   && __builtin_cpu_supports("avx512bw");
    static const bool has_avx2 = __builtin_cpu_supports("avx2");
    switch (chosen_kernels.load(std::memory_order_relaxed)) {
    case SimdKernels::automatic: return has_avx512 ? SimdIsa::avx512 : has_avx2 ? SimdIsa::avx2 : SimdIsa::none;
    case SimdKernels::avx2: return has_avx2 ? SimdIsa::avx2 : SimdIsa::none;
    case SimdKernels::scalar: return SimdIsa::none;
    }
#endif
    return SimdIsa::none;
}

SimdContactKernels simd_contact_kernels()
{
    WIREDEM_WITH_SIMD_ISA(isa, return SimdContactKernels{isa::lanes, &isa::pair_ids, &isa::wall_block});
    return {};
}

} // namespace wiredem::engine
