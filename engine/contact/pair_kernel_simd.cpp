// Compiled with -ffp-contract=off (engine/CMakeLists.txt): see the header for
// why the lanes give the scalar law's bits.
#include "contact/pair_kernel_simd.hpp"

#include "state/world.hpp"

#include <array>
#include <atomic>
#include <cstddef>

#if defined(__x86_64__)
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

std::atomic<SimdKernels> chosen_kernels{SimdKernels::automatic};

#if defined(__x86_64__)

// GCC 12's own intrinsics (gathers, square roots, max, unpacks, inserts)
// start from an "undefined" register that -W(maybe-)uninitialized reports
// when inlined.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"

using namespace avx512;

// The loads below read Vec3 arrays as doubles with a stride of 3, the
// contact list's ids as 32-bit words and its springs with a stride of 4.
static_assert(sizeof(Vec3) == 3 * sizeof(double));
static_assert(sizeof(BodyRef) == sizeof(std::uint32_t));
static_assert(sizeof(TangentialState) == 4 * sizeof(double) && offsetof(TangentialState, spring_m) == 0);

/// base[idx[l]] in lane l.
[[WIREDEM_AVX512]] inline __m512d gather(const double* base, __m256i idx) { return _mm512_i32gather_pd(idx, base, 8); }

/// The spin of a body that does not turn: the scalar path's zero vector.
constexpr double no_spin[3] = {0.0, 0.0, 0.0};

/// One side of eight contacts whose bodies are all of one kind (nearly every
/// block: the list groups the pairs by their kinds), read by index from that
/// kind's arrays.
struct KindLanes {
    const BodyRef* refs;
    const Vec3* x_;
    const Vec3* v_dt_;
    const double* radius_;
    const Vec3* spin_dt_;  ///< nullptr: a kind that does not turn

    [[WIREDEM_AVX512]] KindLanes(const BodyRef* refs_, const ContactInputs& in, BodyKind kind)
        : refs(refs_)
        , x_(in.x[static_cast<std::size_t>(kind)])
        , v_dt_(in.v_dt[static_cast<std::size_t>(kind)])
        , radius_(in.radius[static_cast<std::size_t>(kind)])
        , spin_dt_(kind == BodyKind::grain ? in.spin_dt : nullptr)
    {
    }
    [[WIREDEM_AVX512]] V3 vec3s(const Vec3* base) const
    {
        std::array<const double*, simd_pair_lanes> at;
        for (std::size_t l = 0; l < simd_pair_lanes; ++l) at[l] = base[refs[l].index()].data();
        return load_vec3s(at);
    }
    [[WIREDEM_AVX512]] V3 x() const { return vec3s(x_); }
    [[WIREDEM_AVX512]] V3 v_dt() const { return vec3s(v_dt_); }
    /// A kind that does not turn has the scalar path's zero spin.
    [[WIREDEM_AVX512]] V3 spin_dt() const
    {
        if (spin_dt_ == nullptr) return {_mm512_setzero_pd(), _mm512_setzero_pd(), _mm512_setzero_pd()};
        return vec3s(spin_dt_);
    }
    [[WIREDEM_AVX512]] __m512d radius() const
    {
        const __m256i index = _mm256_and_si256(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(refs)),
            _mm256_set1_epi32(static_cast<int>(BodyRef::index_mask)));
        return gather(radius_, index);
    }
};

/// One side of eight contacts whose bodies may be of any kind (grains, wire
/// nodes, membrane nodes): each lane read from its kind's arrays.
struct AnyLanes {
    const BodyRef* refs;
    const ContactInputs& in;

