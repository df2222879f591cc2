// Compiled with -ffp-contract=off (engine/CMakeLists.txt), like the SIMD pair
// kernel (contact/pair_kernel_simd.hpp, which says why that gives the scalar
// code's bits): eight grains per AVX-512 instruction, each lane doing
// turn()'s operations in Eigen's order.
#include "integrate/rotation.hpp"

#include "contact/pair_kernel_simd.hpp"

#if defined(__x86_64__)
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

#if defined(__x86_64__)

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized" // GCC 12's intrinsics, as in pair_kernel_simd.cpp

static_assert(sizeof(Quat) == 4 * sizeof(double), "a Quat is its coefficients x y z w");

using namespace avx512;

/// turn(q[l], theta[l]) for eight consecutive grains; returns the lanes it
/// did: not those with |θ|² ≥ 10⁻⁴ (the sine and cosine: the scalar code).
[[gnu::target("avx512f,avx512vl,avx512bw")]] unsigned turn_block_avx512(Quat* q, const Vec3* theta)
{
    const V3 t = load_consecutive_vec3s(theta->data());
    const __m512d tx = t.x, ty = t.y, tz = t.z;
    const __m512d zero = _mm512_setzero_pd();
    const __mmask8 still = _mm512_cmp_pd_mask(tx, zero, _CMP_EQ_OQ) & _mm512_cmp_pd_mask(ty, zero, _CMP_EQ_OQ)
                         & _mm512_cmp_pd_mask(tz, zero, _CMP_EQ_OQ);
    // rotation_quaternion: the Taylor series of cos and sin/angle in |θ|².
    const __m512d a2 = tx * tx + ty * ty + tz * tz;
    const __mmask8 lanes = static_cast<__mmask8>(~still & _mm512_cmp_pd_mask(a2, _mm512_set1_pd(1e-4), _CMP_LT_OQ));
    if (lanes == 0) return still;
    const __m512d aa = a2 * a2;
    const __m512d cw = _mm512_set1_pd(1.0) - a2 / _mm512_set1_pd(8.0) + aa / _mm512_set1_pd(384.0);
    const __m512d s = _mm512_set1_pd(0.5) - a2 / _mm512_set1_pd(48.0) + aa / _mm512_set1_pd(3840.0);
    const __m512d rx = s * tx, ry = s * ty, rz = s * tz;
    // r ⊗ q in Eigen's SSE2 order (Geometry_SIMD.h, quat_product for double).
    const Records4 b = load_records4(q->coeffs().data());
    Records4 p;
    p.x = (cw * b.x + ry * b.z) - (rz * b.y - rx * b.w);
    p.y = (cw * b.y + ry * b.w) + (rz * b.x - rx * b.z);
    p.z = (cw * b.z - ry * b.x) + (rz * b.w + rx * b.y);
    p.w = (cw * b.w - ry * b.y) - (rz * b.z + rx * b.x);
    // normalized(): |p|² summed as Eigen's two-double packets, (x² + z²) + (y² + w²);
    // each coefficient divided by its root when positive.
    const __m512d n2 = (p.x * p.x + p.z * p.z) + (p.y * p.y + p.w * p.w);
    const __mmask8 positive = _mm512_cmp_pd_mask(n2, zero, _CMP_GT_OQ);
    const __m512d n = _mm512_sqrt_pd(n2);
    p = {_mm512_mask_div_pd(p.x, positive, p.x, n), _mm512_mask_div_pd(p.y, positive, p.y, n),
        _mm512_mask_div_pd(p.z, positive, p.z, n), _mm512_mask_div_pd(p.w, positive, p.w, n)};
    store_records4(q->coeffs().data(), lanes, p, 0xf);
    return still | lanes;
}

#pragma GCC diagnostic pop

#endif

} // namespace

void turn_all(Quat* q, const Vec3* theta, std::size_t n)
{
    std::size_t i = 0;
#if defined(__x86_64__)
    if (simd_isa() == SimdIsa::avx512)
        for (; i + 8 <= n; i += 8) {
            const unsigned done = turn_block_avx512(q + i, theta + i);
            if (done != 0xffu)
                for (std::size_t l = 0; l < 8; ++l)
                    if (!(done >> l & 1u)) turn(q[i + l], theta[i + l]);
        }
#endif
    for (; i < n; ++i) turn(q[i], theta[i]);
}

} // namespace wiredem::engine
