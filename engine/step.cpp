#include "step.hpp"

#include "forces/membrane_forces.hpp"
#include "forces/wire_forces.hpp"
#include "integrate/gear5.hpp"
#include "integrate/verlet.hpp"
#include "laws/hertz.hpp"
#include "laws/tangential.hpp"

#include <algorithm>
#include <cmath>

namespace wiredem::engine {
namespace {

/// E* for every material pair, row-major; rebuilt per step (a handful of materials).
std::vector<double> effective_moduli(const World& w)
{
    const std::size_t n = w.materials.size();
    std::vector<double> e(n * n);
    for (std::size_t a = 0; a < n; ++a)
        for (std::size_t b = 0; b < n; ++b)
            e[a * n + b] = effective_modulus_pa(w.materials[a].youngs_modulus_pa, w.materials[a].poisson_ratio,
                w.materials[b].youngs_modulus_pa, w.materials[b].poisson_ratio);
    return e;
}

} // namespace

void initialize_accelerations(World& w, ThreadPool& pool)
{
    update_neighbours(w, pool);
    const std::vector<TangentialState> pair_springs = w.contacts.tangential;
    std::vector<std::array<std::vector<TangentialState>, body_kind_count>> wall_springs;
    for (const Wall& wall : w.walls) wall_springs.push_back(wall.tangential);
    compute_pair_forces(w, pool);
    compute_wall_forces(w, pool);
    compute_wire_forces(w, pool);
    compute_membrane_forces(w, pool);
    gather_forces(w, pool);
    w.contacts.tangential = pair_springs;
    for (std::size_t i = 0; i < w.walls.size(); ++i) w.walls[i].tangential = wall_springs[i];

    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    for (auto& body : w.bodies)
        parallel_for(pool, body.size(), [&](std::size_t i) {
            body.x[2][i] = half_dt2 * body.inv_mass_per_kg[i] * body.force_n[i];
        });
    RotationalState& rot = w.grain_rotation;
    parallel_for(pool, rot.orientation.size(), [&](std::size_t i) {
        rot.w[2][i] = half_dt2 * rot.inv_inertia_per_kg_m2[i] * rot.torque_n_m[i];
    });
}

StepReport step(World& w, ThreadPool& pool, StepProfile* profile)
{
    StepReport report;
    const bool gear = w.integrator == Integrator::gear5;
    if (w.step_count == 0) initialize_accelerations(w, pool); // a(0) from the forces
    StageClock clock(profile);
    if (gear) gear5_predict(w, pool);                    // every moving body
    else verlet_first_half(w, pool);
    clock.lap(Stage::predict);
    move_walls(w);                                       // prescribed plate motion
    clock.lap(Stage::move_walls);
    report.neighbours_rebuilt = update_neighbours(w, pool); // cell grid + skin, only when needed
    clock.lap(Stage::neighbours);
    compute_pair_forces(w, pool);                        // Hertz + tangential, one slot per pair
    compute_wall_forces(w, pool);                        // plates and cylinder, one slot per body
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

void move_walls(World& w)
{
    for (Wall& wall : w.walls) wall.point_m += wall.velocity_m_per_s * w.dt_s;
}

double effective_skin_m(const World& w)
{
    if (w.skin_m > 0.0) return w.skin_m;
    double r_max = 0.0;
    for (const auto& body : w.bodies)
        for (double r : body.radius_m) r_max = std::max(r_max, r);
    return 0.2 * r_max;
}

namespace {

/// Signed distance from a body's centre to a wall (positive inside the domain)
/// and the unit normal from the body towards the wall.
struct WallGap {
    double gap_m;
    Vec3 towards;
};
WallGap wall_gap(const Wall& wall, const Vec3& x)
{
    if (wall.shape == Wall::Shape::plane) return {(x - wall.point_m).dot(wall.normal), -wall.normal};
    Vec3 radial = x - wall.point_m;
    radial.z() = 0.0;
    const double rho = radial.norm();
    return {wall.radius_m - rho, rho > 0.0 ? Vec3(radial / rho) : Vec3(Vec3::UnitX())};
}

/// Every wall's candidate bodies (gap < r + skin, moving bodies only). A body
/// that drops out while still marked touching has its slots cleared: it is
/// more than the skin away, so it cannot touch before the next rebuild.
void build_wall_candidates(World& w, double skin_m)
{
    for (Wall& wall : w.walls) {
        for (int k = 0; k < body_kind_count; ++k) {
            const TranslationalState& body = w.bodies[k];
            std::vector<std::uint32_t>& list = wall.candidates[k];
            list.clear();
            for (std::uint32_t i = 0; i < body.size(); ++i) {
                const bool near = body.inv_mass_per_kg[i] != 0.0
                               && wall_gap(wall, body.x[0][i]).gap_m < body.radius_m[i] + skin_m;
                if (near) {
                    list.push_back(i);
                } else if (wall.touching[k][i]) {
                    wall.tangential[k][i] = TangentialState{};
                    wall.force_on_body_n[k][i].setZero();
                    wall.torque_on_body_n_m[k][i].setZero();
                    wall.touching[k][i] = 0;
                }
            }
        }
        wall.point_at_build_m = wall.point_m;
        wall.candidates_built = true;
    }
}

} // namespace

bool update_neighbours(World& w, ThreadPool& pool)
{
    const double skin = effective_skin_m(w);
    const std::size_t n = w.body_count();
    if (!w.neighbours_dirty && w.position_at_build_m.size() == n) {
        double max_move2 = 0.0;
        for (int k = 0; k < body_kind_count; ++k) {
            const auto& pos = w.bodies[k].x[0];
            const std::size_t off = w.flat_offset(static_cast<BodyKind>(k));
            max_move2 = std::max(max_move2,
                reduce_blocks(
                    pool, pos.size(), 0.0,
                    [&](std::size_t b, std::size_t e) {
                        double m = 0.0;
                        for (std::size_t i = b; i < e; ++i)
                            m = std::max(m, (pos[i] - w.position_at_build_m[off + i]).squaredNorm());
                        return m;
                    },
                    [](double a, double b) { return std::max(a, b); }));
        }
        bool walls_ready = true;
        for (const Wall& wall : w.walls) {
            walls_ready = walls_ready && wall.candidates_built;
            max_move2 = std::max(max_move2, (wall.point_m - wall.point_at_build_m).squaredNorm());
        }
        if (walls_ready && max_move2 < 0.25 * skin * skin) return false;
    }

    std::vector<Vec3> pos;
    std::vector<double> radius;
    std::vector<BodyRef> ref;
    pos.reserve(n);
    radius.reserve(n);
    ref.reserve(n);
    for (int k = 0; k < body_kind_count; ++k) {
        const auto& body = w.bodies[k];
        pos.insert(pos.end(), body.x[0].begin(), body.x[0].end());
        radius.insert(radius.end(), body.radius_m.begin(), body.radius_m.end());
        for (std::uint32_t i = 0; i < body.size(); ++i) ref.emplace_back(static_cast<BodyKind>(k), i);
    }
    const PairFilter filter = [&](std::uint32_t i, std::uint32_t j) {
        const BodyRef a = ref[i], b = ref[j];
        if (!w.kinds_interact[static_cast<int>(a.kind())][static_cast<int>(b.kind())]) return false;
        // Neighbours along the wire are held by its springs, not by contact.
        if (a.kind() == BodyKind::wire && b.kind() == BodyKind::wire && b.index() - a.index() < w.wire_contact_skip)
            return false;
        // Two fixed bodies never need a contact.
        return w.of(a.kind()).inv_mass_per_kg[a.index()] != 0.0 || w.of(b.kind()).inv_mass_per_kg[b.index()] != 0.0;
    };
    const auto pairs = w.grid.find_pairs(pool, pos, radius, skin, filter);

    std::vector<std::uint64_t> keys(pairs.size());
    std::vector<BodyRef> first(pairs.size()), second(pairs.size());
    std::vector<std::uint32_t> flat_first(pairs.size()), flat_second(pairs.size());
    for (std::size_t p = 0; p < pairs.size(); ++p) {
        // Flat order equals BodyRef order, so (i < j) is already (first < second).
        flat_first[p] = pairs[p].first;
        flat_second[p] = pairs[p].second;
        first[p] = ref[pairs[p].first];
        second[p] = ref[pairs[p].second];
        keys[p] = pair_key(first[p], second[p]);
    }
    w.contacts.rebuild(keys, first, second, flat_first, flat_second, n);
    const std::vector<double> e_star = effective_moduli(w);
    const std::size_t n_mat = w.materials.size();
    ContactList& c = w.contacts;
    c.hertz_coefficient.resize(c.size());
    parallel_for(pool, c.size(), [&](std::size_t p) {
        const TranslationalState& A = w.of(c.first[p].kind());
        const TranslationalState& B = w.of(c.second[p].kind());
        const std::uint32_t ia = c.first[p].index(), ib = c.second[p].index();
        c.hertz_coefficient[p] = (4.0 / 3.0) * e_star[A.material[ia] * n_mat + B.material[ib]]
                               * std::sqrt(effective_radius_m(A.radius_m[ia], B.radius_m[ib]));
    });
    build_wall_candidates(w, skin);
    w.position_at_build_m = std::move(pos);
    w.neighbours_dirty = false;
    ++w.neighbour_builds;
    return true;
}

void compute_pair_forces(World& w, ThreadPool& pool)
{
    ContactList& c = w.contacts;
    const double dt = w.dt_s;
    const double inv_dt = 1.0 / dt;
    const double damping_s = w.contact.normal_damping_s;
    const TangentialParams& tp = w.contact.tangential;
    // Raw views of what the loop reads, by kind, hoisted out of it.
    struct KindView {
        const Vec3* x;       // x₀
        const Vec3* v_dt;    // x₁ = δt v
        const double* radius;
    };
    std::array<KindView, body_kind_count> view{};
    for (int k = 0; k < body_kind_count; ++k)
        view[k] = {w.bodies[k].x[0].data(), w.bodies[k].x[1].data(), w.bodies[k].radius_m.data()};
    const Vec3* spin_dt = w.grain_rotation.w[1].data(); // δt ω of the grains
    const Vec3 no_spin = Vec3::Zero();

    parallel_for(pool, c.size(), [&](std::size_t p) {
        const BodyRef a = c.first[p], b = c.second[p];
        const KindView& A = view[static_cast<int>(a.kind())];
        const KindView& B = view[static_cast<int>(b.kind())];
        const std::uint32_t ia = a.index(), ib = b.index();
        const Vec3 d = B.x[ib] - A.x[ia];
        const double ra = A.radius[ia], rb = B.radius[ib];
        const double dist2 = d.squaredNorm();
        if (dist2 >= (ra + rb) * (ra + rb) || dist2 == 0.0) {
            // Apart: the contact (and its spring) is gone. Slots of a pair
            // that was apart already are zero: leave them alone.
            if (c.touching[p]) {
                c.tangential[p] = TangentialState{};
                c.force_n[p].setZero();
                c.shares[c.share_of_first[p]] = ContactShare{};
                c.shares[c.share_of_second[p]] = ContactShare{};
                c.normal_force_n[p] = 0.0;
                c.touching[p] = 0;
            }
            return;
        }
        const double dist = std::sqrt(dist2);
        const double overlap = ra + rb - dist;
        const Vec3 n = d * (1.0 / dist); // from a to b
        const double arm_a = ra - 0.5 * overlap, arm_b = rb - 0.5 * overlap;
        const Vec3& spin_a = a.kind() == BodyKind::grain ? spin_dt[ia] : no_spin;
        const Vec3& spin_b = b.kind() == BodyKind::grain ? spin_dt[ib] : no_spin;
        const Vec3 v_rel = ((A.v_dt[ia] - B.v_dt[ib]) + (arm_a * spin_a + arm_b * spin_b).cross(n)) * inv_dt;
        const double rate = v_rel.dot(n); // > 0 while approaching
        const Vec3 vt = v_rel - rate * n;

        // Damped Hertz, F_n = (4/3) E* √R* √ξ (ξ + γ_n dξ/dt) ≥ 0 (laws/hertz.hpp).
        const double fn = std::max(c.hertz_coefficient[p] * std::sqrt(overlap) * (overlap + damping_s * rate), 0.0);
        const TangentialResult t = tangential_force(c.tangential[p], n, vt, fn, tp, dt);
        c.tangential[p] = t.next;
        const Vec3 force = -fn * n + t.force_n;
        const Vec3 n_x_ft = n.cross(t.force_n);
        c.force_n[p] = force;
        c.shares[c.share_of_first[p]] = {force, arm_a * n_x_ft};
        c.shares[c.share_of_second[p]] = {-force, arm_b * n_x_ft};
        c.normal_force_n[p] = fn;
        c.touching[p] = 1;
    });
}

void compute_wall_forces(World& w, ThreadPool& pool)
{
    const std::vector<double> e_star = effective_moduli(w);
    const std::size_t n_mat = w.materials.size();
    const double dt = w.dt_s;
    const double inv_dt = 1.0 / dt;
    const double damping_s = w.contact.normal_damping_s;
    const TangentialParams& tp = w.contact.tangential;

    struct Total {
        Vec3 force = Vec3::Zero();
        std::size_t contacts = 0;
    };
    // A wall added since the last neighbour rebuild has no candidates yet.
    if (std::any_of(w.walls.begin(), w.walls.end(), [](const Wall& wall) { return !wall.candidates_built; }))
        update_neighbours(w, pool);
    for (Wall& wall : w.walls) {
        Total total;
        for (int k = 0; k < body_kind_count; ++k) {
            const TranslationalState& body = w.bodies[k];
            const auto kind = static_cast<BodyKind>(k);
            auto& memory = wall.tangential[k];
            auto& force = wall.force_on_body_n[k];
            auto& torque = wall.torque_on_body_n_m[k];
            auto& touching = wall.touching[k];
            const std::vector<std::uint32_t>& near = wall.candidates[k];
            const Total part = reduce_blocks(
                pool, near.size(), Total{},
                [&](std::size_t begin, std::size_t end) {
                    Total sum;
                    for (std::size_t c = begin; c < end; ++c) {
                        const std::uint32_t i = near[c];
                        const double r = body.radius_m[i];
                        const auto [gap, m] = wall_gap(wall, body.x[0][i]); // m: from the body towards the wall
                        const double overlap = r - gap;
                        if (overlap <= 0.0) {
                            if (touching[i]) {
                                memory[i] = TangentialState{};
                                force[i].setZero();
                                torque[i].setZero();
                                touching[i] = 0;
                            }
                            continue;
                        }
                        touching[i] = 1;
                        const double arm = r - 0.5 * overlap;
                        const Vec3 omega = kind == BodyKind::grain ? Vec3(w.grain_rotation.w[1][i] * inv_dt) : Vec3(Vec3::Zero());
                        const Vec3 v_rel = body.x[1][i] * inv_dt + arm * omega.cross(m) - wall.velocity_m_per_s;
                        const double rate = v_rel.dot(m);
                        const Vec3 vt = v_rel - rate * m;
                        const double fn = hertz_normal_force_n(
                            overlap, rate, e_star[body.material[i] * n_mat + wall.material], r, damping_s);
                        const TangentialResult t = tangential_force(memory[i], m, vt, fn, tp, dt);
                        memory[i] = t.next;
                        force[i] = -fn * m + t.force_n;
                        torque[i] = arm * m.cross(t.force_n);
                        sum.force -= force[i];
                        ++sum.contacts;
                    }
                    return sum;
                },
                [](Total a, const Total& b) {
                    a.force += b.force;
                    a.contacts += b.contacts;
                    return a;
                });
            total.force += part.force;
            total.contacts += part.contacts;
        }
        wall.total_force_n = total.force;
        wall.contacts = total.contacts;
    }
}

void gather_forces(World& w, ThreadPool& pool)
{
    const ContactList& c = w.contacts;
    for (int k = 0; k < body_kind_count; ++k) {
        TranslationalState& body = w.bodies[k];
        const std::size_t off = w.flat_offset(static_cast<BodyKind>(k));
        const Vec3 g = w.gravity_acts[k] ? w.gravity_m_per_s2 : Vec3(Vec3::Zero());
        const bool rotates = k == static_cast<int>(BodyKind::grain);
        parallel_for(pool, body.size(), [&](std::size_t i) {
            Vec3 f = body.mass_kg[i] * g;
            Vec3 tau = Vec3::Zero();
            for (std::uint32_t e = c.incidence_start[off + i]; e < c.incidence_start[off + i + 1]; ++e) {
                f += c.shares[e].force_n; // ascending pair order; zero while apart
                tau += c.shares[e].torque_n_m;
            }
            for (const Wall& wall : w.walls) {
                if (!wall.touching[k][i]) continue; // its slots are zero
                f += wall.force_on_body_n[k][i];
                tau += wall.torque_on_body_n_m[k][i];
            }
            if (k == static_cast<int>(BodyKind::wire)) f += w.wire.node_force_n[i];
            if (k == static_cast<int>(BodyKind::membrane)) f += w.membrane.node_force_n[i];
            body.force_n[i] = f;
            if (rotates) w.grain_rotation.torque_n_m[i] = tau;
        });
    }
    for (const auto& [body, f] : w.point_loads) w.of(body.kind()).force_n[body.index()] += f;
}

} // namespace wiredem::engine
