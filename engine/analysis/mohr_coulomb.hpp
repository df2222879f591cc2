// Mohr–Coulomb envelope across triaxial tests of one specimen (the model spec §7).
//
// Each test contributes its peak state (σ₁, σ₃), i.e. a Mohr circle with centre
// p = (σ₁ + σ₃)/2 and radius t = (σ₁ − σ₃)/2. A straight line t = a + p·tan α
// through the circle tops (the points (p, t)) is fitted by least squares; a line
// τ = c + σ·tan φ tangent to every circle then has sin φ = tan α and
// c = a / cos φ. With one test only, c is fixed at 0 and sin φ = t/p.
//
// Compression is positive. Pure function: no I/O, no global state, thread safe.
#pragma once

#include "core/result.hpp"

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
};

/// Fits the Mohr–Coulomb envelope to the peak states of tests at several confining
/// pressures (one specimen). Errors, as a message naming the test and the value:
/// no tests; a non-finite stress; σ₁ < σ₃; a single test with p ≤ 0; two or more
/// tests that all have the same centre p (slope undefined); |tan α| ≥ 1 (no real φ).
[[nodiscard]] Result<MohrCoulombFit, std::string> fit_mohr_coulomb(std::span<const PeakState> peaks);

/// Centre and radius of the Mohr circle of one peak state. No checks.
[[nodiscard]] MohrCircle mohr_circle(const PeakState& peak) noexcept;

} // namespace wiredem::engine::analysis
