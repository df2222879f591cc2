// Compiled with -ffp-contract=off (as every file, CMakeLists.txt), like the
// grains' turn (rotation_simd.cpp): four clumps per AVX2 instruction, eight
// per AVX-512 one, each lane doing the scalar code's operations in Eigen's
// order.
#include "integrate/clump_simd.hpp"

#include "contact/pair_kernel_simd.hpp"
#include "integrate/rotation.hpp"

#include <array>

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#include "contact/avx512.hpp"
#endif

namespace wiredem::engine {
namespace {

/// Clump i's spheres put at p.orientation[i], one by one (the lanes' scalar twin).
void place_one(const ClumpPlacement& p, std::size_t i)
{
    const Quat q = p.orientation[i];
    const Vec3 centre = p.centre[i], velocity = p.velocity[i];
    const Vec3 spin = q * p.omega1[i]; // δt ω in space
    const std::uint32_t end = p.first_member[i] + p.member_count[i];
    for (std::uint32_t g = p.first_member[i]; g < end; ++g) {
        const Vec3 arm = p.arms_in != nullptr ? p.arms_in[g] : Vec3(q * p.offset[g]);
        if (p.arms_out != nullptr) p.arms_out[g] = arm;
        p.x0[g] = centre + arm;
        p.x1[g] = velocity + spin.cross(arm); // δt (v + ω × r)
        p.theta1[g] = spin;
    }
}

/// gear_turns of clump i.
Vec3 gear_turn(const Vec3* const* w, bool forwards, std::size_t i)
{
    const Vec3 w1 = w[1][i], w2 = w[2][i];
    const Vec3 magnus = w1.cross(w2) / 6.0; // (δt³/12) ω × ω̇ in scaled derivatives
    return forwards ? Vec3(w1 + w2 + w[3][i] + w[4][i] + w[5][i] + magnus)
                    : Vec3(w1 - w2 + w[3][i] - w[4][i] + w[5][i] + magnus);
}

/// clump_kicks of clump i.
void kick_one(const ClumpLoadSums& s, const ClumpKick& k, std::size_t i, Vec3& x2, Vec3& w2)
{
    sum_clump_loads(s, i);
    x2 = k.half_dt2 / s.mass[i] * s.force_out[i];
    const Vec3& inertia = k.inertia[i];
    w2 = k.half_dt2 * (k.orientation[i].conjugate() * s.torque_out[i]).cwiseQuotient(inertia);
    if (k.gyroscopic) {
        const Vec3& w1 = k.omega1[i];
        w2 -= 0.5 * w1.cross(inertia.cwiseProduct(w1)).cwiseQuotient(inertia);
    }
}

#if defined(__x86_64__)

static_assert(sizeof(Quat) == 4 * sizeof(double), "a Quat is its coefficients x y z w");

// One kernel text, two instruction sets.
#define WIREDEM_LANES_KERNELS "integrate/clump_lanes.inc"
#include "contact/lanes_for_each_isa.inc"

/// Items [i, n) `lanes` at a time: block(i) does what it can of items
/// [i, i + lanes) and returns those it did (bit l: item i + l); one(j) does
/// item j, for the others.
template <std::size_t lanes, class Block, class One>
void lanes_or_one(std::size_t& i, std::size_t n, Block&& block, One&& one)
{
    constexpr std::uint32_t all = (1u << lanes) - 1u;
    for (; i + lanes <= n; i += lanes) {
        const std::uint32_t done = block(i);
        if (done != all)
            for (std::size_t l = 0; l < lanes; ++l)
                if (!(done >> l & 1u)) one(i + l);
    }
}

/// Clumps [i, e) `lanes` at a time (block(i, count)) where `lanes`
/// consecutive clumps have as many spheres each, the others one by one
/// (one(i)).
template <std::size_t lanes, class Block, class One>
void equal_counts_or_one(const std::uint32_t* member_count, std::size_t& i, std::size_t e, Block&& block, One&& one)
{
    while (i + lanes <= e) {
        const std::uint32_t count = member_count[i];
        bool same = true;
        for (std::size_t l = 1; l < lanes; ++l) same = same && member_count[i + l] == count;
        if (same) {
            block(i, count);
            i += lanes;
        } else {
            one(i);
            ++i;
        }
    }
}

#endif

} // namespace

void sum_clump_loads(const ClumpLoadSums& s, std::size_t i)
{
    Vec3 f = s.gravity_acts ? Vec3(s.mass[i] * s.gravity) : Vec3::Zero();
    Vec3 tau = Vec3::Zero();
    const std::uint32_t end = s.first_member[i] + s.member_count[i];
    for (std::uint32_t m = s.first_member[i]; m < end; ++m) {
        f += s.force[m];
        const Vec3 arm = s.arms != nullptr ? s.arms[m] : Vec3(s.orientation[i] * s.offset[m]);
        tau += arm.cross(s.force[m]) + s.torque[m];
    }
    s.force_out[i] = f;
    s.torque_out[i] = tau;
}

void clump_kicks(const ClumpLoadSums& s, const ClumpKick& k, std::size_t b, std::size_t e, Vec3* x2, Vec3* w2)
{
    const auto one = [&](std::size_t j) { kick_one(s, k, j, x2[j - b], w2[j - b]); };
    std::size_t i = b;
    if (s.arms != nullptr)
        WIREDEM_WITH_SIMD_ISA(isa, equal_counts_or_one<isa::lanes>(
            s.member_count, i, e,
            [&](std::size_t j, std::uint32_t count) { isa::kicks_block(s, k, j, count, x2 + (j - b), w2 + (j - b)); },
            one));
    for (; i < e; ++i) one(i);
}

void gear_turns(const Vec3* const* w, bool forwards, std::size_t b, std::size_t e, Vec3* turn)
{
    std::size_t i = b;
    WIREDEM_WITH_SIMD_ISA(
        isa, for (; i + isa::lanes <= e; i += isa::lanes) isa::gear_turns_block(w, forwards, i, turn + (i - b)));
    for (; i < e; ++i) turn[i - b] = gear_turn(w, forwards, i);
}

/// The free rotation of one step split along the principal axes (Verlet's
/// drift, the symmetric splitting z y x y z): each part turns q about a body
/// axis k by φ = fraction × ω_k δt and the body-frame angular momentum
/// L = I w₁ the opposite way. A turn about a body axis, (c, s e_k) with
/// c = cos(φ/2), s = sin(φ/2), has two zero components, so each part is
/// written out: q ⊗ (c, s e_k) is eight products, L turns by −φ in the plane
/// normal to e_k (cos φ = 1 − 2s², sin φ = 2cs) and keeps L_k. L is carried
/// across the five parts and made w₁ once, with 1/I; q is normalised once
/// after them (each part is a unit quaternion to rounding). Until
/// 2026-12-07 each part was a quaternion product, a normalisation, a
/// vector turn and three divisions (the same splitting; other roundings,
/// bench/README.md "Verlet's clump drift, rolling in lanes").
void free_rotation(Quat& q, Vec3& w1, const Vec3& inertia)
{
    constexpr int axis[5] = {2, 1, 0, 1, 2};
    constexpr double fraction[5] = {0.5, 0.5, 1.0, 0.5, 0.5};
    const Vec3 inv_inertia = inertia.cwiseInverse();
    Vec3 l = inertia.cwiseProduct(w1);
    double qw = q.w();
    Vec3 qv = q.vec();
    for (int part = 0; part < 5; ++part) {
        const int k = axis[part], i = (k + 1) % 3, j = (k + 2) % 3; // (i, j, k) right-handed
        const double phi = fraction[part] * (l[k] * inv_inertia[k]);
        const HalfAngle h = half_angle(phi * phi);
        const double c = h.cos_half, s = h.sin_half_over_angle * phi;
        // q ⊗ (c, s e_k): w = c q_w − s q_k, v = c q_v + s q_w e_k + s q_v × e_k.
        const double w = c * qw - s * qv[k];
        const double vi = c * qv[i] + s * qv[j], vj = c * qv[j] - s * qv[i], vk = c * qv[k] + s * qw;
        qw = w;
        qv[i] = vi, qv[j] = vj, qv[k] = vk;
        // L in the body frame turned by −φ about e_k.
        const double cos_phi = 1.0 - 2.0 * s * s, sin_phi = 2.0 * c * s;
        const double li = cos_phi * l[i] + sin_phi * l[j], lj = cos_phi * l[j] - sin_phi * l[i];
        l[i] = li, l[j] = lj;
    }
    q = Quat(qw, qv.x(), qv.y(), qv.z()).normalized();
    w1 = l.cwiseProduct(inv_inertia);
}

void turn_clumps(const Quat* q, const Vec3* theta, Quat* out, std::size_t n)
{
    const auto turn_one = [&](std::size_t j) { out[j] = (q[j] * rotation_quaternion(theta[j])).normalized(); };
    std::size_t i = 0;
    WIREDEM_WITH_SIMD_ISA(isa, lanes_or_one<isa::lanes>(
        i, n, [&](std::size_t j) { return isa::turn_after_block(q + j, theta + j, out + j); }, turn_one));
    for (; i < n; ++i) turn_one(i);
}

void free_rotations(Quat* q, Vec3* w1, const Vec3* inertia, std::size_t n)
{
    const auto one = [&](std::size_t j) { free_rotation(q[j], w1[j], inertia[j]); };
    std::size_t i = 0;
    WIREDEM_WITH_SIMD_ISA(isa, lanes_or_one<isa::lanes>(
        i, n, [&](std::size_t j) { return isa::free_rotation_block(q + j, w1 + j, inertia + j); }, one));
    for (; i < n; ++i) one(i);
}

void place_clumps(const ClumpPlacement& p, std::size_t b, std::size_t e)
{
    const auto one = [&](std::size_t j) { place_one(p, j); };
    std::size_t i = b;
    WIREDEM_WITH_SIMD_ISA(isa, equal_counts_or_one<isa::lanes>(
        p.member_count, i, e, [&](std::size_t j, std::uint32_t count) { isa::place_block(p, j, count); }, one));
    for (; i < e; ++i) one(i);
}

} // namespace wiredem::engine