    [[WIREDEM_AVX512]] V3 vec3s(const std::array<const Vec3*, body_kind_count>& base) const
    {
        std::array<const double*, simd_pair_lanes> at;
        for (std::size_t l = 0; l < simd_pair_lanes; ++l)
            at[l] = base[static_cast<std::size_t>(refs[l].kind())][refs[l].index()].data();
        return load_vec3s(at);
    }
    [[WIREDEM_AVX512]] V3 x() const { return vec3s(in.x); }
    [[WIREDEM_AVX512]] V3 v_dt() const { return vec3s(in.v_dt); }
    [[WIREDEM_AVX512]] V3 spin_dt() const
    {
        std::array<const double*, simd_pair_lanes> at;
        for (std::size_t l = 0; l < simd_pair_lanes; ++l)
            at[l] = refs[l].kind() == BodyKind::grain ? in.spin_dt[refs[l].index()].data() : no_spin;
        return load_vec3s(at);
    }
    [[WIREDEM_AVX512]] __m512d radius() const
    {
        alignas(64) std::array<double, simd_pair_lanes> r;
        for (std::size_t l = 0; l < simd_pair_lanes; ++l)
            r[l] = in.radius[static_cast<std::size_t>(refs[l].kind())][refs[l].index()];
        return _mm512_load_pd(r.data());
    }
};

/// Whether the eight references at `refs` are all of the kind of the first.
[[WIREDEM_AVX512]] inline bool one_kind(const BodyRef* refs)
{
    const __m256i kind_bits = _mm256_set1_epi32(static_cast<int>(~BodyRef::index_mask));
    const __m256i kinds = _mm256_and_si256(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(refs)), kind_bits);
    return _mm256_cmpeq_epi32_mask(kinds, _mm256_set1_epi32(static_cast<int>(refs[0].bits & ~BodyRef::index_mask)))
        == 0xFF;
}

/// The springs δ of eight consecutive contacts (32 bytes each: x y z and the
/// word holding `sticking`), transposed into lanes.
[[WIREDEM_AVX512]] inline V3 load_springs(const TangentialState* t)
{
    const Records4 r = load_records4(t->spring_m.data());
    return {r.x, r.y, r.z};
}

/// Writes the springs of the lanes in `lanes`, leaving every `sticking` word.
[[WIREDEM_AVX512]] inline void store_springs(TangentialState* t, __mmask8 lanes, const V3& v)
{
    store_records4(t->spring_m.data(), lanes, {v.x, v.y, v.z, v.z}, 0x7);
}

/// What evaluate_contact does for a contact that is apart: the slots of the
/// lanes in `apart` that touched are cleared (masks, not a branch per lane:
/// which lanes are apart is a coin toss to the branch predictor, and its
/// misses cost more than the arithmetic).
[[WIREDEM_AVX512]] inline void clear_opened(ContactList& c, std::size_t p, __mmask8 apart)
{
    const __m128i touching = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(&c.touching[p]));
    const auto opened = static_cast<__mmask8>(apart & _mm_test_epi8_mask(touching, touching));
    if (opened != 0)
        for (unsigned l = 0; l < simd_pair_lanes; ++l)
            if (opened >> l & 1u) {
                c.tangential[p + l] = TangentialState{};
                c.output[p + l] = ContactOutput{};
                c.touching[p + l] = 0;
            }
}

