// Mohr–Coulomb envelope across triaxial tests of one specimen (the model spec §7).
//
// Each test contributes its peak state (σ₁, σ₃), i.e. a Mohr circle with centre
// p = (σ₁ + σ₃)/2 and radius t = (σ₁ − σ₃)/2. A straight line t = a + p·tan α
// through the circle tops (the points (p, t)) is fitted by least squares; a line
// τ = c + σ·tan φ tangent to every circle then has sin φ = tan α and
// c = a / cos φ. With one test only, c is fixed at 0 and sin φ = t/p.
//
// That line is unconstrained: on a few noisy circles it can meet σ = 0 below
// zero (c < 0: a tensile strength a gravel column does not have) or fall
// (φ < 0), and through two circles it is exact whatever they are. So each fit
// says what it is (its caveats, each with a sentence a reader can act on) and
// carries, beside it, two constrained fits of the same line by least squares
// on the same tangency condition t = c cos φ + p sin φ: the best line with
// a ≥ 0 and tan α ≥ 0 (c ≥ 0, φ ≥ 0), and the one-parameter line through the
// origin (c = 0): tan α = Σ p t / Σ p². The front ends read all of them from
// summary.json; none recomputes a fit.
//
// Compression is positive. Pure function: no I/O, no global state, thread safe.
#pragma once

#include "core/result.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace wiredem::engine::analysis {

/// Peak (yield) state of one triaxial test.
struct PeakState {
    double sigma1_pa = 0.0; ///< σ₁ at the peak of q, axial [Pa], compression positive
    double sigma3_pa = 0.0; ///< σ₃, confining [Pa], compression positive
};

/// One Mohr circle, i.e. one point of the (p, t) fit.
struct MohrCircle {
    double centre_pa = 0.0; ///< p = (σ₁ + σ₃)/2 [Pa]
    double radius_pa = 0.0; ///< t = (σ₁ − σ₃)/2 [Pa]
};

/// What could make a reader misread an unconstrained fit (docs/model.md,
/// "Reading the Mohr-Coulomb fit").
enum class FitCaveat : std::uint8_t {
    single_pressure,         ///< one circle: c = 0 was imposed, φ is that circle's
    two_pressures,           ///< two circles: the line is exact whatever they are; no R²
    narrow_band,             ///< the centres span less than their distance from σ = 0: c is a long extrapolation
    negative_cohesion,       ///< c < 0: the line meets σ = 0 below zero
    negative_friction_angle, ///< φ < 0: the circle tops fall as the pressure rises
};

/// "single_pressure", "two_pressures", "narrow_band", "negative_cohesion",
/// "negative_friction_angle": the codes summary.json lists.
[[nodiscard]] const char* to_string(FitCaveat caveat) noexcept;

/// One straight envelope τ = c + σ tan φ with the line t = a + p·tan α
/// through the circle tops it comes from (sin φ = tan α, c = a / cos φ).
struct MohrEnvelope {
    double friction_angle_rad = 0.0; ///< φ = asin(tan α) [rad]
    double cohesion_pa = 0.0;        ///< c = a / cos φ [Pa]
    double intercept_pa = 0.0;       ///< a [Pa]
    double slope = 0.0;              ///< tan α
    /// 1 − SS_res/SS_tot of the circle tops (SS_tot about their mean t̄, the same
    /// for every fit of one set, so a constrained fit's R² is below the free
    /// fit's and may be negative). Empty when the fit leaves no degree of
    /// freedom (as many circles as free parameters): any such line is exact.
    std::optional<double> r_squared;
};

/// The envelope and the fit it came from.
struct MohrCoulombFit {
    double friction_angle_rad = 0.0;     ///< φ = asin(tan α) [rad]
    double cohesion_pa = 0.0;            ///< c = a / cos φ [Pa]; may come out negative for poor data
    bool cohesion_fixed_at_zero = false; ///< true with a single test: c = 0 was imposed, not fitted

    double intercept_pa = 0.0; ///< a, intercept of t = a + p·tan α [Pa]
    double slope = 0.0;        ///< tan α, slope of the line through the circle tops

    /// α = atan(tan α) [rad]: the angle of the line through the circle tops. The paper
    /// reads this figure as the friction angle; reported so the two can be compared
    /// (the model spec §7). Always ≤ φ for 0 < tan α < 1.
    double paper_top_line_angle_rad = 0.0;

    /// Coefficient of determination of the (p, t) fit, 1 − SS_res/SS_tot; 1 when the
    /// fit is exact (including two tests). Empty with a single test (nothing to fit).
    std::optional<double> r_squared;

    std::vector<MohrCircle> circles; ///< one per test, in input order

    /// What to tell a reader of the figures above, in the order of FitCaveat.
    std::vector<FitCaveat> caveats;
    /// The least-squares line with c ≥ 0 and φ ≥ 0 (a ≥ 0, tan α ≥ 0): the free
    /// fit when that satisfies both, else the better of the fits on the two
    /// bounds (a = 0 with tan α = max(0, Σ p t / Σ p²); tan α = 0 with a = t̄).
    MohrEnvelope nonnegative;
    /// The one-parameter line through the origin: c = 0, tan α = Σ p t / Σ p².
    MohrEnvelope cohesionless;
};

/// The free fit's figures as a MohrEnvelope (its R² as the fit reports it).
[[nodiscard]] MohrEnvelope free_envelope(const MohrCoulombFit& fit) noexcept;

/// One sentence on `caveat` for a reader of `fit`, with the figures it is
/// about and the constrained fits to read instead ("negative cohesion c =
/// -2.1 kPa: ..."). Plain ASCII (warnings are printed by the client too).
[[nodiscard]] std::string describe(FitCaveat caveat, const MohrCoulombFit& fit);

/// Fits the Mohr–Coulomb envelope to the peak states of tests at several confining
/// pressures (one specimen). Errors, as a message naming the test and the value:
/// no tests; a non-finite stress; σ₁ < σ₃; a single test with p ≤ 0; two or more
/// tests that all have the same centre p (slope undefined); |tan α| ≥ 1 (no real φ),
/// of the free fit or of a constrained one (possible only when some σ₃ ≤ 0).
[[nodiscard]] Result<MohrCoulombFit, std::string> fit_mohr_coulomb(std::span<const PeakState> peaks);

/// The unconfined compressive strength the envelope predicts [Pa]: the σ₁ of
/// the circle through σ₃ = 0 that touches τ = c + σ tan φ,
/// 2c cos φ / (1 − sin φ) (docs/model.md, "The free-standing test"). NaN for
/// φ ≥ 90° or a non-finite input; negative when c is.
[[nodiscard]] double unconfined_strength_pa(double friction_angle_rad, double cohesion_pa) noexcept;

/// Centre and radius of the Mohr circle of one peak state. No checks.
[[nodiscard]] MohrCircle mohr_circle(const PeakState& peak) noexcept;

} // namespace wiredem::engine::analysis
