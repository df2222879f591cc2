// AVX-512 helpers for the SIMD kernels (the *_lanes.inc texts included by
// contact/pair_kernel_simd.cpp, integrate/rotation_simd.cpp,
// forces/membrane_simd.cpp, forces/wire_simd.cpp): eight lanes of doubles
// with the arithmetic of the scalar code, lane masks, and transposes between
// arrays of small records and lane registers; avx2.hpp gives the same names
// for four lanes. Include only in files built with -ffp-contract=off (see
// pair_kernel_simd.hpp: no fused multiply–add, so the lanes keep the scalar
// code's bits) and only on x86-64.
#pragma once

#include "core/types.hpp"

#include <immintrin.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>

namespace wiredem::engine::avx512 {

// Every helper is inlined into functions built for AVX-512 (F, VL, BW),
// which the CPU is checked for at run time (simd_isa).
#define WIREDEM_AVX512_TARGET gnu::target("avx512f,avx512vl,avx512bw")
#define WIREDEM_AVX512 WIREDEM_AVX512_TARGET, gnu::always_inline

inline constexpr unsigned lanes = 8;
// Eight lanes of doubles; GCC's vector extensions give __m512d the
// arithmetic operators, lane by lane (no fusing: -ffp-contract=off).
using Pd = __m512d;
/// A lane mask: bit l for lane l (what AVX-512 compares give).
using Mask = __mmask8;

/// Bit l set for lane l.
[[WIREDEM_AVX512]] inline std::uint32_t bits(Mask m) { return m; }
[[WIREDEM_AVX512]] inline bool none(Mask m) { return m == 0; }
[[WIREDEM_AVX512]] inline Mask mask_of_bits(std::uint32_t b) { return static_cast<Mask>(b); }
/// a ⋈ b lane by lane (P: a _CMP_… predicate).
template <int P>
[[WIREDEM_AVX512]] inline Mask compare(Pd a, Pd b)
{
    return _mm512_cmp_pd_mask(a, b, P);
}
[[WIREDEM_AVX512]] inline Pd set1(double x) { return _mm512_set1_pd(x); }
[[WIREDEM_AVX512]] inline Pd zero() { return _mm512_setzero_pd(); }
[[WIREDEM_AVX512]] inline Pd sqrt(Pd a) { return _mm512_sqrt_pd(a); }
/// The second operand when either is NaN, as std::fmin(b, a) of ordered values.
[[WIREDEM_AVX512]] inline Pd min(Pd a, Pd b) { return _mm512_min_pd(a, b); }
[[WIREDEM_AVX512]] inline Pd max(Pd a, Pd b) { return _mm512_max_pd(a, b); }
/// b in the lanes of `pick`, a in the others.
[[WIREDEM_AVX512]] inline Pd blend(Mask pick, Pd a, Pd b) { return _mm512_mask_blend_pd(pick, a, b); }
/// a in the lanes of `keep`, zero in the others.
[[WIREDEM_AVX512]] inline Pd maskz(Mask keep, Pd a) { return _mm512_maskz_mov_pd(keep, a); }
/// √a in the lanes of `m`, src in the others.
[[WIREDEM_AVX512]] inline Pd mask_sqrt(Pd src, Mask m, Pd a) { return _mm512_mask_sqrt_pd(src, m, a); }
/// a / b in the lanes of `m`, src in the others.
[[WIREDEM_AVX512]] inline Pd mask_div(Pd src, Mask m, Pd a, Pd b) { return _mm512_mask_div_pd(src, m, a, b); }
[[WIREDEM_AVX512]] inline Pd loadu(const double* p) { return _mm512_loadu_pd(p); }
[[WIREDEM_AVX512]] inline Pd load_lanes(const std::array<double, lanes>& a) { return _mm512_loadu_pd(a.data()); }
[[WIREDEM_AVX512]] inline void storeu(double* p, Pd a) { _mm512_storeu_pd(p, a); }
[[WIREDEM_AVX512]] inline void store_lanes(std::array<double, lanes>& out, Pd a) { _mm512_storeu_pd(out.data(), a); }
/// Every lane.
[[WIREDEM_AVX512]] inline Mask all_lanes() { return 0xFF; }
/// No lane.
[[WIREDEM_AVX512]] inline Mask no_lanes() { return 0; }

#define WIREDEM_LANES_FN WIREDEM_AVX512
#include "contact/lanes_vec3.inc"
#undef WIREDEM_LANES_FN

[[WIREDEM_AVX512]] inline __m512i lanes_of(long long a, long long b, long long c, long long d, long long e,
    long long f, long long g, long long h)
{
    return _mm512_setr_epi64(a, b, c, d, e, f, g, h);
}

/// The Vec3s at `low` and `high` as rows x y z 0, one per half (masked to
/// three doubles, so the last body of an array is not read past).
[[WIREDEM_AVX512]] inline __m512d two_rows(const double* low, const double* high) // x y z 0 x y z 0
{
    return _mm512_insertf64x4(
        _mm512_castpd256_pd512(_mm256_maskz_loadu_pd(0x7, low)), _mm256_maskz_loadu_pd(0x7, high), 1);
}
/// Components of eight consecutive records of four doubles (a quaternion's
/// x y z w; a spring's x y z and the word holding `sticking`), one register each.
struct Records4 {
    __m512d x, y, z, w;
};

/// Rows of four doubles (lane l's x y z w), two per register (r04: lanes 0
/// and 4, …), transposed into lanes.
[[WIREDEM_AVX512]] inline Records4 transpose_rows(__m512d r04, __m512d r15, __m512d r26, __m512d r37)
{
    const __m512d xz01 = _mm512_unpacklo_pd(r04, r15), yw01 = _mm512_unpackhi_pd(r04, r15);
    const __m512d xz23 = _mm512_unpacklo_pd(r26, r37), yw23 = _mm512_unpackhi_pd(r26, r37);
    const __m512i even = lanes_of(0, 1, 8, 9, 4, 5, 12, 13), odd = lanes_of(2, 3, 10, 11, 6, 7, 14, 15);
    return {_mm512_permutex2var_pd(xz01, even, xz23), _mm512_permutex2var_pd(yw01, even, yw23),
        _mm512_permutex2var_pd(xz01, odd, xz23), _mm512_permutex2var_pd(yw01, odd, yw23)};
}

/// x, y and z of the Vec3 at p[l] in lane l: eight loads of x y z
/// transposed in registers, cheaper than three gathers on this CPU.
[[WIREDEM_AVX512]] inline V3 load_vec3s(const std::array<const double*, 8>& p)
{
    const Records4 r = transpose_rows(two_rows(p[0], p[4]), two_rows(p[1], p[5]), two_rows(p[2], p[6]), two_rows(p[3], p[7]));
    return {r.x, r.y, r.z};
}

/// The eight records at `in`, transposed into lanes.
[[WIREDEM_AVX512]] inline Records4 load_records4(const double* in)
{
    const __m512d l01 = _mm512_loadu_pd(in), l23 = _mm512_loadu_pd(in + 8);
    const __m512d l45 = _mm512_loadu_pd(in + 16), l67 = _mm512_loadu_pd(in + 24);
    const __m512i xy = lanes_of(0, 4, 8, 12, 1, 5, 9, 13), zw = lanes_of(2, 6, 10, 14, 3, 7, 11, 15);
    const __m512d xy03 = _mm512_permutex2var_pd(l01, xy, l23), xy47 = _mm512_permutex2var_pd(l45, xy, l67);
    const __m512d zw03 = _mm512_permutex2var_pd(l01, zw, l23), zw47 = _mm512_permutex2var_pd(l45, zw, l67);
    const __m512i low = lanes_of(0, 1, 2, 3, 8, 9, 10, 11), high = lanes_of(4, 5, 6, 7, 12, 13, 14, 15);
    return {_mm512_permutex2var_pd(xy03, low, xy47), _mm512_permutex2var_pd(xy03, high, xy47),
        _mm512_permutex2var_pd(zw03, low, zw47), _mm512_permutex2var_pd(zw03, high, zw47)};
}

/// The records of four doubles at `low` and `high`, one per half.
[[WIREDEM_AVX512]] inline __m512d whole_rows(const double* low, const double* high)
{
    return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(low)), _mm256_loadu_pd(high), 1);
}