/// The rest of evaluate_contact for the overlapping lanes in `lanes`, from
/// their geometry (normal from first to second, overlap ξ, velocity of
/// first's contact point relative to second's): the laws, then the slots.
/// Returns the lanes done: those whose branch was certain.
[[WIREDEM_AVX512]] inline __mmask8 evaluate_lanes(ContactList& c, std::size_t p, __mmask8 lanes, const V3& normal,
    __m512d overlap, const V3& velocity, const ContactInputs& in)
{
    const __m512d zero = _mm512_setzero_pd();
    std::uint32_t sticking_bits = 0;
    for (unsigned l = 0; l < simd_pair_lanes; ++l)
        sticking_bits |= static_cast<std::uint32_t>(c.tangential[p + l].sticking) << l;
    const auto sticking = static_cast<__mmask8>(sticking_bits);

    // Normal force: damped_hertz_force_n; max(0, f) is std::max(f, 0.0).
    const __m512d rate = dot(velocity, normal);
    const V3 vt = velocity - rate * normal;
    const __m512d k = _mm512_loadu_pd(&c.hertz_coefficient[p]);
    const __m512d fn =
        _mm512_max_pd(zero, k * _mm512_sqrt_pd(overlap) * (overlap + _mm512_set1_pd(in.damping_s) * rate));

    // Tangential force: tangential_force, every branch computed and blended.
    const TangentialParams& tp = in.tangential;
    const __m512d mu = _mm512_set1_pd(tp.friction_coeff), gamma = _mm512_set1_pd(tp.damping_s_per_m);
    const __m512d dt = _mm512_set1_pd(in.dt);
    const V3 old_spring = load_springs(&c.tangential[p]);
    const __m512d speed = _mm512_sqrt_pd(dot(vt, vt));
    // A sliding contact slides on while γ_t |v_t| > μ and v_t has not turned back.
    const __mmask8 slides_on = static_cast<__mmask8>(~sticking) & _mm512_cmp_pd_mask(gamma * speed, mu, _CMP_GT_OQ)
                             & _mm512_cmp_pd_mask(dot(vt, old_spring), zero, _CMP_GE_OQ);
    // Sticking: the spring turned into the tangent plane at its length. A
    // sliding contact that stops sticks with a new spring (δ_t = 0).
    V3 spring = old_spring - dot(old_spring, normal) * normal;
    const __m512d new_len2 = dot(spring, spring);
    const __mmask8 turned = _mm512_cmp_pd_mask(new_len2, zero, _CMP_GT_OQ);
    const __m512d one = _mm512_set1_pd(1.0);
    // × 1 leaves a lane that the scalar law does not rescale unchanged.
    spring = _mm512_mask_sqrt_pd(one, turned, _mm512_mask_div_pd(one, turned, dot(old_spring, old_spring), new_len2))
           * spring;
    spring = masked(sticking, spring);
    spring = spring + dt * vt;
    const V3 held = (_mm512_set1_pd(-tp.stiffness_per_m) * fn) * spring;
    const __m512d coulomb = mu * fn;
    const __m512d critical = _mm512_set1_pd(tp.critical_slip_m);
    const __m512d held2 = dot(held, held), spring2 = dot(spring, spring);
    const __mmask8 holds = _mm512_cmp_pd_mask(held2, coulomb * coulomb, _CMP_LE_OQ)
                         & _mm512_cmp_pd_mask(spring2, critical * critical, _CMP_LE_OQ);
    const __mmask8 breaks = _mm512_cmp_pd_mask(held2, coulomb * coulomb, _CMP_GT_OQ)
                          | _mm512_cmp_pd_mask(spring2, critical * critical, _CMP_GT_OQ);
    // Dynamic friction, F_t = −F_n min(μ, γ_t |v_t|) v̂_t (0 at rest); the
    // slip v_t δt is kept to tell a reversal. min(γ|v|, μ) is std::fmin(μ, γ|v|).
    const __mmask8 slides = slides_on | (static_cast<__mmask8>(~slides_on) & breaks);
    const __m512d f = fn * _mm512_min_pd(gamma * speed, mu);
    const __mmask8 moves = _mm512_cmp_pd_mask(speed, zero, _CMP_GT_OQ);
    const __m512d per_speed = -f / speed;
    const V3 dynamic = masked(moves, per_speed * vt);
    const V3 slip = dt * vt;
    const V3 tangential = blend(slides, held, dynamic);
    spring = blend(slides, spring, slip);
    // Every lane whose branch is certain (ordered comparisons; a NaN or an
    // unordered break test goes to the scalar law).
    lanes &= slides_on | holds | breaks;
    lanes &= _mm512_cmp_pd_mask(speed, speed, _CMP_ORD_Q);
    if (lanes == 0) return 0;
    // Contacts that start or stop sliding change their flag.
    // The slots, as evaluate_contact writes them.
    if (in.memory == MemoryUpdate::commit) {
        const auto flips = static_cast<__mmask8>(lanes & (sticking ^ static_cast<__mmask8>(~slides)));
        if (flips != 0)
            for (unsigned l = 0; l < simd_pair_lanes; ++l)
                if (flips >> l & 1u) c.tangential[p + l].sticking = !(slides >> l & 1u);
        store_springs(&c.tangential[p], lanes, spring);
    }
    const V3 force = -fn * normal + tangential, normal_x_tangential = cross(normal, tangential);
    const __m512d output[8] = {force.x, force.y, force.z, normal_x_tangential.x, normal_x_tangential.y, normal_x_tangential.z, overlap, fn};
    static_assert(offsetof(ContactOutput, normal_x_tangential_n) == 3 * sizeof(double)
                  && offsetof(ContactOutput, overlap_m) == 6 * sizeof(double)
                  && offsetof(ContactOutput, normal_force_n) == 7 * sizeof(double));
    store_records8(c.output[p].force_n.data(), lanes, output);
    _mm_mask_storeu_epi8(&c.touching[p], lanes, _mm_set1_epi8(1));
    return lanes;
}


