// Compiled with -ffp-contract=off (engine/CMakeLists.txt): each lane does
// wire_segment's, wire_stretch_force_n's and wire_joint's operations in
// Eigen's order, and compute_wire_forces' dashpots in theirs.
#include "forces/wire_simd.hpp"

#include "contact/pair_kernel_simd.hpp"

#include <cmath>
#include <cstddef>

#if defined(__x86_64__)
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

#if defined(__x86_64__)

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized" // GCC 12's intrinsics, as in pair_kernel_simd.cpp
#pragma GCC diagnostic ignored "-Wuninitialized"

using namespace avx512;

// A WireSegment is a record of four doubles: unit x y z, then the length.
static_assert(sizeof(WireSegment) == 4 * sizeof(double) && offsetof(WireSegment, length_m) == 3 * sizeof(double));
static_assert(sizeof(std::array<Vec3, 3>) == 9 * sizeof(double));

/// Eight consecutive 3-vectors from v[0] on, into lanes.
[[WIREDEM_AVX512]] inline V3 load_consecutive(const Vec3* v) { return load_consecutive_vec3s(v->data()); }

[[gnu::target("avx512f,avx512vl,avx512bw")]] void segments_avx512(const Vec3* x, const Vec3* dx,
    const WireKernelParams& p, WireSegment* segment, Vec3* force_n, double* strain, std::size_t count)
{
    const __m512d zero = _mm512_setzero_pd();
    const __m512d k = _mm512_set1_pd(p.axial_stiffness_n_per_m), l0 = _mm512_set1_pd(p.segment_length_m);
    const __m512d damping = _mm512_set1_pd(p.tau_per_dt * p.axial_stiffness_n_per_m);
    const bool damped = p.tau_per_dt > 0.0;
    for (std::size_t s = 0; s < count; s += 8) {
        // wire_segment: d / |d|, or nothing for |d| = 0.
        const V3 d = load_consecutive(x + s + 1) - load_consecutive(x + s);
        const __m512d len = _mm512_sqrt_pd(dot(d, d));
        const __mmask8 has_length = _mm512_cmp_pd_mask(len, zero, _CMP_NEQ_UQ); // NaN goes on, as == 0 is false
        const V3 unit = masked(has_length, {d.x / len, d.y / len, d.z / len});
        const __m512d length = _mm512_maskz_mov_pd(has_length, len);
        store_records4(segment[s].unit.data(), 0xff, {unit.x, unit.y, unit.z, length}, 0xf);
        // wire_stretch_force_n: k (|d| − l₀)/|d| · d.
        V3 f = masked(has_length, (k * (len - l0) / len) * d);
        // The dashpot, while the segment has a length (> 0, ordered).
        if (damped) {
            const __mmask8 dashpot = _mm512_cmp_pd_mask(length, zero, _CMP_GT_OQ);
            const V3 rate = load_consecutive(dx + s + 1) - load_consecutive(dx + s);
            const __m512d c = damping * dot(rate, unit);
            const V3 damped_f = f + c * unit;
            f = blend(dashpot, f, damped_f);
        }
        store_vec3s(force_n[s].data(), f);
        _mm512_storeu_pd(strain + s, (length - l0) / l0);
    }
}

