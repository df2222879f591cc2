// Compiled with -ffp-contract=off (engine/CMakeLists.txt): each lane does
// membrane_edge_force_n's and the pressure's operations in Eigen's order.
#include "forces/membrane_simd.hpp"

#include "contact/pair_kernel_simd.hpp"

#if defined(__x86_64__)
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

#if defined(__x86_64__)

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized" // GCC 12's intrinsics, as in pair_kernel_simd.cpp

using namespace avx512;

[[gnu::target("avx512f,avx512vl,avx512bw")]] void edges_avx512(const Vec3* x,
    const std::array<std::uint32_t, 2>* edges, const double* rest_m, double stiffness_n_per_m, MembraneEdgeLaw law,
    Vec3* force_n, std::size_t count)
{
    static_assert(sizeof(std::array<std::uint32_t, 2>) == 8 && sizeof(Vec3) == 3 * sizeof(double));
    const double* at = x->data();
    const __m512d k = _mm512_set1_pd(stiffness_n_per_m), zero = _mm512_setzero_pd();
    for (std::size_t e = 0; e < count; e += 8) {
        // Both ends of eight edges: masked loads transposed in registers
        // (cheaper than gathers on this CPU, as in the pair kernel).
        std::array<const double*, 8> end_a, end_b;
        for (int l = 0; l < 8; ++l) {
            end_a[l] = at + 3 * std::size_t{edges[e + l][0]};
            end_b[l] = at + 3 * std::size_t{edges[e + l][1]};
        }
        const V3 a = load_vec3s(end_a), b = load_vec3s(end_b);
        const V3 d = b - a;
        const __m512d len = _mm512_sqrt_pd(dot(d, d));
        const __m512d stretch = len - _mm512_loadu_pd(rest_m + e);
        // Zero where the scalar law returns Vec3::Zero(): len == 0, or a
        // slack tension-only edge (unordered comparisons: a NaN goes on, as
        // in the scalar code).
        __mmask8 pulls = _mm512_cmp_pd_mask(len, zero, _CMP_NEQ_UQ);
        if (law == MembraneEdgeLaw::tension_only) pulls &= _mm512_cmp_pd_mask(stretch, zero, _CMP_NLE_UQ);
        const __m512d s = k * stretch / len;
        store_vec3s(force_n[e].data(), masked(pulls, s * d));
    }
}

/// Corner `c` of the eight triangles at `tri`, into lanes (masked loads
/// transposed in registers, as for the edges).
[[WIREDEM_AVX512]] inline V3 corners(const double* at, const std::array<std::uint32_t, 3>* tri, int c)
{
    std::array<const double*, 8> corner;
    for (int l = 0; l < 8; ++l) corner[l] = at + 3 * std::size_t{tri[l][c]};
    return load_vec3s(corner);
}

[[gnu::target("avx512f,avx512vl,avx512bw")]] void triangles_avx512(const Vec3* x,
    const std::array<std::uint32_t, 3>* triangles, double pressure_pa, Vec3* force_n, std::size_t count)
{
    const double* at = x->data();
    const __m512d sixth = _mm512_set1_pd(pressure_pa / 6.0);
    for (std::size_t t = 0; t < count; t += 8) {
        const auto* tri = triangles + t;
        const V3 a = corners(at, tri, 0), b = corners(at, tri, 1), c = corners(at, tri, 2);
        store_vec3s(force_n[t].data(), sixth * cross(b - a, c - a));
    }
}

#pragma GCC diagnostic pop

#endif

} // namespace

MembraneSimdKernels simd_membrane_kernels()
{
    MembraneSimdKernels k;
#if defined(__x86_64__)
    if (simd_isa() == SimdIsa::avx512) {
        k.edges = &edges_avx512;
        k.triangles = &triangles_avx512;
    }
#endif
    return k;
}

} // namespace wiredem::engine
