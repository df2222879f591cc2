// AVX2 helpers for the SIMD contact kernels (contact/pair_kernel_lanes.inc):
// four lanes of doubles with the arithmetic of the scalar code, lane masks,
// and transposes between arrays of small records and lane registers. The
// counterpart of avx512.hpp for CPUs without AVX-512, with the same names,
// so one kernel text serves both. Include only in files built with
// -ffp-contract=off (no fused multiply–add: the lanes keep the scalar code's
// bits; AVX2 itself has no FMA, but the CPUs that have it have FMA too) and
// only on x86-64.
#pragma once

#include "core/types.hpp"

#include <immintrin.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>

namespace wiredem::engine::avx2 {

// Every helper is inlined into functions built for AVX2, which the CPU is
// checked for at run time (simd_isa).
#define WIREDEM_AVX2_TARGET gnu::target("avx2")
#define WIREDEM_AVX2 WIREDEM_AVX2_TARGET, gnu::always_inline

inline constexpr unsigned lanes = 4;
using Pd = __m256d;

/// A lane mask: all ones in the lanes that are set (what AVX compares give).
struct Mask {
    __m256d v;
};
[[WIREDEM_AVX2]] inline Mask operator&(Mask a, Mask b) { return {_mm256_and_pd(a.v, b.v)}; }
[[WIREDEM_AVX2]] inline Mask operator|(Mask a, Mask b) { return {_mm256_or_pd(a.v, b.v)}; }
[[WIREDEM_AVX2]] inline Mask operator^(Mask a, Mask b) { return {_mm256_xor_pd(a.v, b.v)}; }
[[WIREDEM_AVX2]] inline Mask operator~(Mask a)
{
    return {_mm256_xor_pd(a.v, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))};
}
[[WIREDEM_AVX2]] inline Mask& operator&=(Mask& a, Mask b) { return a = a & b; }
/// Bit l set for lane l.
[[WIREDEM_AVX2]] inline std::uint32_t bits(Mask m) { return static_cast<std::uint32_t>(_mm256_movemask_pd(m.v)); }
[[WIREDEM_AVX2]] inline bool none(Mask m) { return _mm256_testz_pd(m.v, m.v) != 0; }
/// The mask with lane l set where bit l of `b` is.
[[WIREDEM_AVX2]] inline Mask mask_of_bits(std::uint32_t b)
{
    const __m256i lane_bit = _mm256_setr_epi64x(1, 2, 4, 8);
    const __m256i set = _mm256_and_si256(_mm256_set1_epi64x(static_cast<long long>(b)), lane_bit);
    return {_mm256_castsi256_pd(_mm256_cmpeq_epi64(set, lane_bit))};
}
/// a ⋈ b lane by lane (P: a _CMP_… predicate).
template <int P>
[[WIREDEM_AVX2]] inline Mask compare(Pd a, Pd b)
{
    return {_mm256_cmp_pd(a, b, P)};
}

[[WIREDEM_AVX2]] inline Pd set1(double x) { return _mm256_set1_pd(x); }
[[WIREDEM_AVX2]] inline Pd zero() { return _mm256_setzero_pd(); }
[[WIREDEM_AVX2]] inline Pd sqrt(Pd a) { return _mm256_sqrt_pd(a); }
/// The second operand when either is NaN, as std::fmin(b, a) of ordered values.
[[WIREDEM_AVX2]] inline Pd min(Pd a, Pd b) { return _mm256_min_pd(a, b); }
[[WIREDEM_AVX2]] inline Pd max(Pd a, Pd b) { return _mm256_max_pd(a, b); }
/// b in the lanes of `pick`, a in the others.
[[WIREDEM_AVX2]] inline Pd blend(Mask pick, Pd a, Pd b) { return _mm256_blendv_pd(a, b, pick.v); }
/// a in the lanes of `keep`, zero in the others.
[[WIREDEM_AVX2]] inline Pd maskz(Mask keep, Pd a) { return _mm256_and_pd(keep.v, a); }
/// √a in the lanes of `m`, src in the others (the others' square roots are
/// computed and dropped: no exception is trapped).
[[WIREDEM_AVX2]] inline Pd mask_sqrt(Pd src, Mask m, Pd a) { return blend(m, src, _mm256_sqrt_pd(a)); }
/// a / b in the lanes of `m`, src in the others.
[[WIREDEM_AVX2]] inline Pd mask_div(Pd src, Mask m, Pd a, Pd b) { return blend(m, src, a / b); }
[[WIREDEM_AVX2]] inline Pd loadu(const double* p) { return _mm256_loadu_pd(p); }
[[WIREDEM_AVX2]] inline Pd load_lanes(const std::array<double, lanes>& a) { return _mm256_loadu_pd(a.data()); }
[[WIREDEM_AVX2]] inline void storeu(double* p, Pd a) { _mm256_storeu_pd(p, a); }
[[WIREDEM_AVX2]] inline void store_lanes(std::array<double, lanes>& out, Pd a) { _mm256_storeu_pd(out.data(), a); }
/// Every lane.
[[WIREDEM_AVX2]] inline Mask all_lanes() { return {_mm256_castsi256_pd(_mm256_set1_epi64x(-1))}; }
/// No lane.
[[WIREDEM_AVX2]] inline Mask no_lanes() { return {_mm256_setzero_pd()}; }

