// Compiled with -ffp-contract=off (engine/CMakeLists.txt): each lane does
// membrane_edge_force_n's, the pressure's and the node sum's operations in
// the scalar order.
#include "forces/membrane_simd.hpp"

#include "contact/pair_kernel_simd.hpp"

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

#if defined(__x86_64__)

// One kernel text, two instruction sets.
#define WIREDEM_LANES_KERNELS "forces/membrane_lanes.inc"
#include "contact/lanes_for_each_isa.inc"

#endif

} // namespace

MembraneSimdKernels simd_membrane_kernels()
{
    switch (simd_isa()) {
#if defined(__x86_64__)
    case SimdIsa::avx512: return {with_avx512::lanes, &with_avx512::edges, &with_avx512::triangles, &with_avx512::sums, &with_avx512::split};
    case SimdIsa::avx2: return {with_avx2::lanes, &with_avx2::edges, &with_avx2::triangles, &with_avx2::sums, &with_avx2::split};
#endif
    default: return {};
    }
}

} // namespace wiredem::engine
