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
    WIREDEM_WITH_SIMD_ISA(
        isa, return MembraneSimdKernels{isa::lanes, &isa::edges, &isa::triangles, &isa::sums, &isa::split});
    return {};
}

} // namespace wiredem::engine
