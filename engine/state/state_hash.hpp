// A fingerprint of what a step advances, to check that runs are bit-identical
// (any thread count, a restored snapshot against an uninterrupted run).
#pragma once

#include "state/world.hpp"

#include <cstdint>

namespace wiredem::engine {

/// FNV-1a over every field whose role is FieldRole::state (world_fields.hpp):
/// every body's position and scaled derivatives, the grains' rotations and
/// orientations, the contact memory (tangential springs and touching flags of
/// pairs and of walls), the wire's rest angles, the walls' positions and
/// velocities, δt and the clock. Each field contributes its length and its
/// numbers' bytes, so ±0 and NaN payloads count: equal hashes mean equal bits.
/// The pair springs are hashed in list order: two runs compare equal when
/// their neighbour lists (a cache) are equal too, as in identical histories.
[[nodiscard]] std::uint64_t state_hash(const World& w);

} // namespace wiredem::engine
