// The kinds of wire-deployment pattern (the model spec §5): the engine's
// vocabulary, which the job spec reads its "specimen.wire.pattern" into
// directly (api/job_spec.hpp). Apart from pattern.hpp so that the api's
// headers can name it without the pattern code (and Eigen).
#pragma once


namespace wiredem::engine {

/// How the nozzle lays the wire. JSON (and pattern_name): "none", "helix",
/// "spiral_helix", "radial_helix", "toolpath".
enum class PatternKind {
    none,          ///< no wire
    helix,         ///< circle of radius R_a rising at v_z
    spiral_helix,  ///< circle of radius R_i whose centre travels on the circle R_a
    radial_helix,  ///< circle R_a with a radial excursion to the axis every φ_rs
    toolpath,      ///< the robot's own path: a polyline per layer (PatternSpec::toolpath)
};

} // namespace wiredem::engine