/// The records of four doubles at p[l], transposed into lanes.
[[WIREDEM_AVX512]] inline Records4 load_rows4(const std::array<const double*, 8>& p)
{
    return transpose_rows(whole_rows(p[0], p[4]), whole_rows(p[1], p[5]), whole_rows(p[2], p[6]), whole_rows(p[3], p[7]));
}

/// Writes the records of the lanes in `lanes` back to `out`, only the
/// components in `components` (bit 0 x … bit 3 w) of each.
[[WIREDEM_AVX512]] inline void store_records4(double* out, __mmask8 lanes, const Records4& r, unsigned components)
{
    for (int pair = 0; pair < 4; ++pair) {
        const long long a = 2 * pair, b = a + 1;
        const __m512d xy = _mm512_permutex2var_pd(r.x, lanes_of(a, a + 8, 0, 0, b, b + 8, 0, 0), r.y);
        const __m512d zw = _mm512_permutex2var_pd(r.z, lanes_of(0, 0, a, a + 8, 0, 0, b, b + 8), r.w);
        const __m512d records = _mm512_mask_blend_pd(0xcc, xy, zw); // x y from xy, z w from zw
        const auto mask = static_cast<__mmask8>(((lanes >> a & 1u) ? components : 0u) | ((lanes >> b & 1u) ? components << 4 : 0u));
        _mm512_mask_storeu_pd(out + 8 * pair, mask, records);
    }
}