/// Sphere–sphere geometry (sphere_sphere_geometry, operation for operation)
/// of eight body pairs, then the law.
template <class Lanes>
[[WIREDEM_AVX512]] inline std::uint32_t pair_lanes(ContactList& c, std::size_t p, const Lanes& a, const Lanes& b,
    const ContactInputs& in)
{
    const V3 xa = a.x(), xb = b.x();
    const __m512d ra = a.radius(), rb = b.radius();
    const V3 d = xb - xa;
    const __m512d dist2 = dot(d, d);
    const __m512d reach = ra + rb;
    const __m512d zero = _mm512_setzero_pd();
    const __m512d reach2 = reach * reach;

    // Apart (dist² ≥ (r_a + r_b)² or coincident).
    const __mmask8 apart = _mm512_cmp_pd_mask(dist2, reach2, _CMP_GE_OQ) | _mm512_cmp_pd_mask(dist2, zero, _CMP_EQ_OQ);
    clear_opened(c, p, apart);
    const __mmask8 lanes = _mm512_cmp_pd_mask(dist2, reach2, _CMP_LT_OQ) & _mm512_cmp_pd_mask(dist2, zero, _CMP_NEQ_OQ);
    if (lanes == 0) return apart;
    const __m512d half = _mm512_set1_pd(0.5);
    const __m512d dist = _mm512_sqrt_pd(dist2);
    const __m512d overlap = reach - dist;
    const V3 normal = (_mm512_set1_pd(1.0) / dist) * d;
    const __m512d arm_a = ra - half * overlap, arm_b = rb - half * overlap;
    const V3 va = a.v_dt(), vb = b.v_dt();
    const V3 wa = a.spin_dt(), wb = b.spin_dt();
    const V3 velocity = _mm512_set1_pd(in.inv_dt) * ((va - vb) + cross(arm_a * wa + arm_b * wb, normal));

    return apart | evaluate_lanes(c, p, lanes, normal, overlap, velocity, in);
}

[[gnu::target("avx512f,avx512vl,avx512bw")]] std::uint32_t pair_block_avx512(ContactList& c, std::size_t p, const ContactInputs& in)
{
    const BodyRef *first = &c.first[p], *second = &c.second[p];
    if (one_kind(first) && one_kind(second))
        return pair_lanes(c, p, KindLanes(first, in, first[0].kind()), KindLanes(second, in, second[0].kind()), in);
    return pair_lanes(c, p, AnyLanes{first, in}, AnyLanes{second, in}, in);
}

