// Formwork, the first phase of every column test: what becomes of the rigid
// membrane the column was prepared in (engine/specimen/preparation.hpp).
//
// Triaxial test (engine/triaxial/triaxial.hpp): the membrane becomes the
// cell's deformable sheet. A prepared membrane is usually taller than the
// column, and the plates are infinite planes: a free membrane node above the
// top plate would be pushed through it. As in a real cell, where the membrane
// is sealed to the top cap, every membrane node within its contact radius of
// the top plate or above it is clamped to the cap when the test starts: held
// (not integrated) and carried with the plate's velocity.
//
// Free-standing test (engine/triaxial/free_standing.hpp): the formwork goes.
// The membrane's radius opens at a constant speed (its nodes move radially
// outwards, kinematic: nothing the column does slows them), so the column
// loses its lateral support gradually instead of in one step that would
// turn the elastic energy of its squeeze into a kick; then the membrane
// stops and no longer touches the grains or the wire.
#pragma once

#include "state/world.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace wiredem::engine {

/// Makes the membrane deformable and clamps the nodes within their contact
/// radius of the top plate or above it to the plate (kinematic, at rest).
/// @return the clamped nodes, in id order
[[nodiscard]] std::vector<std::uint32_t> seal_membrane_to_cap(World& w, std::size_t top_plate_wall);

/// Gives the clamped nodes the top plate's velocity for the next step.
void carry_with_cap(World& w, const std::vector<std::uint32_t>& cap_nodes, std::size_t top_plate_wall);

/// Sets every membrane node moving radially outwards at `speed_m_per_s`
/// (kinematic; a node on the axis stays).
void open_formwork(World& w, double speed_m_per_s);

/// Stops the membrane's nodes (fixed) and turns off its contacts with the
/// grains and the wire: the formwork is gone.
void close_formwork(World& w);

} // namespace wiredem::engine