/// Writes the records of the lanes in `lanes` to out[l], only the
/// components in `components` (bit 0 x … bit 3 w) of each (store_records4's
/// transpose; each record's half of a register stored on its own).
[[WIREDEM_AVX512]] inline void store_rows4(
    const std::array<double*, 8>& out, __mmask8 lanes, const Records4& r, unsigned components)
{
    const auto keep = static_cast<__mmask8>(components);
    for (int pair = 0; pair < 4; ++pair) {
        const long long a = 2 * pair, b = a + 1;
        const __m512d xy = _mm512_permutex2var_pd(r.x, lanes_of(a, a + 8, 0, 0, b, b + 8, 0, 0), r.y);
        const __m512d zw = _mm512_permutex2var_pd(r.z, lanes_of(0, 0, a, a + 8, 0, 0, b, b + 8), r.w);
        const __m512d records = _mm512_mask_blend_pd(0xcc, xy, zw); // x y from xy, z w from zw
        if (lanes >> a & 1u) _mm256_mask_storeu_pd(out[a], keep, _mm512_castpd512_pd256(records));
        if (lanes >> b & 1u) _mm256_mask_storeu_pd(out[b], keep, _mm512_extractf64x4_pd(records, 1));
    }
}

/// Writes lane l of v to the 3-vector at out[l] (store_rows4's masked
/// stores: nothing past its third double).
[[WIREDEM_AVX512]] inline void store_vec3s_at(const std::array<double*, 8>& out, const V3& v)
{
    store_rows4(out, 0xFF, Records4{v.x, v.y, v.z, v.z}, 0x7);
}

/// Writes eight consecutive 3-vectors (x₀ y₀ z₀ x₁ … z₇, 24 doubles) from
/// lanes: three stores of v transposed in registers (AVX-512 has scatters,
/// but on this CPU they cost several times these permutes).
[[WIREDEM_AVX512]] inline void store_vec3s(double* out, const V3& v)
{
    // Each output register: x and y interleaved (index ≥ 8 picks the second
    // operand), then z put into the gaps.
    const __m512d o0 = _mm512_permutex2var_pd(
        _mm512_permutex2var_pd(v.x, lanes_of(0, 8, 0, 1, 9, 0, 2, 10), v.y), lanes_of(0, 1, 8, 3, 4, 9, 6, 7), v.z);
    const __m512d o1 = _mm512_permutex2var_pd(
        _mm512_permutex2var_pd(v.x, lanes_of(0, 3, 11, 0, 4, 12, 0, 5), v.y), lanes_of(10, 1, 2, 11, 4, 5, 12, 7), v.z);
    const __m512d o2 = _mm512_permutex2var_pd(
        _mm512_permutex2var_pd(v.x, lanes_of(13, 0, 6, 14, 0, 7, 15, 0), v.y), lanes_of(0, 13, 2, 3, 14, 5, 6, 15), v.z);
    _mm512_storeu_pd(out, o0);
    _mm512_storeu_pd(out + 8, o1);
    _mm512_storeu_pd(out + 16, o2);
}

