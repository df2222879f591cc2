#include "step.hpp"

#include "contact/gather_simd.hpp"
#include "contact/geometry.hpp"
#include "contact/pair_kernel_simd.hpp"
#include "core/assert.hpp"
#include "forces/membrane_forces.hpp"
#include "forces/wire_forces.hpp"
#include "integrate/clumps.hpp"
#include "integrate/gear5.hpp"
#include "integrate/verlet.hpp"
#include "laws/hertz.hpp"
#include "laws/rolling.hpp"
#include "laws/tangential.hpp"
#include "parallel/body_blocks.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <utility>

namespace wiredem::engine {
void evaluate_forces(World& w, ThreadPool& pool, MemoryUpdate memory)
{
    update_neighbours(w, pool);
    compute_contact_forces(w, pool, memory);
    compute_wire_forces(w, pool);
    compute_membrane_forces(w, pool);
    gather_forces(w, pool);
}

void begin_run(World& w, ThreadPool& pool)
{
    evaluate_forces(w, pool, MemoryUpdate::keep);

    invalidate_prediction(w); // x₂ changes
    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    for (int k = 0; k < body_kind_count; ++k) {
        TranslationalState& body = w.bodies[k];
        const std::vector<Vec3>& force = w.body_force_n[k];
        parallel_for(pool, body.size(), [&](std::size_t i) {
            if (is_dynamic(body, i)) body.x[2][i] = half_dt2 * body.inv_mass_per_kg[i] * force[i];
        });
    }
    RotationalState& rot = w.grain_rotation;
    parallel_for(pool, rot.orientation.size(), [&](std::size_t i) {
        if (is_dynamic(w.of(BodyKind::grain), i)) rot.theta[2][i] = half_dt2 * rot.inv_inertia_per_kg_m2[i] * w.grain_torque_n_m[i];
    });
    clump_initial_accelerations(w, pool);
}

StepReport step(World& w, ThreadPool& pool, StepProfile* profile)
{
    StepReport report;
    const bool gear = w.integrator == Integrator::gear5;
    if (w.step_count == 0) begin_run(w, pool); // a(0) from the forces
    StageClock clock(profile);
    if (gear) gear5_predict(w, pool);                    // every moving body
    else verlet_first_half(w, pool);
    clock.lap(Stage::predict);
    move_walls(w);                                       // prescribed plate motion
    clock.lap(Stage::move_walls);
    report.neighbours_rebuilt = update_neighbours(w, pool); // cell grid + skin, only when needed
    clock.lap(Stage::neighbours);
    compute_contact_forces(w, pool);                     // pairs and walls: Hertz + tangential, one slot each
    clock.lap(Stage::contacts);
    compute_wire_forces(w, pool);                        // stretch + bending, one slot per element
    clock.lap(Stage::wire);
    compute_membrane_forces(w, pool);                    // edge springs + σ₃·A per triangle
    clock.lap(Stage::membrane);
    gather_forces(w, pool);                              // per body, fixed order
    clock.lap(Stage::gather);
    report.blew_up = !(gear ? gear5_correct(w, pool) : verlet_second_half(w, pool));
    clock.lap(Stage::correct);
    if (profile) ++profile->steps;
    w.time_s += w.dt_s;
    ++w.step_count;
    return report;
}

void move_walls(State& s)
{
    for (Wall& wall : s.walls) wall.point_m += wall.velocity_m_per_s * s.dt_s;
}

double effective_skin_m(const World& w)
{
    if (w.skin_m > 0.0) return w.skin_m;
    // The largest radius, over four running maxima that do not wait on each
    // other (radii are positive: the order of max() does not matter).
    std::array<double, 4> r_max{};
    for (const auto& body : w.bodies) {
        const std::vector<double>& r = body.radius_m;
        std::size_t i = 0;
        for (; i + 4 <= r.size(); i += 4)
            for (std::size_t l = 0; l < 4; ++l) r_max[l] = std::max(r_max[l], r[i + l]);
        for (; i < r.size(); ++i) r_max[0] = std::max(r_max[0], r[i]);
    }
    return 0.2 * std::max(std::max(r_max[0], r_max[1]), std::max(r_max[2], r_max[3]));
}

namespace {

/// Whether any body has moved half the skin since the contact list's build
/// (`list`; looked at only if `check_list`) and near_reselect_fraction of
/// the near skin since the near pairs' selection (`near`; only if
/// `check_near`), in one pass over the positions. Each is an or of
/// comparisons, with no chain of maxima that wait on each other: the same
/// test as the largest move's.
struct Moves {
    bool list = false, near = false;
};
Moves body_moves(const World& w, ThreadPool& pool, bool check_list, bool check_near)
{
    const double limit2 = 0.25 * w.skin_at_build_m * w.skin_at_build_m;
    const double near_limit = near_reselect_fraction * w.near.skin_m;
    const double near_limit2 = near_limit * near_limit;
    // Every kind's bodies in one loop, on the blocks the predictor has just
    // moved them in (body_blocks); an or needs no order. A block skips the
    // test that another has answered already.
    std::atomic<bool> list_moved{false}, near_moved{false};
    body_blocks(w, pool, [&](std::size_t k, std::size_t b, std::size_t e) {
        const bool test_list = check_list && !list_moved.load(std::memory_order_relaxed);
        const bool test_near = check_near && !near_moved.load(std::memory_order_relaxed);
        const auto& pos = w.bodies[k].x[0];
        const std::size_t offset = w.flat_offset(static_cast<BodyKind>(k));
        // Only the positions looked at: the other array may be empty.
        const Vec3* at_build = test_list ? w.position_at_build_m.data() + offset : nullptr;
        const Vec3* at_selection = test_near ? w.near.position_m.data() + offset : nullptr;
        bool list = false, near = false;
        if (test_list && test_near)
            for (std::size_t i = b; i < e; ++i) {
                list |= (pos[i] - at_build[i]).squaredNorm() >= limit2;
                near |= (pos[i] - at_selection[i]).squaredNorm() >= near_limit2;
            }
        else if (test_list)
            for (std::size_t i = b; i < e; ++i) list |= (pos[i] - at_build[i]).squaredNorm() >= limit2;
        else if (test_near)
            for (std::size_t i = b; i < e; ++i) near |= (pos[i] - at_selection[i]).squaredNorm() >= near_limit2;
        if (list) list_moved.store(true, std::memory_order_relaxed);
        if (near) near_moved.store(true, std::memory_order_relaxed);
    });
    return Moves{list_moved.load(), near_moved.load()};
}

/// Selects the near pairs of the contact list at the current positions
/// (NearPairs): the body pairs whose gap is below the near skin (or not a
/// number: the kernel decides those), and each body's incidences on them and
/// on walls. A listed pair left out that touched at the last evaluation is
/// apart now, and released as the kernel would release it. With
/// NearPairs::all, every listed pair, with no test.
void select_near_pairs(World& w, ThreadPool& pool)
{
    ContactList& c = w.contacts;
    NearPairs& near = w.near;
    const double skin = near_skin_fraction * w.skin_at_build_m;
    const std::size_t pairs = c.pair_count();
    near.for_build = w.neighbour_builds;
    if (near.all) {
        near.pairs.resize(pairs);
        std::iota(near.pairs.begin(), near.pairs.end(), 0u);
        near.first.clear();
        near.second.clear();
        near.incidence_start.clear();
        near.incidence.clear();
        near.position_m.clear();
        near.skin_m = near.drift_m = 0.0;
        return;
    }
    // In three loops over fixed blocks (the same for any thread count), each
    // writing what the serial loops over pairs and bodies would: (1) which
    // pairs are near, and how many in each block of pairs; (2) each block of
    // bodies' kept incidences, in the block's own part of a scratch list (its
    // incidences' place in the contact list's), its bodies' positions and
    // largest drift; (3) the near pairs, and the kept incidences moved to
    // their place, each block from its offset (the counts summed in block
    // order).
    constexpr std::size_t block = reduction_block;
    const auto blocks_of = [](std::size_t count) { return (count + block - 1) / block; };
    std::vector<std::uint8_t> is_near(c.size(), 1); // wall contacts: always evaluated
    std::vector<std::uint32_t> near_before(blocks_of(pairs) + 1, 0);
    parallel_for_blocks(pool, pairs, block, [&](std::size_t begin, std::size_t end) {
        std::uint32_t count = 0;
        for (std::size_t p = begin; p < end; ++p) {
            const BodyRef a = c.first[p], b = c.second[p];
            const TranslationalState& A = w.of(a.kind());
            const TranslationalState& B = w.of(b.kind());
            const double reach = A.radius_m[a.index()] + B.radius_m[b.index()] + skin;
            const bool close = !((B.x[0][b.index()] - A.x[0][a.index()]).squaredNorm() >= reach * reach);
            is_near[p] = close;
            count += close;
            if (!close && c.touching[p]) c.release(p);
        }
        near_before[begin / block + 1] = count;
    });
    for (std::size_t b = 1; b < near_before.size(); ++b) near_before[b] += near_before[b - 1];

    // Bodies by kind (as parallel_for_parts cuts them), their blocks numbered
    // in flat order.
    const std::size_t n = w.body_count();
    std::array<std::size_t, body_kind_count> sizes{};
    std::array<std::size_t, body_kind_count + 1> first_block{};
    for (int k = 0; k < body_kind_count; ++k) {
        sizes[k] = w.bodies[k].size();
        first_block[k + 1] = first_block[k] + blocks_of(sizes[k]);
    }
    std::vector<std::uint32_t> kept_before(first_block[body_kind_count] + 1, 0);
    std::vector<double> block_drift2(first_block[body_kind_count], 0.0);
    const auto kept_scratch = std::make_unique_for_overwrite<std::uint32_t[]>(c.incidence.size()); // Incidence::bits
    near.incidence_start.resize(n + 1);
    near.position_m.resize(n);
    parallel_for_parts(pool, sizes, block, [&](std::size_t k, std::size_t begin, std::size_t end) {
        const std::size_t offset = w.flat_offset(static_cast<BodyKind>(k));
        // Each body's start counted from the block's (moved in loop 3).
        std::uint32_t* const out = kept_scratch.get() + c.incidence_start[offset + begin];
        std::uint32_t kept = 0;
        for (std::size_t i = offset + begin; i < offset + end; ++i) {
            near.incidence_start[i] = kept;
            for (std::uint32_t e = c.incidence_start[i]; e < c.incidence_start[i + 1]; ++e) {
                out[kept] = c.incidence[e].bits;
                kept += is_near[c.incidence[e].contact()];
            }
        }
        const auto& pos = w.bodies[k].x[0];
        const Vec3* at_build = w.position_at_build_m.data() + offset;
        double drift2 = 0.0;
        for (std::size_t i = begin; i < end; ++i) {
            near.position_m[offset + i] = pos[i];
            drift2 = std::max(drift2, (pos[i] - at_build[i]).squaredNorm());
        }
        const std::size_t b = first_block[k] + begin / block;
        kept_before[b + 1] = kept;
        block_drift2[b] = drift2;
    });
    for (std::size_t b = 1; b < kept_before.size(); ++b) kept_before[b] += kept_before[b - 1];

    // The near pairs (part 0), ascending, and each body's incidences on the
    // contacts kept, in the list's order (parts 1 to 3, by kind).
    near.pairs.resize(near_before.back());
    near.first.resize(near_before.back());
    near.second.resize(near_before.back());
    near.incidence.resize(kept_before.back());
    const std::array<std::size_t, body_kind_count + 1> parts{pairs, sizes[0], sizes[1], sizes[2]};
    parallel_for_parts(pool, parts, block, [&](std::size_t part, std::size_t begin, std::size_t end) {
        if (part == 0) {
            std::uint32_t at = near_before[begin / block];
            for (auto p = static_cast<std::uint32_t>(begin); p < end; ++p)
                if (is_near[p]) {
                    near.pairs[at] = p;
                    near.first[at] = c.first[p];
                    near.second[at] = c.second[p];
                    ++at;
                }
            return;
        }
        const std::size_t k = part - 1;
        const std::size_t offset = w.flat_offset(static_cast<BodyKind>(k));
        const std::size_t b = first_block[k] + begin / block;
        const std::uint32_t at = kept_before[b], kept = kept_before[b + 1] - at;
        for (std::size_t i = offset + begin; i < offset + end; ++i) near.incidence_start[i] += at;
        const std::uint32_t* const from = kept_scratch.get() + c.incidence_start[offset + begin];
        for (std::uint32_t e = 0; e < kept; ++e) near.incidence[at + e].bits = from[e];
    });
    near.incidence_start[n] = kept_before.back();

    // The serial loop's max(): it ignored a NaN (a body flown off in a blown-up
    // run: std::max(d, NaN) is d), and so does each block's; of the rest, the
    // largest, whichever the order.
    double drift2 = 0.0;
    for (double d : block_drift2) drift2 = std::max(drift2, d);
    near.drift_m = std::sqrt(drift2);
    near.skin_m = skin;
    ++near.selections;
}

/// Rebuilds the contact list at the current positions.
void rebuild_contact_list(World& w, ThreadPool& pool);

} // namespace

bool update_neighbours(World& w, ThreadPool& pool)
{
    const std::size_t n = w.body_count();
    // A wall added or removed since the last build: its contacts are not listed.
    const bool walls_listed = w.contacts.wall_start.size() == w.walls.size() + 1;
    bool rebuild = w.neighbours_dirty || !walls_listed || w.position_at_build_m.size() != n;
    bool reselect = w.near.for_build != w.neighbour_builds || (!w.near.all && w.near.position_m.size() != n);
    if (!rebuild) {
        // The list is rebuilt once anything has moved half the skin since its
        // build, the near pairs selected again once a body has moved
        // near_reselect_fraction of the near skin since theirs (with every
        // listed pair near, never). A body that has not moved that far since
        // the selection has moved less than that plus the drift (the largest
        // move from the build to the selection) since the build. While that
        // sum is at most 0.45 skins (a margin far above rounding), no body can
        // need a rebuild where none needs a selection, and the near test alone
        // runs; else both, in one pass. Either way the list is rebuilt at the
        // steps its own test says.
        const double skin = w.skin_at_build_m;
        const bool check_near = !reselect && !w.near.all;
        const bool near_bounds_list =
            check_near && w.near.drift_m + near_reselect_fraction * w.near.skin_m <= 0.45 * skin;
        Moves moved = body_moves(w, pool, !near_bounds_list, check_near);
        if (near_bounds_list && moved.near) moved.list = body_moves(w, pool, true, false).list;
        rebuild = moved.list;
        reselect = reselect || moved.near;
        for (std::size_t wi = 0; wi < w.walls.size() && !rebuild; ++wi)
            rebuild = (w.walls[wi].point_m - w.wall_point_at_build_m[wi]).squaredNorm() >= 0.25 * skin * skin;
    }
    if (rebuild) {
        // The last list's life decides whether this one's pairs are selected.
        NearPairs& near = w.near;
        near.all = near.list_built_at_step != NearPairs::none
                && w.step_count - near.list_built_at_step < near_min_list_life_steps;
        near.list_built_at_step = w.step_count;
        rebuild_contact_list(w, pool);
    }
    if (rebuild || reselect) select_near_pairs(w, pool);
    return rebuild;
}

namespace {

void rebuild_contact_list(World& w, ThreadPool& pool)
{
    const std::size_t n = w.body_count();
    const double skin = effective_skin_m(w);
    // Loops over fixed blocks (the same for any thread count), each writing
    // what a serial loop would, in its order.
    constexpr std::size_t block = reduction_block;
    const auto blocks_of = [](std::size_t count) { return (count + block - 1) / block; };
    std::array<std::size_t, body_kind_count> sizes{};
    std::array<std::size_t, body_kind_count + 1> first_block{}; // blocks of bodies, numbered in flat order
    for (int k = 0; k < body_kind_count; ++k) {
        sizes[k] = w.bodies[k].size();
        first_block[k + 1] = first_block[k] + blocks_of(sizes[k]);
    }
    const std::size_t body_blocks = first_block[body_kind_count];
    // The bodies in flat order, and each wall's candidates in each block of
    // them: moving bodies whose gap is below r + skin, in flat order.
    std::vector<Vec3> pos(n);
    std::vector<double> radius(n);
    std::vector<BodyRef> ref(n);
    const std::size_t walls = w.walls.size();
    std::vector<std::vector<std::uint32_t>> wall_candidates(walls * body_blocks); // [wall][block]
    parallel_for_parts(pool, sizes, block, [&](std::size_t k, std::size_t begin, std::size_t end) {
        const auto kind = static_cast<BodyKind>(k);
        const TranslationalState& body = w.bodies[k];
        const std::size_t offset = w.flat_offset(kind);
        for (std::size_t i = begin; i < end; ++i) {
            pos[offset + i] = body.x[0][i];
            radius[offset + i] = body.radius_m[i];
            ref[offset + i] = BodyRef(kind, static_cast<std::uint32_t>(i));
        }
        const std::size_t b = first_block[k] + begin / block;
        for (std::size_t wi = 0; wi < walls; ++wi) {
            std::vector<std::uint32_t>& out = wall_candidates[wi * body_blocks + b];
            for (std::size_t i = begin; i < end; ++i)
                if (moves_by_forces(body, i) && wall_gap(w.walls[wi], pos[offset + i]).gap_m < radius[offset + i] + skin)
                    out.push_back(static_cast<std::uint32_t>(offset + i));
        }
    });
    // Flat order is kind order: each kind pairs with the later kinds it
    // interacts with (and itself), and the grid looks nowhere else.
    const FlatOffsets flat = w.flat_offsets();
    PartnerRanges partners;
    partners.group_start.assign(flat.begin(), flat.end());
    partners.partner_ranges.resize(body_kind_count);
    for (int k = 0; k < body_kind_count; ++k)
        for (int m = k; m < body_kind_count; ++m)
            if (w.kinds_interact[k][m]) partners.partner_ranges[k].emplace_back(flat[m], flat[m + 1]);
    const PairFilter filter = [&](std::uint32_t i, std::uint32_t j) {
        const BodyRef a = ref[i], b = ref[j];
        // Neighbours along the wire are held by its springs, not by contact.
        if (a.kind() == BodyKind::wire && b.kind() == BodyKind::wire && b.index() - a.index() < w.wire_contact_skip)
            return false;
        // Two spheres of one clump never touch: it is rigid.
        if (a.kind() == BodyKind::grain && b.kind() == BodyKind::grain && w.clumps.is_member(a.index())
            && w.clumps.member_clump[a.index()] == w.clumps.member_clump[b.index()])
            return false;
        // Two bodies whose motion is prescribed never need a contact.
        return moves_by_forces(w.of(a.kind()), a.index()) || moves_by_forces(w.of(b.kind()), b.index());
    };
    const auto pairs = w.grid.find_pairs(pool, pos, radius, skin, partners, filter);

    // Body pairs in pair_key order: grouped by their two kinds, each group
    // in the grid's (i, j) order (flat order equals BodyRef order, so i < j
    // is already first < second): a stable counting sort, each block of
    // pairs counting its groups, then writing them from its offsets (group
    // by group, each in block order).
    constexpr std::size_t groups = body_kind_count * body_kind_count;
    const auto kinds_of = [&](const std::pair<std::uint32_t, std::uint32_t>& pair) {
        return static_cast<std::size_t>(ref[pair.first].kind()) * body_kind_count
             + static_cast<std::size_t>(ref[pair.second].kind());
    };
    std::vector<std::array<std::size_t, groups>> group_at(blocks_of(pairs.size()));
    parallel_for_blocks(pool, pairs.size(), block, [&](std::size_t begin, std::size_t end) {
        std::array<std::size_t, groups> count{};
        for (std::size_t q = begin; q < end; ++q) ++count[kinds_of(pairs[q])];
        group_at[begin / block] = count;
    });
    std::size_t at = 0;
    for (std::size_t g = 0; g < groups; ++g)
        for (auto& in_block : group_at) at += std::exchange(in_block[g], at);
    std::vector<BodyRef> first(pairs.size()), second(pairs.size());
    parallel_for_blocks(pool, pairs.size(), block, [&](std::size_t begin, std::size_t end) {
        std::array<std::size_t, groups>& next = group_at[begin / block];
        for (std::size_t q = begin; q < end; ++q) {
            const std::size_t to = next[kinds_of(pairs[q])]++;
            first[to] = ref[pairs[q].first];
            second[to] = ref[pairs[q].second];
        }
    });
    // Then each wall's candidates, by (wall, body).
    for (std::size_t wi = 0; wi < walls; ++wi) {
        for (std::size_t b = 0; b < body_blocks; ++b)
            for (std::uint32_t i : wall_candidates[wi * body_blocks + b]) {
                first.push_back(ref[i]);
                second.push_back(wall_ref(static_cast<std::uint32_t>(wi)));
            }
        w.wall_point_at_build_m[wi] = w.walls[wi].point_m;
    }
    ContactList& c = w.contacts;
    c.rebuild(std::move(first), std::move(second), w.walls.size(), flat);
    c.hertz_coefficient.resize(c.size());
    parallel_for(pool, c.size(), [&](std::size_t p) {
        const TranslationalState& A = w.of(c.first[p].kind());
        const std::uint32_t ia = c.first[p].index();
        if (is_wall(c.second[p])) { // R* = r against a wall
            const std::uint8_t wall_material = w.walls[c.second[p].index()].material;
            c.hertz_coefficient[p] = hertz_prefactor(
                w.materials.effective_modulus_pa(A.material[ia], wall_material), A.radius_m[ia]);
            return;
        }
        const TranslationalState& B = w.of(c.second[p].kind());
        const std::uint32_t ib = c.second[p].index();
        c.hertz_coefficient[p] = hertz_prefactor(w.materials.effective_modulus_pa(A.material[ia], B.material[ib]),
            effective_radius_m(A.radius_m[ia], B.radius_m[ib]));
    });
    w.position_at_build_m = std::move(pos);
    w.skin_at_build_m = skin;
    w.neighbours_dirty = false;
    ++w.neighbour_builds;
}

/// The rolling law's view of a grain–grain or grain–wall contact: the
/// bodies' relative spin δt (ω_first − ω_second), R* (r against a wall) and
/// the sum of their inverse inertias about the contact point.
struct RollingSides {
    Vec3 relative_spin_dt;
    double eff_radius_m;
    double inverse_inertia;
};

/// The rolling law on touching contact p whose normal (first to second) is
/// `normal` and normal force fn: its spring and torque slots.
[[gnu::always_inline]] inline void roll_contact(
    ContactList& c, std::size_t p, const Vec3& normal, double fn, const RollingSides& s, const ContactInputs& in)
{
    if (!(s.inverse_inertia > 0.0)) return; // neither side turns
    const RollingResult r = rolling_torque(c.rolling_rad[p], normal, s.relative_spin_dt * in.inv_dt, fn, s.eff_radius_m,
        in.tangential.stiffness_per_m, 1.0 / s.inverse_inertia, in.rolling, in.dt);
    if (in.memory == MemoryUpdate::commit) c.rolling_rad[p] = r.next_rad;
    c.rolling_torque_n_m[p] = r.torque_n_m;
}

/// The contact kernel: from a contact's geometry (or its absence) to its
/// force, spring and slots, with the laws of laws/. One writer per slot.
/// `rolling` (nullptr: no rolling law on this contact) is worked out only
/// where the contact overlaps.
template <class Rolling>
[[gnu::always_inline]] inline void evaluate_contact(ContactList& c, std::size_t p, bool overlaps,
    const ContactGeometry& g, const ContactInputs& in, const TangentialParams& tangential, Rolling&& rolling)
{
    if (!overlaps) {
        // Apart: the contact (and its spring) is gone. Slots of a contact
        // that was apart already are zero: leave them alone.
        if (c.touching[p]) c.release(p);
        return;
    }
    const double rate = g.velocity_m_per_s.dot(g.normal); // dξ/dt, > 0 while approaching
    const Vec3 vt = g.velocity_m_per_s - rate * g.normal;
    const double fn = damped_hertz_force_n(c.hertz_coefficient[p], g.overlap_m, rate, in.damping_s);
    const TangentialResult t = tangential_force(c.tangential[p], g.normal, vt, fn, tangential, in.dt);
    if (in.memory == MemoryUpdate::commit) c.tangential[p] = t.next;
    ContactOutput& out = c.output[p];
    out.force_n = -fn * g.normal + t.force_n;
    out.normal_x_tangential_n = g.normal.cross(t.force_n);
    out.overlap_m = g.overlap_m;
    out.normal_force_n = fn;
    c.touching[p] = 1;
    if (in.inverse_inertia_about_contact != nullptr)
        if (const std::optional<RollingSides> s = rolling()) roll_contact(c, p, g.normal, fn, *s, in);
}

} // namespace

void compute_contact_forces(World& w, ThreadPool& pool, MemoryUpdate memory)
{
    ContactList& c = w.contacts;
    // What both kernels read, by kind, hoisted out of the loops.
    ContactInputs in = contact_inputs(w);
    in.memory = memory;
    // Rolling resistance (laws/rolling.hpp), grain–grain and grain–wall
    // only (wire and membrane nodes do not turn), in the kernels after each
    // contact's force, from its F_n; the list keeps its springs while the
    // law is on.
    const RollingParams& rolling = w.contact.rolling;
    if (rolling.on() ? c.rolling_rad.size() != c.size() : c.rolls()) c.keep_rolling(rolling.on());
    std::vector<double> inverse_inertia_about_contact;
    if (rolling.on()) {
        const TranslationalState& grains = w.of(BodyKind::grain);
        const std::vector<double>& inv_inertia = w.grain_rotation.inv_inertia_per_kg_m2;
        // 1/(I + m r²): each grain's inverse inertia about a point of its
        // surface (0 for a grain that must not turn), once per step. A
        // clump's sphere, which has no mass of its own, takes its clump's
        // about the sphere's farthest surface point on the axis of I₁,
        // 1/(I₁ + M (|b| + r)²): a lone sphere's value at b = 0.
        inverse_inertia_about_contact.resize(grains.size());
        const ClumpState& clumps = w.clumps;
        parallel_for_blocks(pool, grains.size(), 1024, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                if (grains.motion[i] == Motion::clumped) {
                    const std::uint32_t k = clumps.member_clump[i];
                    const double arm = clumps.member_offset_m[i].norm() + grains.radius_m[i];
                    inverse_inertia_about_contact[i]
                        = 1.0 / (clumps.principal_inertia_kg_m2[k].minCoeff() + clumps.mass_kg[k] * arm * arm);
                    continue;
                }
                inverse_inertia_about_contact[i]
                    = inv_inertia[i] / (1.0 + grains.mass_kg[i] * grains.radius_m[i] * grains.radius_m[i] * inv_inertia[i]);
            }
        });
        in.rolling = rolling;
        in.inverse_inertia_about_contact = inverse_inertia_about_contact.data();
    }
    const auto grain = static_cast<std::size_t>(BodyKind::grain);
    const Vec3 no_spin = Vec3::Zero();
    auto spin_of = [&](BodyRef b) -> const Vec3& { return b.kind() == BodyKind::grain ? in.spin_dt[b.index()] : no_spin; };

    // Body pairs, then body–wall contacts: two geometry adapters, one kernel.
    const std::size_t pairs = c.pair_count();
    auto pair = [&](std::size_t p) {
        const BodyRef a = c.first[p], b = c.second[p];
        const auto ka = static_cast<std::size_t>(a.kind()), kb = static_cast<std::size_t>(b.kind());
        const std::uint32_t ia = a.index(), ib = b.index();
        ContactGeometry g;
        const bool overlaps = sphere_sphere_geometry(in.x[ka][ia], in.x[kb][ib], in.radius[ka][ia], in.radius[kb][ib],
            in.v_dt[ka][ia], in.v_dt[kb][ib], spin_of(a), spin_of(b), in.inv_dt, g);
        evaluate_contact(c, p, overlaps, g, in, in.tangential, [&]() -> std::optional<RollingSides> {
            if (ka != grain || kb != grain) return std::nullopt;
            return RollingSides{in.spin_dt[ia] - in.spin_dt[ib], effective_radius_m(in.radius[grain][ia], in.radius[grain][ib]),
                in.inverse_inertia_about_contact[ia] + in.inverse_inertia_about_contact[ib]};
        });
    };
    // The near pairs only (NearPairs: the others are apart); four or eight
    // at a time where the CPU can (same bits, contact/pair_kernel_simd.hpp);
    // the lanes it leaves, and the rest, one by one.
    WIREDEM_ASSERT(
        w.near.for_build == w.neighbour_builds && (w.near.all || w.near.position_m.size() == w.body_count()),
        "compute_contact_forces: the near pairs are not those of the contact list (update_neighbours first)");
    const std::vector<std::uint32_t>& near = w.near.pairs;
    const SimdContactKernels simd = simd_contact_kernels();
    const std::size_t lanes = simd.lanes;
    constexpr std::size_t pair_block = 256;
    parallel_for_blocks(pool, near.size(), pair_block, [&](std::size_t begin, std::size_t end) {
        const std::uint32_t* ids = near.data() + begin;
        const std::size_t count = end - begin;
        std::size_t q = 0;
        if (simd.pairs) {
            q = count / lanes * lanes;
            std::array<std::uint32_t, pair_block> left;
            const std::size_t n_left = simd.pairs(c, ids, w.near.first_of(c).data() + begin,
                w.near.second_of(c).data() + begin, q, in, left.data());
            for (std::size_t i = 0; i < n_left; ++i) pair(left[i]);
        }
        for (; q < count; ++q) pair(ids[q]);
    });
    // A wall with a friction coefficient of its own (Wall::friction_coeff)
    // puts it into the tangential law of its contacts; the SIMD wall kernel
    // has the contact law's, so such a wall's contacts go one by one.
    std::vector<TangentialParams> wall_tangential(w.walls.size(), in.tangential);
    for (std::size_t wi = 0; wi < w.walls.size(); ++wi)
        if (w.walls[wi].friction_coeff) wall_tangential[wi].friction_coeff = *w.walls[wi].friction_coeff;
    // A grain on a wall: R* = r; the wall does not turn.
    auto wall_rolling = [&](std::size_t p) -> std::optional<RollingSides> {
        if (c.first[p].kind() != BodyKind::grain) return std::nullopt;
        const std::uint32_t ia = c.first[p].index();
        return RollingSides{in.spin_dt[ia], in.radius[grain][ia], in.inverse_inertia_about_contact[ia]};
    };
    auto wall_contact = [&](std::size_t p) {
        const BodyRef a = c.first[p];
        const auto ka = static_cast<std::size_t>(a.kind());
        const std::uint32_t ia = a.index();
        const std::uint32_t wall = c.second[p].index();
        ContactGeometry g;
        const bool overlaps = sphere_wall_geometry(
            w.walls[wall], in.x[ka][ia], in.radius[ka][ia], in.v_dt[ka][ia], spin_of(a), in.inv_dt, g);
        evaluate_contact(c, p, overlaps, g, in, wall_tangential[wall], [&]() { return wall_rolling(p); });
    };
    parallel_for_blocks(pool, c.size() - pairs, 256, [&](std::size_t begin, std::size_t end) {
        for (std::size_t p = pairs + begin; p < pairs + end;) {
            // A block of one wall's contacts at a time, where the CPU can.
            const std::uint32_t wall = c.second[p].index();
            if (simd.wall && !w.walls[wall].friction_coeff
                && p + lanes <= std::min<std::size_t>(pairs + end, c.wall_start[wall + 1])) {
                // The lanes roll their grains too (wall_lanes); those it leaves go one by one.
                const std::uint32_t done = simd.wall(c, p, w.walls[wall], in);
                for (std::size_t l = 0; l < lanes; ++l)
                    if (!(done >> l & 1u)) wall_contact(p + l);
                p += lanes;
            } else {
                wall_contact(p++);
            }
        }
    });

    // What the bodies exert on each wall, summed in contact order, one
    // reduction per body kind (a wall's contacts are sorted by kind): the
    // plate forces of the force-controlled triaxial test feed back into the
    // motion, so the order of this sum is part of the results.
    struct Total {
        Vec3 force = Vec3::Zero();
        std::size_t contacts = 0;
    };
    auto add = [](Total x, const Total& y) {
        x.force += y.force;
        x.contacts += y.contacts;
        return x;
    };
    for (std::size_t wi = 0; wi < w.walls.size(); ++wi) {
        Total total;
        for (std::size_t begin = c.wall_start[wi], end; begin < c.wall_start[wi + 1]; begin = end) {
            const BodyKind kind = c.first[begin].kind();
            for (end = begin; end < c.wall_start[wi + 1] && c.first[end].kind() == kind;) ++end;
            total = add(total, reduce_blocks(pool, end - begin, Total{}, [&](std::size_t b, std::size_t e) {
                Total sum;
                for (std::size_t p = begin + b; p < begin + e; ++p) {
                    if (!c.touching[p]) continue;
                    sum.force -= c.output[p].force_n;
                    ++sum.contacts;
                }
                return sum;
            }, add));
        }
        w.wall_loads[wi] = {total.force, total.contacts};
    }
}