#define WIREDEM_LANES_FN WIREDEM_AVX2
#include "contact/lanes_vec3.inc"
#undef WIREDEM_LANES_FN

/// x, y and z of the Vec3 at p[l] in lane l: x y of two bodies per 256-bit
/// load, unpacked; z one by one (no load reads past a body).
[[WIREDEM_AVX2]] inline V3 load_vec3s(const std::array<const double*, lanes>& p)
{
    const __m256d xy02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p[0])), _mm_loadu_pd(p[2]), 1);
    const __m256d xy13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p[1])), _mm_loadu_pd(p[3]), 1);
    return {_mm256_unpacklo_pd(xy02, xy13), _mm256_unpackhi_pd(xy02, xy13), _mm256_setr_pd(p[0][2], p[1][2], p[2][2], p[3][2])};
}

/// 4 × 4 transpose: row l of the result is lane l of a, b, c, d.
[[WIREDEM_AVX2]] inline void transpose4(__m256d& a, __m256d& b, __m256d& c, __m256d& d)
{
    const __m256d ab_lo = _mm256_unpacklo_pd(a, b), ab_hi = _mm256_unpackhi_pd(a, b); // a0 b0 a2 b2, a1 b1 a3 b3
    const __m256d cd_lo = _mm256_unpacklo_pd(c, d), cd_hi = _mm256_unpackhi_pd(c, d);
    a = _mm256_permute2f128_pd(ab_lo, cd_lo, 0x20); // a0 b0 c0 d0
    b = _mm256_permute2f128_pd(ab_hi, cd_hi, 0x20);
    c = _mm256_permute2f128_pd(ab_lo, cd_lo, 0x31);
    d = _mm256_permute2f128_pd(ab_hi, cd_hi, 0x31);
}

/// Writes four consecutive 3-vectors (x₀ y₀ z₀ x₁ … z₃, 12 doubles) from
/// lanes: transposed in registers, then overlapping stores in order (none
/// past the twelfth double).
[[WIREDEM_AVX2]] inline void store_vec3s(double* out, const V3& v)
{
    __m256d r0 = v.x, r1 = v.y, r2 = v.z, r3 = _mm256_setzero_pd();
    transpose4(r0, r1, r2, r3); // r_l = x_l y_l z_l 0
    _mm256_storeu_pd(out, r0);
    _mm256_storeu_pd(out + 3, r1);
    _mm256_storeu_pd(out + 6, r2);
    _mm_storeu_pd(out + 9, _mm256_castpd256_pd128(r3));
    _mm_store_sd(out + 11, _mm256_extractf128_pd(r3, 1));
}

/// The four consecutive 3-vectors at `in` (x₀ y₀ z₀ x₁ … z₃, 12 doubles),
/// into lanes: four overlapping loads (none past the twelfth double)
/// transposed in registers.
[[WIREDEM_AVX2]] inline V3 load_consecutive_vec3s(const double* in)
{
    __m256d r0 = _mm256_loadu_pd(in), r1 = _mm256_loadu_pd(in + 3), r2 = _mm256_loadu_pd(in + 6);
    __m256d r3 = _mm256_permute4x64_pd(_mm256_loadu_pd(in + 8), 0x39); // z2 x3 y3 z3 → x3 y3 z3 z2
    transpose4(r0, r1, r2, r3);
    return {r0, r1, r2};
}

/// Components of four consecutive records of four doubles, one register each.
struct Records4 {
    __m256d x, y, z, w;
};

/// The records of four doubles at p[l], transposed into lanes.
[[WIREDEM_AVX2]] inline Records4 load_rows4(const std::array<const double*, lanes>& p)
{
    Records4 r{_mm256_loadu_pd(p[0]), _mm256_loadu_pd(p[1]), _mm256_loadu_pd(p[2]), _mm256_loadu_pd(p[3])};
    transpose4(r.x, r.y, r.z, r.w);
    return r;
}

