// Reading a strength off a triaxial test's loading curves (docs/model.md,
// "How yield is read").
//
// A granular column under a flexible membrane does not always have a peak of q
// inside the strain range: the membrane stiffens as it bulges, σ₃,eff grows,
// and q can rise to the last sample although the packing itself has yielded.
// The stress ratio η = (σ₁ − σ₃)/(σ₁ + σ₃) = sin φ_mob, the friction the
// packing mobilises, does not grow with the confinement, so yield is read at
// the maximum of η, with the Mohr circle of that state (σ₁, σ₃,eff). The
// maximum of q is reported beside it.
//
// A DEM curve is noisy (force chains buckle one at a time), so both curves are
// judged after a centred moving average over a fixed width of axial strain,
// and every reading says what kind of maximum it is:
//   peak     the maximum is followed by a drop of more than the tolerance
//            (relative to the maximum) by the end of the test;
//   plateau  no such drop, and the curve rose by no more than the tolerance
//            over the last end window of strain: the maximum is the plateau;
//   rising   it rose by more than the tolerance over that window: the value at
//            the end is a lower bound, not a strength.
// Pure functions, thread safe, deterministic (fixed summation order).
#pragma once

#include "core/result.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace wiredem::engine::analysis {

/// What kind of maximum a loading curve has.
enum class CurveShape : std::uint8_t { peak, plateau, rising };

/// "peak", "plateau" or "rising".
[[nodiscard]] const char* to_string(CurveShape shape) noexcept;

/// How a curve is judged. The defaults are the project's definition; a
/// summary states them with every figure.
struct CurveTolerances {
    /// Width of the centred moving average, in axial strain. 0.5 % averages
    /// over ~0.5 mm of plate travel on a 10 cm column: several slip events,
    /// still much narrower than a peak of a dense packing (1–3 % wide).
    double smoothing_strain = 0.005;
    /// A drop after the maximum, or a rise over the end window, counts when it
    /// is more than this fraction of the maximum: 5 %, above the spread that
    /// remains in the smoothed curves of a few thousand grains.
    double shape_tolerance = 0.05;
    /// Strain window at the end of the test over which a still rising curve
    /// is recognised, and the residual (large-strain) value is averaged.
    double end_window_strain = 0.02;
};

/// A centred moving average of `value` over `width` of `strain`: sample i is
/// the mean of the finite samples j with |strain_j − strain_i| ≤ width/2
/// (to rounding)
/// (NaN when none is finite). `strain` must be non-decreasing (loading).
[[nodiscard]] std::vector<double> smooth_over_strain(
    std::span<const double> strain, std::span<const double> value, double width);

/// The maximum of one smoothed loading curve and what kind it is.
struct CurveReading {
    CurveShape shape = CurveShape::rising;
    std::size_t index = 0;        ///< sample of the smoothed maximum (first of equals)
    double value = 0.0;           ///< smoothed curve at that sample
    double end_value = 0.0;       ///< smoothed curve at the last sample
    /// (value − end_value)/|value|: the drop after the maximum, relative.
    double drop = 0.0;
    /// Rise over the end window, relative to |value|.
    double end_rise = 0.0;
};

/// Reads an already smoothed curve. Errors: sizes differ, no sample, strain
/// decreasing, no finite value, a maximum of 0 (no scale for the tolerance).
[[nodiscard]] Result<CurveReading, std::string> read_curve(
    std::span<const double> strain, std::span<const double> smoothed, const CurveTolerances& tol = {});

/// The strength of one test, from its loading samples.
struct StrengthReading {
    /// The maximum of the stress ratio η of the smoothed σ₁ and σ₃,eff: the
    /// yield state.
    CurveReading stress_ratio;
    double yield_axial_strain = 0.0;  ///< ε_a at that sample
    double yield_sigma1_pa = 0.0;     ///< smoothed σ₁ there [Pa]: its Mohr circle …
    double yield_sigma3_pa = 0.0;     ///< … with the smoothed σ₃,eff [Pa]
    /// The maximum of the smoothed q and its kind (the raw maximum of q is
    /// reported by the test itself).
    CurveReading deviatoric;
    /// Mean of the raw η over the end window: the large-strain (residual) ratio.
    double residual_stress_ratio = 0.0;
};

/// Reads the strength of one test from its loading samples (strain
/// non-decreasing, σ's in Pa, compression positive). Errors as read_curve.
[[nodiscard]] Result<StrengthReading, std::string> read_strength(std::span<const double> axial_strain,
    std::span<const double> sigma1_pa, std::span<const double> sigma3_pa, const CurveTolerances& tol = {});

} // namespace wiredem::engine::analysis
