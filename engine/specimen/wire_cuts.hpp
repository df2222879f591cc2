// Cutting a prepared wire before a test (issue 39): at given positions along
// the wire, or after every k loops around the column's axis. A cut removes a
// segment (forces/wire_forces.hpp, cut_wire_segment): the chain falls into
// pieces (wire_pieces), each with two free ends.
#pragma once

#include "core/result.hpp"
#include "state/world.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace wiredem::engine {

/// Where to cut the wire.
struct WireCuts {
    /// Positions along the wire, as the rest length from its first node [m],
    /// ≥ 0: the segment s with s l_w ≤ position < (s + 1) l_w is removed.
    std::vector<double> at_m;
    /// After every this many loops around the column's axis (the z axis
    /// through x = y = 0); 0: none. The winding angle of the nodes about the
    /// axis, unwrapped along the wire (each step between two nodes taken as
    /// the angle in (−π, π] between their horizontal positions): the segment
    /// across which |angle| passes k·2π, 2k·2π, … is removed.
    std::uint64_t every_loops = 0;
};

/// The segments `cuts` asks for in `w`'s wire, ascending, each once.
/// Errors: a position past the wire's last segment (naming its index in
/// cuts.at_m, the position and the wire's rest length).
[[nodiscard]] Result<std::vector<std::uint32_t>, std::string> wire_cut_segments(const World& w, const WireCuts& cuts);

/// Cuts those segments (the ones not removed already), recorded as cuts at
/// the World's time. Returns how many it cut; errors as wire_cut_segments',
/// with nothing cut.
[[nodiscard]] Result<std::size_t, std::string> cut_wire(World& w, const WireCuts& cuts);

} // namespace wiredem::engine
