// Compiled with -ffp-contract=off (engine/CMakeLists.txt): see the header.
#include "contact/gather_simd.hpp"

#include "contact/pair_kernel_simd.hpp"

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#endif

#include <algorithm>

namespace wiredem::engine {
namespace {

#if defined(__x86_64__)

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized" // GCC 12's intrinsics, as in lanes_for_each_isa.inc

static_assert(offsetof(ContactOutput, force_n) == 0 && offsetof(ContactOutput, overlap_m) == 3 * sizeof(double)
              && offsetof(ContactOutput, normal_x_tangential_n) == 4 * sizeof(double) && alignof(ContactOutput) >= 32);

/// x y z of v, 0.
[[WIREDEM_AVX2]] inline __m256d load3(const Vec3& v)
{
    return _mm256_setr_pd(v.x(), v.y(), v.z(), 0.0);
}

/// x y z of a into v.
[[WIREDEM_AVX2]] inline void store3(Vec3& v, __m256d a)
{
    _mm_storeu_pd(v.data(), _mm256_castpd256_pd128(a));
    _mm_store_sd(v.data() + 2, _mm256_extractf128_pd(a, 1));
}

template <bool rotates>
[[WIREDEM_AVX2_TARGET]] void gather_avx2(const GatherInputs& in, std::size_t begin, std::size_t end)
{
    const ContactList& c = *in.contacts;
    // Each record as eight doubles (force_n at offset 0; no record at all for
    // a body kind without contacts).
    const auto* records = reinterpret_cast<const double*>(c.output.data());
    const __m256d half = _mm256_set1_pd(0.5);
    // Incidence::sign(), read from a table by side().
    static constexpr double signs[2] = {1.0, -1.0};
    const avx2::V3 gravity = avx2::broadcast(in.gravity_m_per_s2);
    for (std::size_t i = begin; i < end; ++i) {
        // Four bodies without a contact (most wire and membrane nodes): m g
        // (+ extra), and no torque, four at a time in the same operations.
        if (i + 4 <= end && in.incidence_start[in.flat_offset + i] == in.incidence_start[in.flat_offset + i + 4]) {
            const __m256d m = _mm256_loadu_pd(in.mass_kg + i);
            avx2::V3 f{m * gravity.x, m * gravity.y, m * gravity.z};
            if (in.extra_force_n != nullptr) f = f + avx2::load_consecutive_vec3s(in.extra_force_n[i].data());
            avx2::store_vec3s(in.force_n[i].data(), f);
            if constexpr (rotates) std::fill(in.torque_n_m + i, in.torque_n_m + i + 4, Vec3::Zero());
            i += 3;
            continue;
        }
        // f = m g, then ± each contact's force in incidence order; the lever
        // arm r − ξ/2 as the scalar gather writes it.
        const Vec3 weight = in.mass_kg[i] * in.gravity_m_per_s2;
        __m256d f = load3(weight);
        __m256d tau = _mm256_setzero_pd();
        const __m256d r = _mm256_set1_pd(in.radius_m[i]);
        const std::uint32_t last = in.incidence_start[in.flat_offset + i + 1];
        for (std::uint32_t e = in.incidence_start[in.flat_offset + i]; e < last; ++e) {
            const Incidence link = in.incidence[e];
            const double* record = records + 8 * std::size_t{link.contact()};
            const __m256d force_overlap = _mm256_load_pd(record);
            f = f + _mm256_broadcast_sd(&signs[link.side()]) * force_overlap;
            if constexpr (rotates) {
                const __m256d overlap = _mm256_broadcast_sd(record + 3); // ξ, loaded again rather than shuffled
                tau = tau + (r - half * overlap) * _mm256_load_pd(record + 4);
                if (in.rolling_torque_n_m != nullptr)
                    tau = tau + _mm256_broadcast_sd(&signs[link.side()]) * load3(in.rolling_torque_n_m[link.contact()]);
            }
        }
        if (in.extra_force_n != nullptr) f = f + load3(in.extra_force_n[i]);
        store3(in.force_n[i], f);
        if constexpr (rotates) store3(in.torque_n_m[i], tau);
    }
}

[[WIREDEM_AVX2_TARGET]] void gather_block_avx2(const GatherInputs& in, std::size_t begin, std::size_t end)
{
    if (in.torque_n_m != nullptr) gather_avx2<true>(in, begin, end);
    else gather_avx2<false>(in, begin, end);
}

#pragma GCC diagnostic pop

#endif

} // namespace

SimdGather simd_gather()
{
#if defined(__x86_64__)
    if (simd_isa() != SimdIsa::none) return &gather_block_avx2;
#endif
    return nullptr;
}

} // namespace wiredem::engine
