// Compiled with -ffp-contract=off (engine/CMakeLists.txt): each lane does
// wire_segment's, wire_stretch_force_n's and wire_joint's operations in
// Eigen's order, and compute_wire_forces' dashpots in theirs.
#include "forces/wire_simd.hpp"

#include "contact/pair_kernel_simd.hpp"

#include <cmath>
#include <cstddef>

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

#if defined(__x86_64__)

// A WireSegment is a record of four doubles: unit x y z, then the length.
static_assert(sizeof(WireSegment) == 4 * sizeof(double) && offsetof(WireSegment, length_m) == 3 * sizeof(double));

// One kernel text, two instruction sets.
#define WIREDEM_LANES_KERNELS "forces/wire_lanes.inc"
#include "contact/lanes_for_each_isa.inc"

#endif

} // namespace

WireSimdKernels simd_wire_kernels()
{
    WIREDEM_WITH_SIMD_ISA(isa, return WireSimdKernels{isa::lanes, &isa::segments, &isa::joints, &isa::nodes});
    return {};
}

} // namespace wiredem::engine