/// The eight consecutive 3-vectors at `in` (x₀ y₀ z₀ x₁ … z₇, 24 doubles),
/// into lanes: three loads transposed in registers (store_vec3s undone).
[[WIREDEM_AVX512]] inline V3 load_consecutive_vec3s(const double* in)
{
    const __m512d a = _mm512_loadu_pd(in), b = _mm512_loadu_pd(in + 8), c = _mm512_loadu_pd(in + 16);
    // a = x0 y0 z0 x1 y1 z1 x2 y2, b = z2 x3 y3 z3 x4 y4 z4 x5, c = y5 z5 x6 y6 z6 x7 y7 z7
    const __m512d xa = _mm512_permutex2var_pd(a, lanes_of(0, 3, 6, 9, 12, 15, 0, 0), b);
    const __m512d ya = _mm512_permutex2var_pd(a, lanes_of(1, 4, 7, 10, 13, 0, 0, 0), b);
    const __m512d za = _mm512_permutex2var_pd(a, lanes_of(2, 5, 8, 11, 14, 0, 0, 0), b);
    return {_mm512_permutex2var_pd(xa, lanes_of(0, 1, 2, 3, 4, 5, 10, 13), c),
        _mm512_permutex2var_pd(ya, lanes_of(0, 1, 2, 3, 4, 8, 11, 14), c),
        _mm512_permutex2var_pd(za, lanes_of(0, 1, 2, 3, 4, 9, 12, 15), c)};
}

/// Writes eight records of eight doubles, record l = lane l of r[0] … r[7]
/// (an 8 × 8 transpose), to the 64-byte aligned out[l], for the lanes in
/// `lanes` only.
[[WIREDEM_AVX512]] inline void store_rows8(const std::array<double*, 8>& out, __mmask8 lanes, const __m512d (&r)[8])
{
    // Pairs (r[2i][k], r[2i+1][k]) in 128-bit blocks: even k, then odd k.
    const __m512d a_even = _mm512_unpacklo_pd(r[0], r[1]), a_odd = _mm512_unpackhi_pd(r[0], r[1]);
    const __m512d b_even = _mm512_unpacklo_pd(r[2], r[3]), b_odd = _mm512_unpackhi_pd(r[2], r[3]);
    const __m512d c_even = _mm512_unpacklo_pd(r[4], r[5]), c_odd = _mm512_unpackhi_pd(r[4], r[5]);
    const __m512d d_even = _mm512_unpacklo_pd(r[6], r[7]), d_odd = _mm512_unpackhi_pd(r[6], r[7]);
    // Blocks (0, 2) and (1, 3) of two registers: the pairs of k and k + 4.
    const __m512d ab04 = _mm512_shuffle_f64x2(a_even, b_even, 0x88), ab26 = _mm512_shuffle_f64x2(a_even, b_even, 0xdd);
    const __m512d ab15 = _mm512_shuffle_f64x2(a_odd, b_odd, 0x88), ab37 = _mm512_shuffle_f64x2(a_odd, b_odd, 0xdd);
    const __m512d cd04 = _mm512_shuffle_f64x2(c_even, d_even, 0x88), cd26 = _mm512_shuffle_f64x2(c_even, d_even, 0xdd);
    const __m512d cd15 = _mm512_shuffle_f64x2(c_odd, d_odd, 0x88), cd37 = _mm512_shuffle_f64x2(c_odd, d_odd, 0xdd);
    const __m512d records[8] = {_mm512_shuffle_f64x2(ab04, cd04, 0x88), _mm512_shuffle_f64x2(ab15, cd15, 0x88),
        _mm512_shuffle_f64x2(ab26, cd26, 0x88), _mm512_shuffle_f64x2(ab37, cd37, 0x88),
        _mm512_shuffle_f64x2(ab04, cd04, 0xdd), _mm512_shuffle_f64x2(ab15, cd15, 0xdd),
        _mm512_shuffle_f64x2(ab26, cd26, 0xdd), _mm512_shuffle_f64x2(ab37, cd37, 0xdd)};
    for (int l = 0; l < 8; ++l)
        if (lanes >> l & 1u) _mm512_store_pd(out[l], records[l]);
}

