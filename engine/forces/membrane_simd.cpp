// Compiled with -ffp-contract=off (engine/CMakeLists.txt): each lane does
// membrane_edge_force_n's and the pressure's operations in Eigen's order.
#include "forces/membrane_simd.hpp"

#include "contact/pair_kernel_simd.hpp"

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

#if defined(__x86_64__)

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized" // GCC 12's intrinsics, as in pair_kernel_simd.cpp

// One kernel text (membrane_lanes.inc), two instruction sets.
namespace with_avx512 {
using namespace avx512;
#define WIREDEM_LANES_FN WIREDEM_AVX512
#define WIREDEM_LANES_TARGET gnu::target("avx512f,avx512vl,avx512bw")
#include "forces/membrane_lanes.inc"
#undef WIREDEM_LANES_TARGET
#undef WIREDEM_LANES_FN
} // namespace with_avx512

namespace with_avx2 {
using namespace avx2;
#define WIREDEM_LANES_FN WIREDEM_AVX2
#define WIREDEM_LANES_TARGET gnu::target("avx2")
#include "forces/membrane_lanes.inc"
#undef WIREDEM_LANES_TARGET
#undef WIREDEM_LANES_FN
} // namespace with_avx2

#pragma GCC diagnostic pop

#endif

} // namespace

MembraneSimdKernels simd_membrane_kernels()
{
    switch (simd_isa()) {
#if defined(__x86_64__)
    case SimdIsa::avx512: return {with_avx512::lanes, &with_avx512::edges, &with_avx512::triangles};
    case SimdIsa::avx2: return {with_avx2::lanes, &with_avx2::edges, &with_avx2::triangles};
#endif
    default: return {};
    }
}

} // namespace wiredem::engine
