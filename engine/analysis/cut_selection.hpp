// Where to cut a wire so that it loses the least (issue 39): the places of a
// reference test where the wire's segment strain was lowest. The seed paper
// suggests that the spiral helix's wire could be cut between its loops
// without losing much strength; these functions turn a test's strain
// profile into cut positions a job takes (specimen.wire.cuts_at_m), so that
// the claim can be tested by running the cut column beside the whole one.
// `wiredem cuts` (client/cuts_command.cpp) reads the profile from a result
// file. Pure functions; deterministic (ties go to the lower segment).
#pragma once

#include "core/types.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace wiredem::engine::analysis {

/// The angle the step from `a` to `b` winds about the z axis: the angle in
/// (−π, π] between their horizontal positions [rad] (what WireCuts::every_loops
/// counts loops with).
[[nodiscard]] double winding_step_rad(const Vec3& a, const Vec3& b) noexcept;

/// The wire's rest length per loop about the column's axis: its rest length
/// (nodes − 1) l_w times 2π over the magnitude of its unwrapped winding angle
/// [m]; 0 when the wire winds less than one loop (no loop length to speak of).
[[nodiscard]] double length_per_loop_m(std::span<const Vec3> node_position_m, double segment_length_m);

/// One cut place.
struct CutPlace {
    std::uint32_t segment = 0;  ///< the segment removed
    double position_m = 0.0;    ///< (segment + ½) l_w: the rest length from the first node to its middle [m]
    double strain = 0.0;        ///< its strain in the reference profile
};

/// The `count` segments of lowest strain (signed: a slack or compressed
/// segment is lower than a stretched one) whose middles are at least
/// `min_spacing_m` apart and at least `min_spacing_m` from the wire's two
/// ends (so that no piece is shorter than that), chosen greedily from the
/// lowest up (ties: the lower segment first); segments `excluded` marks (1:
/// removed already, as State::wire_breaks) are never chosen. Returned in
/// ascending position; fewer than `count` when no more places are far
/// enough apart. min_spacing_m ≥ 0, segment_length_m > 0.
[[nodiscard]] std::vector<CutPlace> lowest_strain_cuts(std::span<const double> segment_strain, double segment_length_m,
    std::size_t count, double min_spacing_m, std::span<const std::uint8_t> excluded = {});

} // namespace wiredem::engine::analysis
