// One time step of the whole system, as an explicit list of stages.
#pragma once

#include "parallel/thread_pool.hpp"
#include "profile.hpp"
#include "state/world.hpp"

namespace wiredem::engine {

/// What a step noticed. Steps never throw: problems are flagged here.
struct StepReport {
    bool blew_up = false;             ///< a position became NaN/∞: δt too large or bad input
    bool neighbours_rebuilt = false;  ///< the neighbour list was rebuilt this step
};

/// Advances `w` by w.dt_s. Thread-count independent: the same World gives
/// bit-identical results with any pool size. With a profile, adds the time
/// spent in each Stage to it (the first step's begin_run is not charged to
/// any stage).
StepReport step(World& w, ThreadPool& pool, StepProfile* profile = nullptr);

/// Sets every body's second Gear derivative from the forces at the current
/// state (x₂ = δt²/2 · F/m, likewise for rotation). The contact stage runs
/// with MemoryUpdate::keep: no spring takes the step's slip v_t δt, so the
/// first step advances the springs once, from the stored state. What depends
/// on the positions alone is applied, as in any evaluation: contacts apart
/// are released, and wire joints bent beyond their yield angle yield (the
/// initial memory made consistent with the initial positions; applying it
/// again there changes nothing). step() does this before the first step;
/// without it Gear-5 would start from a = 0 and carry the start-up error for
/// the whole run.
void begin_run(World& w, ThreadPool& pool);

/// The force stages of a step at the current positions (neighbours,
/// contacts with `memory`, wire, membrane, gather), without moving anything:
/// begin_run's evaluation, and a test's reference for it.
void evaluate_forces(World& w, ThreadPool& pool, MemoryUpdate memory);

// The stages, in the order step() runs them; exposed for tests and benchmarks.

/// Moves walls with their prescribed velocity by one step.
void move_walls(State& s);
/// The near skin (NearPairs) as a fraction of the contact list's skin.
inline constexpr double near_skin_fraction = 0.25;
/// The near pairs are selected again once a body has moved this fraction of
/// the near skin since the last selection. Below one half: the pairs left out
/// had a gap of at least the near skin, and two bodies that each move less
/// than 0.4 of it leave at least 0.2 of it, far above the rounding of the
/// gap and move tests.
inline constexpr double near_reselect_fraction = 0.4;
/// A contact list whose last one lived fewer steps than this takes all its
/// pairs as near (NearPairs::all): where bodies cross the skin in a few
/// steps (a column being poured), selections would come every step or two
/// and cost more than they save.
inline constexpr std::uint64_t near_min_list_life_steps = 100;

/// Rebuilds the contact list (body pairs and body–wall contacts) if a body or
/// a wall moved more than half the skin since the last build, or bodies or
/// walls were added, and selects the near pairs (NearPairs) after a rebuild
/// or once a body has moved near_reselect_fraction of the near skin. Returns
/// true if it rebuilt the list.
bool update_neighbours(World& w, ThreadPool& pool);
/// Evaluates the near body pairs of the list and every body–wall contact
/// (the other listed pairs are apart until the next selection), with one
/// kernel (geometry adapters in contact/geometry.hpp, the laws of laws/; one
/// writer per contact slot), then totals each wall's force. With `keep`, the
/// contacts' memory is not advanced (ContactInputs::memory). Needs the near
/// pairs of the current list (update_neighbours).
void compute_contact_forces(World& w, ThreadPool& pool, MemoryUpdate memory = MemoryUpdate::commit);
/// Sums each body's contact, element and gravity forces in a fixed order.
void gather_forces(World& w, ThreadPool& pool);

/// Effective skin actually used [m].
[[nodiscard]] double effective_skin_m(const World& w);

} // namespace wiredem::engine