/// The four consecutive records at `in`, transposed into lanes.
[[WIREDEM_AVX2]] inline Records4 load_records4(const double* in) { return load_rows4({in, in + 4, in + 8, in + 12}); }

/// Writes the records of four doubles of the lanes in `m` to out[l], only
/// the components in `components` (bit 0 x … bit 3 w) of each; the others
/// keep what out[l] holds when this is called. (A branch per lane: AVX2's
/// masked stores measured 5–12 % slower on the whole step, on AMD Zen 3.)
[[WIREDEM_AVX2]] inline void store_rows4(
    const std::array<double*, lanes>& out, Mask m, Records4 r, unsigned components)
{
    transpose4(r.x, r.y, r.z, r.w);
    const __m256d records[4] = {r.x, r.y, r.z, r.w};
    const Mask keep = mask_of_bits(components);
    const std::uint32_t write = bits(m);
    for (unsigned l = 0; l < lanes; ++l)
        if (write >> l & 1u)
            _mm256_storeu_pd(out[l], components == 0xFu ? records[l] : blend(keep, _mm256_loadu_pd(out[l]), records[l]));
}

/// Writes lane l of v to the 3-vector at out[l]: transposed in registers,
/// then two stores per vector (none past its third double).
[[WIREDEM_AVX2]] inline void store_vec3s_at(const std::array<double*, lanes>& out, const V3& v)
{
    __m256d r0 = v.x, r1 = v.y, r2 = v.z, r3 = _mm256_setzero_pd();
    transpose4(r0, r1, r2, r3); // r_l = x_l y_l z_l 0
    const __m256d rows[4] = {r0, r1, r2, r3};
    for (unsigned l = 0; l < lanes; ++l) {
        _mm_storeu_pd(out[l], _mm256_castpd256_pd128(rows[l]));
        _mm_store_sd(out[l] + 2, _mm256_extractf128_pd(rows[l], 1));
    }
}

/// store_rows4 to four consecutive records at `out`.
[[WIREDEM_AVX2]] inline void store_records4(double* out, Mask m, Records4 r, unsigned components)
{
    store_rows4({out, out + 4, out + 8, out + 12}, m, r, components);
}

/// Writes records of eight doubles, record l = lane l of r[0] … r[7], to the
/// 32-byte aligned out[l], for the lanes in `m` only.
[[WIREDEM_AVX2]] inline void store_rows8(const std::array<double*, lanes>& out, Mask m, const __m256d (&r)[8])
{
    __m256d a = r[0], b = r[1], c = r[2], d = r[3], e = r[4], f = r[5], g = r[6], h = r[7];
    transpose4(a, b, c, d);
    transpose4(e, f, g, h);
    const __m256d low[4] = {a, b, c, d}, high[4] = {e, f, g, h};
    const std::uint32_t write = bits(m);
    for (unsigned l = 0; l < lanes; ++l)
        if (write >> l & 1u) {
            _mm256_store_pd(out[l], low[l]);
            _mm256_store_pd(out[l] + 4, high[l]);
        }
}

/// store_rows8 to four consecutive records at `out`.
[[WIREDEM_AVX2]] inline void store_records8(double* out, Mask m, const __m256d (&r)[8])
{
    store_rows8({out, out + 8, out + 16, out + 24}, m, r);
}

/// base[index of refs[l]] in lane l.
[[WIREDEM_AVX2]] inline Pd gather_by_index(const double* base, const BodyRef* refs)
{
    return _mm256_setr_pd(base[refs[0].index()], base[refs[1].index()], base[refs[2].index()], base[refs[3].index()]);
}

/// base[at[l]] in lane l.
[[WIREDEM_AVX2]] inline Pd gather_at(const double* base, const std::array<std::uint32_t, 4>& at)
{
    return _mm256_setr_pd(base[at[0]], base[at[1]], base[at[2]], base[at[3]]);
}

/// out[l] = refs[at[l]], written with one store: read back as a vector (one_kind),
/// four scalar stores stall the load until they reach the cache.
[[WIREDEM_AVX2]] inline void gather_refs(const BodyRef* refs, const std::array<std::uint32_t, 4>& at, BodyRef* out)
{
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out),
        _mm_setr_epi32(static_cast<int>(refs[at[0]].bits), static_cast<int>(refs[at[1]].bits),
            static_cast<int>(refs[at[2]].bits), static_cast<int>(refs[at[3]].bits)));
}

