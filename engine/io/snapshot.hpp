// Snapshot and restore of a whole World, to continue a run later or
// elsewhere (the campaign's crash resume, the cluster fan-out).
//
// The file is HDF5 (engine/io/hdf5.hpp): one dataset per field of the table
// in state/world_fields.hpp, rows × columns, doubles or 64-bit integers, and
// on the root group the attributes format = "wiredem snapshot", version, the
// number of walls and the state_hash of what was written.
//
// A restored run continues bit-identically: N steps, save, restore (in this
// or another process, with any thread count), M more steps give the same
// state_hash as N + M steps without interruption. Why, see snapshot.cpp.
#pragma once

#include "core/result.hpp"
#include "io/hdf5.hpp"
#include "state/world.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

namespace wiredem::engine {

/// Version of the snapshot layout; restore_snapshot reads this version only.
/// Bump it whenever a field is added, removed or changes meaning.
/// 3: bodies' motion types; 4: one record of outputs per contact; 5: body
/// pairs grouped by their kinds (pair_key); 6: the membrane's elements in
/// grid order, without incidence lists or per-element forces; a wire joint's
/// bending forces in three arrays; the skin the neighbour list was built with;
/// 7: the rolling law's parameters, and its springs and torques while it is on;
/// 8: a wall's own friction coefficient (Wall::friction_coeff);
/// 9: the wire's breaking strain, and its removed segments when it has any;
/// 10: clumps (rigid multi-sphere grains) while there are any.
inline constexpr std::int64_t snapshot_version = 10;

/// The group of a snapshot file that holds the host's state (below).
inline constexpr const char* snapshot_host_group = "host";

/// Writes every field of `w` to `path`, replacing the file. The file appears
/// complete or not at all (written beside it, then renamed). Returns the
/// state_hash of `w`, which the file also records.
[[nodiscard]] Result<std::uint64_t, std::string> save_snapshot(const World& w, const std::filesystem::path& path);

/// The same, with what the host needs besides the World (a test driver's
/// state, a preparation report) written by `write_host` into the group
/// "/host" of the same file, so that both appear together or not at all.
/// An exception from `write_host` becomes the error.
[[nodiscard]] Result<std::uint64_t, std::string> save_snapshot(
    const World& w, const std::filesystem::path& path, const std::function<void(io::Group&)>& write_host);

/// Reads a snapshot written by save_snapshot. Errors (no such file, not a
/// snapshot, another version, a missing or misshapen field, a state that does
/// not hash to the recorded value) are messages naming the file.
[[nodiscard]] Result<World, std::string> restore_snapshot(const std::filesystem::path& path);

/// The same, handing the group "/host" to `read_host` (an error when the file
/// has none). An exception from `read_host` becomes the error.
[[nodiscard]] Result<World, std::string> restore_snapshot(
    const std::filesystem::path& path, const std::function<void(const io::Group&)>& read_host);

} // namespace wiredem::engine