namespace {

/// The scalar gather of bodies [begin, end) of one kind (gather_simd.hpp
/// has the AVX2 one, with the same bits): near pairs, then walls in wall
/// order (ascending contact index); zero while apart. The force on `second` is
/// (−1)·F (and f + (−F) is f − F exactly); the lever arm r − ξ/2 is the
/// kernel's own expression.
template <bool rotates>
void gather_scalar(const GatherInputs& in, std::size_t begin, std::size_t end)
{
    const ContactList& c = *in.contacts;
    for (std::size_t i = begin; i < end; ++i) {
        Vec3 f = in.mass_kg[i] * in.gravity_m_per_s2;
        Vec3 tau = Vec3::Zero();
        const std::uint32_t last = in.incidence_start[in.flat_offset + i + 1];
        for (std::uint32_t e = in.incidence_start[in.flat_offset + i]; e < last; ++e) {
            const Incidence link = in.incidence[e];
            const ContactOutput& out = c.output[link.contact()];
            f += link.sign() * out.force_n;
            if constexpr (rotates) {
                tau += (in.radius_m[i] - 0.5 * out.overlap_m) * out.normal_x_tangential_n;
                if (in.rolling_torque_n_m != nullptr) tau += link.sign() * in.rolling_torque_n_m[link.contact()];
            }
        }
        if (in.extra_force_n != nullptr) f += in.extra_force_n[i];
        in.force_n[i] = f;
        if constexpr (rotates) in.torque_n_m[i] = tau;
    }
}

void gather_block_scalar(const GatherInputs& in, std::size_t begin, std::size_t end)
{
    if (in.torque_n_m != nullptr) gather_scalar<true>(in, begin, end);
    else gather_scalar<false>(in, begin, end);
}

} // namespace

