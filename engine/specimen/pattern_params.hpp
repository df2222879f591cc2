// How the nozzle lays the wire, as a job gives it (pattern.hpp,
// PatternSpec): one definition, which the engine's PatternSpec and the job
// spec's specimen.wire object (api/job_spec.hpp, WireSpec) both are, so that
// nothing copies it field by field; the names are the job's. The defaults
// are the job spec's (the paper's nozzle in a 20 mm-radius membrane, the
// model spec §5); the ranges are the job spec's (api/job_spec.cpp). A
// pattern ignores the parameters it does not use.
#pragma once

#include "specimen/pattern_kind.hpp"

#include <numbers>

namespace wiredem::engine {

struct PatternParams {
    PatternKind pattern = PatternKind::helix;  ///< the nozzle's path; helix: the simplest of the paper
    double nozzle_rise_speed_m_per_s = 0.5;    ///< v_z^w, the nozzle's largest rise speed [m/s]
    double angular_speed_rad_per_s = 300.0;    ///< ω [rad/s]; the path speed is ω R_a
    double helix_radius_m = 12e-3;             ///< R_a [m]; 0.6 R for the 20 mm column
    double inner_radius_m = 4e-3;              ///< R_i, spiral_helix only [m]
    double period_angle_rad = std::numbers::pi / 2; ///< φ_rs, spiral_helix and radial_helix only [rad]
    friend bool operator==(const PatternParams&, const PatternParams&) = default;
};

} // namespace wiredem::engine