/// store_rows8 to eight consecutive records at `out`.
[[WIREDEM_AVX512]] inline void store_records8(double* out, __mmask8 lanes, const __m512d (&r)[8])
{
    store_rows8({out, out + 8, out + 16, out + 24, out + 32, out + 40, out + 48, out + 56}, lanes, r);
}

/// base[index of refs[l]] in lane l.
[[WIREDEM_AVX512]] inline Pd gather_by_index(const double* base, const BodyRef* refs)
{
    const __m256i index = _mm256_and_si256(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(refs)),
        _mm256_set1_epi32(static_cast<int>(BodyRef::index_mask)));
    return _mm512_i32gather_pd(index, base, 8);
}

/// base[at[l]] in lane l.
[[WIREDEM_AVX512]] inline Pd gather_at(const double* base, const std::array<std::uint32_t, 8>& at)
{
    return _mm512_i32gather_pd(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(at.data())), base, 8);
}

/// out[l] = refs[at[l]], written with one store: read back as a vector (one_kind,
/// gather_by_index), eight scalar stores stall the load until they reach the cache.
[[WIREDEM_AVX512]] inline void gather_refs(const BodyRef* refs, const std::array<std::uint32_t, 8>& at, BodyRef* out)
{
    const __m256i index = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(at.data()));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_i32gather_epi32(reinterpret_cast<const int*>(refs), index, 4));
}

/// Writes ids[l] for each lane l set in `lanes_set`, in lane order, to
/// out[0], out[1], …, and returns how many: one compress instead of a branch
/// per set lane (which lanes are set is a coin toss to the branch predictor).
/// Writes eight words at `out` whatever the count.
[[WIREDEM_AVX512]] inline std::size_t append_ids(std::uint32_t* out, const std::uint32_t* ids, std::uint32_t lanes_set)
{
    const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ids));
    const __m256i packed = _mm256_maskz_compress_epi32(static_cast<__mmask8>(lanes_set), v);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), packed);
    return static_cast<std::size_t>(std::popcount(lanes_set & 0xFFu));
}

/// The lanes whose word has a nonzero low byte (a bool stored there, the
/// rest of the word padding).
[[WIREDEM_AVX512]] inline Mask low_byte_set(Pd words)
{
    return _mm512_test_epi64_mask(_mm512_castpd_si512(words), _mm512_set1_epi64(0xFF));
}

/// Writes the lanes of `v` in `m`, in lane order, to out[0], out[1], …
/// (eight values at `out` whatever the count).
[[WIREDEM_AVX512]] inline void compress_store(double* out, Mask m, Pd v) { _mm512_storeu_pd(out, _mm512_maskz_compress_pd(m, v)); }

/// Whether the eight references at `refs` are all of the kind of the first.
[[WIREDEM_AVX512]] inline bool one_kind(const BodyRef* refs)
{
    const __m256i kind_bits = _mm256_set1_epi32(static_cast<int>(~BodyRef::index_mask));
    const __m256i kinds = _mm256_and_si256(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(refs)), kind_bits);
    return _mm256_cmpeq_epi32_mask(kinds, _mm256_set1_epi32(static_cast<int>(refs[0].bits & ~BodyRef::index_mask)))
        == 0xFF;
}

/// Bit l set where the byte flag at flags[l] is not zero.
[[WIREDEM_AVX512]] inline std::uint32_t flag_bits(const std::uint8_t* flags)
{
    const __m128i word = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(flags));
    return _mm_test_epi8_mask(word, word) & 0xFFu;
}

/// Sets the byte flags[l] to 1 for the lanes in `m`.
[[WIREDEM_AVX512]] inline void set_flags(std::uint8_t* flags, Mask m) { _mm_mask_storeu_epi8(flags, m, _mm_set1_epi8(1)); }

} // namespace wiredem::engine::avx512