// Each body sums the records of its near pairs and walls (NearPairs), in the
// contact list's order; the pairs left out are apart, their records zero.
// Leaving them out gives the bits of a sum over every listed contact: a zero
// record adds +0 (as first side) or −0 (as second) to the force, and +0 to
// the torque ((r − 0/2)·(+0)). x + (−0) is x for every x, and x + (+0) is x
// unless x is −0. Neither sum can be −0 where a zero record would come: the
// torque starts at +0, the force at m g with every component −0 made +0, and
// a sum of IEEE additions rounded to nearest is −0 only if both terms are.
void gather_forces(World& w, ThreadPool& pool)
{
    const SimdGather simd = simd_gather();
    const SimdGather gather = simd != nullptr ? simd : &gather_block_scalar;
    std::array<GatherInputs, body_kind_count> inputs;
    for (int k = 0; k < body_kind_count; ++k) {
        const auto kind = static_cast<BodyKind>(k);
        const TranslationalState& body = w.bodies[k];
        GatherInputs& in = inputs[k];
        in.contacts = &w.contacts;
        in.incidence_start = w.near.incidence_start_of(w.contacts).data();
        in.incidence = w.near.incidence_of(w.contacts).data();
        in.flat_offset = w.flat_offset(kind);
        in.mass_kg = body.mass_kg.data();
        in.radius_m = body.radius_m.data();
        // + 0: a component −0 becomes +0 (see above).
        if (w.gravity_acts[k]) in.gravity_m_per_s2 = w.gravity_m_per_s2 + Vec3::Zero();
        if (kind == BodyKind::wire) in.extra_force_n = w.wire_forces.node_force_n.data();
        if (kind == BodyKind::membrane) in.extra_force_n = w.membrane_forces.node_force_n.data();
        in.force_n = w.body_force_n[k].data();
        if (kind == BodyKind::grain) {
            in.torque_n_m = w.grain_torque_n_m.data();
            // Only grains turn; a contact that does not roll holds zero.
            if (!w.contacts.rolling_torque_n_m.empty()) in.rolling_torque_n_m = w.contacts.rolling_torque_n_m.data();
        }
    }
    // A load on a body past the last (or on a wall) would never be added.
    for (int k = 0; k < body_kind_count; ++k)
        WIREDEM_ASSERT(w.point_loads.of(static_cast<BodyKind>(k), static_cast<std::uint32_t>(w.bodies[k].size()), BodyRef::max_index + 1).empty(),
            "a point load names a body that does not exist");
    WIREDEM_ASSERT(w.point_loads.empty() || !is_wall(w.point_loads.list().back().first), "a point load names a wall");
    // Every kind's bodies in one loop (each body's sum is its own). A block
    // adds its own bodies' point loads (World::point_loads; in a column test
    // under mass scaling the wire's weight, one per node) right after their
    // sums, on its thread: the list names each body at most once, in body
    // order (state/point_loads.hpp), so each body's force is f + p.
    // The blocks of the integrators' loops (body_blocks): the thread that
    // gathers a body's force corrects it.
    body_blocks(w, pool, [&](std::size_t k, std::size_t begin, std::size_t end) {
        gather(inputs[k], begin, end);
        std::vector<Vec3>& force = w.body_force_n[k];
        for (const auto& [body, p] : w.point_loads.of(static_cast<BodyKind>(k), static_cast<std::uint32_t>(begin),
                 static_cast<std::uint32_t>(end)))
            force[body.index()] += p;
    });
}

} // namespace wiredem::engine
