// The triaxial test's parameters that a job gives as they are (triaxial.hpp):
// one definition, which the engine's TriaxialSettings and the job spec's
// "triaxial" object (api/job_spec.hpp, TriaxialSpec) both are, so that
// nothing copies them field by field. Apart from triaxial.hpp so that the
// api's headers can name it without the driver. The defaults are the job
// spec's (the model's); the ranges in [brackets] are the job spec's
// (api/job_spec.cpp), the rules after them the engine's own (settings_error).
#pragma once

#include "triaxial/consolidation_kind.hpp"

#include <optional>
#include <vector>

namespace wiredem::engine {

struct TriaxialParams {
    // A constructor, so that this is no aggregate: GCC 12 at -O3 took the
    // snapshot_strains of an aggregate base in a temporary JobSpec{} for
    // uninitialised (-Wmaybe-uninitialized).
    TriaxialParams() = default;
    double target_axial_strain = 0.1;     ///< loading stops when ε_a reaches this, (0, 0.5]; in (0, 1)
    /// σ₃ rises from 0 to the target over this time as ½(1 − cos(π t/T)), a
    /// ramp without a jump in rate at either end [s], [0, 1e3]; 0: a step.
    double pressure_ramp_time_s = 0.05;
    /// σ₃ held (the top plate consolidating the column, `consolidation`)
    /// before loading [s], [0, 1e3].
    double hold_time_s = 0.05;
    /// The hold lasts at least hold_time_s and goes on until the column has
    /// consolidated (consolidated_mismatch), at most this long [s],
    /// [0, 1e3], ≥ hold_time_s; nullopt: default_max_hold_factor × hold_time_s.
    std::optional<double> max_hold_time_s;
    Consolidation consolidation = Consolidation::effective; ///< what σ₁ is brought to before loading
    double sample_interval_s = 1e-2;      ///< time between rows of the time series [s], (0, 1e3]
    /// Axial strains at which to take snapshots, [0, 0.5] each, strictly
    /// increasing. The engine always adds 0 (loading start) and the target,
    /// and clamps values outside [0, target]; the job's reader refuses them,
    /// and fills {0, target/2, target} when the JSON has none.
    std::vector<double> snapshot_strains{0.0, 0.05, 0.1};
    friend bool operator==(const TriaxialParams&, const TriaxialParams&) = default;
};

} // namespace wiredem::engine
