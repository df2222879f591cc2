// Named grain presets (specimen.grain_preset; issue 40, part 4): a real
// material's grain shape, grading and contact friction under one name, so a
// user selects "gravel" instead of writing five fields. The values live here
// only; the reader expands a preset into the fields it names
// (apply_grain_preset in job_spec.cpp) and refuses any of them given beside
// it, and the writer writes the name instead of them, so a job file reads the
// same before and after a round trip. docs/model.md ("A calibrated gravel")
// gives the sources and the calibration runs behind each number; a change
// of a value changes every stored job that names the preset, so a new
// calibration gets a new name ("gravel-2"), never new numbers under an old one.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace wiredem::api {

/// The grain presets. JSON: "none", "gravel".
enum class GrainPreset : std::uint8_t {
    none,    ///< no preset: the fields as given (the seed paper's spheres by default)
    gravel,  ///< crushed gravel 8/32, calibrated against its angle of repose (docs/model.md)
};

/// What a preset sets. The grading is a sieve analysis by mass as a lab
/// reports it (sieve apertures in mm); a job scales it so that its mass
/// median D50 is 2 × specimen.grain_radius_m, the grain size the column is
/// built around (a column of real 8/32 gravel is hundreds of grains wide;
/// the models' columns are a few: docs/model.md says what that leaves out).
struct GrainPresetValues {
    std::string_view name;            ///< its JSON name
    std::string_view clump_template;  ///< specimen.grain_shape's built-in template
    /// The sieve curve: apertures [mm], strictly increasing, and the mass
    /// fraction passing each, 0 at the first and 1 at the last.
    std::array<double, 5> sieve_mm;
    std::array<double, 5> fraction_passing;
    double friction_coeff;            ///< contact.friction_coeff, μ
    double rolling_friction_coeff;    ///< contact.rolling_friction_coeff, μ_r
    double rolling_damping_ratio;     ///< contact.rolling_damping_ratio, η_r
};

/// The crushed gravel 8/32: the built-in "crushed" clump (five spheres,
/// no symmetry), a grading 8–31.5 mm with C_u = 2.0 and D50 = 17.9 mm
/// (15 % passing 11.2 mm, 40 % 16 mm, 70 % 22.4 mm: the middle of an
/// 8/32 concrete or drainage gravel's band), μ = 0.6 (rock on rock), and
/// μ_r calibrated so that a heap of it stands at the angle of repose of
/// crushed rock, 38–42°, in the model's small columns; its triaxial friction
/// angle is not calibrated (docs/model.md, "A calibrated gravel", which
/// records the runs and what they leave out).
inline constexpr GrainPresetValues gravel_preset{
    "gravel",
    "crushed",
    {8.0, 11.2, 16.0, 22.4, 31.5},
    {0.0, 0.15, 0.40, 0.70, 1.0},
    0.6,
    0.35,
    0.3,
};

/// The values of a preset; nullptr for GrainPreset::none.
[[nodiscard]] constexpr const GrainPresetValues* grain_preset_values(GrainPreset p)
{
    return p == GrainPreset::gravel ? &gravel_preset : nullptr;
}

} // namespace wiredem::api