[[gnu::target("avx512f,avx512vl,avx512bw")]] void joints_avx512(const WireSegment* segment, const Vec3* dx,
    const WireKernelParams& p, double* rest_angle_rad, std::array<Vec3, 3>* force_n, std::size_t count)
{
    const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0), six = _mm512_set1_pd(6.0);
    const __m512d k_rot = _mm512_set1_pd(p.bending_stiffness_n_m), zeta_y = _mm512_set1_pd(p.bending_yield_angle_rad);
    const __m512d straight = _mm512_set1_pd(wire_straight_sin), gradient_sin = _mm512_set1_pd(wire_gradient_sin);
    const __m512d damping = _mm512_set1_pd(p.tau_per_dt * p.bending_stiffness_n_m);
    const bool damped = p.tau_per_dt > 0.0;
    for (std::size_t j = 0; j < count; j += 8) {
        const Records4 a = load_records4(segment[j].unit.data()), b = load_records4(segment[j + 1].unit.data());
        const V3 ua{a.x, a.y, a.z}, ub{b.x, b.y, b.z};
        const __m512d la = a.w, lb = b.w;
        // wire_joint returns nothing (zero forces, the rest angle kept) for a
        // segment of zero length; a NaN length goes on, as == 0 is false.
        const __mmask8 bends = _mm512_cmp_pd_mask(la, zero, _CMP_NEQ_UQ) & _mm512_cmp_pd_mask(lb, zero, _CMP_NEQ_UQ);
        const __m512d cos_z = dot(ua, ub);
        const V3 normal = cross(ua, ub);
        const __m512d sin_z = _mm512_sqrt_pd(dot(normal, normal));
        alignas(64) double sin_lanes[8], cos_lanes[8], zeta_lanes[8];
        _mm512_store_pd(sin_lanes, sin_z);
        _mm512_store_pd(cos_lanes, cos_z);
        for (int l = 0; l < 8; ++l) zeta_lanes[l] = std::atan2(sin_lanes[l], cos_lanes[l]);
        const __m512d zeta = _mm512_load_pd(zeta_lanes);
        // yielded_rest_angle_rad: max(0, min(max(ζ₀, ζ − ζ_y), ζ + ζ_y)) with
        // std::max(a, b) = b > a ? b : a = _mm512_max_pd(b, a) (ties and NaNs
        // give a, as std::max does), std::min likewise.
        const __m512d old_rest = _mm512_loadu_pd(rest_angle_rad + j);
        const __m512d rest = _mm512_max_pd(
            _mm512_min_pd(zeta + zeta_y, _mm512_max_pd(zeta - zeta_y, old_rest)), zero);
        const __mmask8 curved = _mm512_cmp_pd_mask(sin_z, straight, _CMP_GT_OQ);
        const __m512d z_over_sin = _mm512_mask_blend_pd(curved, one + zeta * zeta / six, zeta / sin_z);
        const __m512d k = k_rot * (z_over_sin - rest / _mm512_max_pd(straight, sin_z));
        const V3 towards_next = ua - cos_z * ub, towards_prev = ub - cos_z * ua;
        const V3 f_next = (k / lb) * towards_next, f_prev = (-k / la) * towards_prev;
        V3 f[3] = {masked(bends, f_prev), masked(bends, {-(f_prev.x + f_next.x), -(f_prev.y + f_next.y),
                                                          -(f_prev.z + f_next.z)}), masked(bends, f_next)};
        _mm512_storeu_pd(rest_angle_rad + j, _mm512_mask_blend_pd(bends, old_rest, rest));
        if (damped) {
            // ∇ζ where the joint bends and !(sin ζ < 10⁻⁹); zero elsewhere.
            const __mmask8 has_gradient = bends & _mm512_cmp_pd_mask(sin_z, gradient_sin, _CMP_NLT_UQ);
            const __m512d sb = lb * sin_z, sa = la * sin_z;
            const V3 g_next = masked(has_gradient, {-towards_next.x / sb, -towards_next.y / sb, -towards_next.z / sb});
            const V3 g_prev = masked(has_gradient, {towards_prev.x / sa, towards_prev.y / sa, towards_prev.z / sa});
            const V3 g_mid = masked(has_gradient, {-(g_prev.x + g_next.x), -(g_prev.y + g_next.y), -(g_prev.z + g_next.z)});
            const __m512d zeta_dot_dt = dot(g_prev, load_consecutive(dx + j)) + dot(g_mid, load_consecutive(dx + j + 1))
                                      + dot(g_next, load_consecutive(dx + j + 2));
            const __m512d c = damping * zeta_dot_dt;
            f[0] = f[0] - c * g_prev;
            f[1] = f[1] - c * g_mid;
            f[2] = f[2] - c * g_next;
        }
        // Out: node by node, nine doubles per joint.
        alignas(64) double lanes[9][8];
        for (int n = 0; n < 3; ++n) {
            _mm512_store_pd(lanes[3 * n], f[n].x);
            _mm512_store_pd(lanes[3 * n + 1], f[n].y);
            _mm512_store_pd(lanes[3 * n + 2], f[n].z);
        }
        for (int l = 0; l < 8; ++l) {
            double* out = force_n[j + l][0].data();
            for (int c = 0; c < 9; ++c) out[c] = lanes[c][l];
        }
    }
}

#pragma GCC diagnostic pop

#endif

} // namespace

WireSimdKernels simd_wire_kernels()
{
    WireSimdKernels k;
#if defined(__x86_64__)
    if (simd_isa() == SimdIsa::avx512) {
        k.segments = &segments_avx512;
        k.joints = &joints_avx512;
    }
#endif
    return k;
}

} // namespace wiredem::engine
