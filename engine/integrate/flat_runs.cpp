#include "integrate/flat_runs.hpp"

#include "contact/pair_kernel_simd.hpp"

#include <bit>
#include <cstdint>

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#endif

namespace wiredem::engine {
namespace {

[[gnu::always_inline]] inline bool all_finite_loop(const double* v, std::size_t n)
{
    std::uint64_t non_finite = 0;
    for (std::size_t j = 0; j < n; ++j) non_finite |= non_finite_bit(v[j]);
    return non_finite == 0;
}

/// The Vec3 expression δt²/2 · inv_mass · load, operation for operation.
[[gnu::always_inline]] inline void scale_loop(
    const double* __restrict inv_mass, const Vec3* __restrict load, double half_dt2, std::size_t n, Vec3* __restrict out)
{
    for (std::size_t i = 0; i < n; ++i) out[i] = half_dt2 * inv_mass[i] * load[i];
}

bool all_finite_baseline(const double* v, std::size_t n) { return all_finite_loop(v, n); }
void scale_baseline(const double* inv_mass, const Vec3* load, double half_dt2, std::size_t n, Vec3* out)
{
    scale_loop(inv_mass, load, half_dt2, n, out);
}
#if defined(__x86_64__)
[[WIREDEM_AVX2_TARGET]] bool all_finite_avx2(const double* v, std::size_t n) { return all_finite_loop(v, n); }
[[WIREDEM_AVX2_TARGET]] void scale_avx2(const double* inv_mass, const Vec3* load, double half_dt2, std::size_t n, Vec3* out)
{
    scale_loop(inv_mass, load, half_dt2, n, out);
}
#endif

} // namespace

bool all_finite(const double* v, std::size_t n)
{
#if defined(__x86_64__)
    if (simd_isa() != SimdIsa::none) return all_finite_avx2(v, n);
#endif
    return all_finite_baseline(v, n);
}

void scale_accelerations(const double* inv_mass, const Vec3* load, double half_dt2, std::size_t n, Vec3* out)
{
#if defined(__x86_64__)
    if (simd_isa() != SimdIsa::none) return scale_avx2(inv_mass, load, half_dt2, n, out);
#endif
    scale_baseline(inv_mass, load, half_dt2, n, out);
}

} // namespace wiredem::engine
