// The free-standing test's parameters that a job gives as they are
// (free_standing.hpp): one definition, which the engine's
// FreeStandingSettings and the job spec's "free_standing" object
// (api/job_spec.hpp, FreeStandingSpec) both are, so that nothing copies them
// field by field. Apart from free_standing.hpp so that the api's headers can
// name it without the driver. The defaults are the job spec's; the ranges
// in [brackets] are the job spec's (api/job_spec.cpp), the rules after them
// the engine's own (free_standing_settings_error).
#pragma once

namespace wiredem::engine {

struct FreeStandingParams {
    /// The formwork opens over this time [s], (0, 1e3]: the membrane's
    /// radius grows at removal_distance_m / removal_time_s (docs/model.md: a
    /// column the membrane squeezed gains at most 2 M v² of kinetic energy
    /// from a removal at speed v).
    double removal_time_s = 0.02;
    /// How far the membrane's radius opens, and the top plate rises [m], (0, 1].
    double removal_distance_m = 5e-3;
    /// At rest when the kinetic energy per grain (the preparation's
    /// criterion, settling_energy_j, masses scaled by s only) is below this
    /// × density_scale [J], (0, 1].
    double settle_kinetic_energy_per_grain_j = 1e-9;
    double max_settling_time_s = 0.5;     ///< settling ends here even if not at rest [s], (0, 1e4]
    /// The column stands when it came to rest with a loss of its grains'
    /// bulk height (H_b before − H_b after)/H_b before of at most this, in
    /// (0, 1), and with at most max_lost_fraction of its grains lost.
    double max_height_loss = 0.1;
    /// q of the bulk height H_b = z_q / q (bulk_height_m), in [0.5, 1].
    double bulk_fraction = 0.95;
    /// The column stands only if at most this share of its grains' volume
    /// left it (beyond the escape distance), in [0, 1).
    double max_lost_fraction = 0.1;
    double plate_speed_m_per_s = 1e-3;    ///< top plate speed in compression [m/s], (0, 10]
    double target_axial_strain = 0.1;     ///< compression ends here at the latest, (0, 0.5]
    /// The column has failed when its axial stress, averaged over the rows of
    /// the last smoothing_strain of axial strain, has stayed below (1 − this)
    /// of the largest such average over the last end_window_strain of strain
    /// (analysis::CurveTolerances), in (0, 1]; 1: compress to the target.
    double failure_drop = 0.5;
    double sample_interval_s = 1e-3;      ///< time between rows [s], (0, 1e3]
    friend bool operator==(const FreeStandingParams&, const FreeStandingParams&) = default;
};

} // namespace wiredem::engine