/// For each 4-bit lane mask, the indices that move the set lanes, `width`
/// units each, to the front in lane order (the rest: `fill`).
template <class T, unsigned width>
constexpr std::array<std::array<T, 4 * width>, 16> pack_table(T fill)
{
    std::array<std::array<T, 4 * width>, 16> t{};
    for (unsigned m = 0; m < 16; ++m) {
        unsigned k = 0;
        for (unsigned l = 0; l < 4; ++l)
            if (m >> l & 1u) {
                for (unsigned b = 0; b < width; ++b) t[m][width * k + b] = static_cast<T>(width * l + b);
                ++k;
            }
        for (; k < 4; ++k)
            for (unsigned b = 0; b < width; ++b) t[m][width * k + b] = fill;
    }
    return t;
}
/// Byte shuffles (_mm_shuffle_epi8) that pack 32-bit lanes; 0x80 zeroes.
inline constexpr auto pack_lanes_table = pack_table<std::uint8_t, 4>(0x80);
/// 32-bit lane indices (_mm256_permutevar8x32) that pack doubles.
inline constexpr auto pack_doubles_table = pack_table<std::int32_t, 2>(0);

/// Writes ids[l] for each lane l set in `lanes_set`, in lane order, to
/// out[0], out[1], …, and returns how many (one shuffle, no branch per set
/// lane). Writes four words at `out` whatever the count.
[[WIREDEM_AVX2]] inline std::size_t append_ids(std::uint32_t* out, const std::uint32_t* ids, std::uint32_t lanes_set)
{
    const unsigned m = lanes_set & 0xFu;
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(ids));
    const __m128i shuffle = _mm_loadu_si128(reinterpret_cast<const __m128i*>(pack_lanes_table[m].data()));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_shuffle_epi8(v, shuffle));
    return static_cast<std::size_t>(std::popcount(m));
}

/// The lanes whose word has a nonzero low byte (a bool stored there, the
/// rest of the word padding).
[[WIREDEM_AVX2]] inline Mask low_byte_set(Pd words)
{
    const __m256i low = _mm256_and_si256(_mm256_castpd_si256(words), _mm256_set1_epi64x(0xFF));
    return ~Mask{_mm256_castsi256_pd(_mm256_cmpeq_epi64(low, _mm256_setzero_si256()))};
}

/// Writes the lanes of `v` in `m`, in lane order, to out[0], out[1], …
/// (four values at `out` whatever the count).
[[WIREDEM_AVX2]] inline void compress_store(double* out, Mask m, Pd v)
{
    const __m256i index = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(pack_doubles_table[bits(m)].data()));
    _mm256_storeu_pd(out, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), index)));
}

/// Whether the four references at `refs` are all of the kind of the first.
[[WIREDEM_AVX2]] inline bool one_kind(const BodyRef* refs)
{
    const __m128i kind_bits = _mm_set1_epi32(static_cast<int>(~BodyRef::index_mask));
    const __m128i kinds = _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(refs)), kind_bits);
    const __m128i same = _mm_cmpeq_epi32(kinds, _mm_set1_epi32(static_cast<int>(refs[0].bits & ~BodyRef::index_mask)));
    return _mm_movemask_ps(_mm_castsi128_ps(same)) == 0xF;
}

/// Bit l set where the byte flag at flags[l] is not zero.
[[WIREDEM_AVX2]] inline std::uint32_t flag_bits(const std::uint8_t* flags)
{
    std::uint32_t word = 0;
    std::memcpy(&word, flags, lanes);
    const __m128i set = _mm_cmpgt_epi8(_mm_cvtsi32_si128(static_cast<int>(word)), _mm_setzero_si128());
    return static_cast<std::uint32_t>(_mm_movemask_epi8(set)) & 0xFu;
}

/// Sets the byte flags[l] to 1 for the lanes in `m` (one word written, no
/// branch per lane).
[[WIREDEM_AVX2]] inline void set_flags(std::uint8_t* flags, Mask m)
{
    // Bit l of the index → byte l of the word.
    static constexpr std::uint32_t spread[16] = {0x00000000, 0x00000001, 0x00000100, 0x00000101, 0x00010000,
        0x00010001, 0x00010100, 0x00010101, 0x01000000, 0x01000001, 0x01000100, 0x01000101, 0x01010000, 0x01010001,
        0x01010100, 0x01010101};
    std::uint32_t word = 0;
    std::memcpy(&word, flags, lanes);
    word |= spread[bits(m)];
    std::memcpy(flags, &word, lanes);
}

} // namespace wiredem::engine::avx2
