// The specimen's size that a job gives as it is (preparation.hpp): one
// definition, which the engine's PreparationSpec and the job spec's
// "specimen" object (api/job_spec.hpp, SpecimenSpec) both are, so that
// nothing copies it field by field. The defaults are the job spec's (the
// model's, the model spec §2 and §8); the ranges are the job spec's
// (api/job_spec.cpp).
#pragma once

#include <cstdint>

namespace wiredem::engine {

struct SpecimenSize {
    double membrane_radius_m = 0.02;   ///< R, the membrane's radius [m]
    double membrane_height_m = 0.12;   ///< H_m, the membrane's height [m]
    /// N_p, the grains poured. 8000, not the paper's 1000: the model spec §8.
    std::uint64_t grain_count = 8000;
    double grain_radius_m = 1.23e-3;   ///< r_p, the grains' mean radius [m]
    /// s: radii uniform in r_p (1 ± s); 0 = monodisperse. A grain-size curve
    /// (PreparationSpec::grain_sizes) replaces r_p and s for the sizes.
    double grain_radius_spread = 0.0;
    friend bool operator==(const SpecimenSize&, const SpecimenSize&) = default;
};

} // namespace wiredem::engine