/// Sphere–wall geometry (wall_gap, sphere_wall_geometry) of eight contacts
/// of one wall, then the same law.
template <class Lanes>
[[WIREDEM_AVX512]] inline std::uint32_t wall_lanes(
    ContactList& c, std::size_t p, const Wall& wall, const Lanes& body, const ContactInputs& in)
{
    const V3 x = body.x();
    const __m512d r = body.radius();
    const __m512d zero = _mm512_setzero_pd();
    const V3 point = {_mm512_set1_pd(wall.point_m.x()), _mm512_set1_pd(wall.point_m.y()), _mm512_set1_pd(wall.point_m.z())};
    __m512d gap;
    V3 towards;
    if (wall.shape == Wall::Shape::plane) {
        const V3 n = {_mm512_set1_pd(wall.normal.x()), _mm512_set1_pd(wall.normal.y()), _mm512_set1_pd(wall.normal.z())};
        gap = dot(x - point, n);
        towards = {-n.x, -n.y, -n.z};
    } else {
        // |radial| with radial.z = 0: (x² + y²) + 0·0, as Eigen's norm sums.
        const V3 radial = {x.x - point.x, x.y - point.y, zero};
        const __m512d rho = _mm512_sqrt_pd(dot(radial, radial));
        gap = _mm512_set1_pd(wall.radius_m) - rho;
        const __mmask8 off_axis = _mm512_cmp_pd_mask(rho, zero, _CMP_GT_OQ);
        towards = {_mm512_mask_div_pd(_mm512_set1_pd(1.0), off_axis, radial.x, rho),
            _mm512_mask_div_pd(zero, off_axis, radial.y, rho), _mm512_mask_div_pd(zero, off_axis, radial.z, rho)};
    }
    const __m512d overlap = r - gap;
    // Apart when r − gap ≤ 0 (ordered: a NaN goes to the scalar law).
    const __mmask8 apart = _mm512_cmp_pd_mask(overlap, zero, _CMP_LE_OQ);
    clear_opened(c, p, apart);
    const __mmask8 lanes = _mm512_cmp_pd_mask(overlap, zero, _CMP_GT_OQ);
    if (lanes == 0) return apart;
    const __m512d arm = r - _mm512_set1_pd(0.5) * overlap;
    const __m512d inv_dt = _mm512_set1_pd(in.inv_dt);
    const V3 v = body.v_dt(), spin = body.spin_dt();
    const V3 wall_v = {_mm512_set1_pd(wall.velocity_m_per_s.x()), _mm512_set1_pd(wall.velocity_m_per_s.y()),
        _mm512_set1_pd(wall.velocity_m_per_s.z())};
    const V3 velocity = (inv_dt * v + arm * cross(inv_dt * spin, towards)) - wall_v;
    return apart | evaluate_lanes(c, p, lanes, towards, overlap, velocity, in);
}

[[gnu::target("avx512f,avx512vl,avx512bw")]] std::uint32_t wall_block_avx512(
    ContactList& c, std::size_t p, const Wall& wall, const ContactInputs& in)
{
    const BodyRef* first = &c.first[p];
    if (one_kind(first)) return wall_lanes(c, p, wall, KindLanes(first, in, first[0].kind()), in);
    return wall_lanes(c, p, wall, AnyLanes{first, in}, in);
}

#pragma GCC diagnostic pop

#endif

} // namespace

ContactInputs contact_inputs(const World& w)
{
    ContactInputs in;
    for (int k = 0; k < body_kind_count; ++k) {
        in.x[k] = w.bodies[k].x[0].data();
        in.v_dt[k] = w.bodies[k].x[1].data();
        in.radius[k] = w.bodies[k].radius_m.data();
    }
    in.spin_dt = w.grain_rotation.theta[1].data();
    in.inv_dt = 1.0 / w.dt_s;
    in.dt = w.dt_s;
    in.damping_s = w.contact.normal_damping_s;
    in.tangential = w.contact.tangential;
    return in;
}

void set_simd_kernels(SimdKernels kernels) { chosen_kernels.store(kernels, std::memory_order_relaxed); }

bool simd_kernels_in_use()
{
    if (chosen_kernels.load(std::memory_order_relaxed) == SimdKernels::scalar) return false;
#if defined(__x86_64__)
    static const bool has_avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl")
                                   && __builtin_cpu_supports("avx512bw");
    return has_avx512;
#else
    return false;
#endif
}

SimdPairKernel simd_pair_kernel()
{
#if defined(__x86_64__)
    if (simd_kernels_in_use()) return &pair_block_avx512;
#endif
    return nullptr;
}

SimdWallKernel simd_wall_kernel()
{
#if defined(__x86_64__)
    if (simd_kernels_in_use()) return &wall_block_avx512;
#endif
    return nullptr;
}

} // namespace wiredem::engine
