#include "energy.hpp"

#include "contact/geometry.hpp"
#include "forces/wire_forces.hpp"
#include "laws/hertz.hpp"
#include "laws/membrane_edge.hpp"
#include "laws/wire_bond.hpp"

#include <cmath>

namespace wiredem::engine {
namespace {

double hertz_energy_j(double overlap_m, double e_star_pa, double r_star_m)
{
    return overlap_m > 0.0 ? 8.0 / 15.0 * e_star_pa * std::sqrt(r_star_m) * std::pow(overlap_m, 2.5) : 0.0;
}

double sum(ThreadPool& pool, std::size_t n, const auto& term)
{
    return reduce_blocks(
        pool, n, 0.0,
        [&](std::size_t b, std::size_t e) {
            double s = 0.0;
            for (std::size_t i = b; i < e; ++i) s += term(i);
            return s;
        },
        [](double a, double b) { return a + b; });
}

} // namespace

ElasticEnergy elastic_energy(const World& w, ThreadPool& pool)
{
    ElasticEnergy e;
    const ContactList& c = w.contacts;
    e.contacts_j = sum(pool, c.size(), [&](std::size_t p) {
        const TranslationalState& A = w.of(c.first[p].kind());
        const std::uint32_t ia = c.first[p].index();
        if (is_wall(c.second[p])) {
            // Every body that can touch the wall is listed (held bodies never are).
            const Wall& wall = w.walls[c.second[p].index()];
            return hertz_energy_j(A.radius_m[ia] - wall_gap(wall, A.x[0][ia]).gap_m,
                w.materials.effective_modulus_pa(A.material[ia], wall.material), A.radius_m[ia]);
        }
        if (!c.touching[p]) return 0.0;
        const TranslationalState& B = w.of(c.second[p].kind());
        const std::uint32_t ib = c.second[p].index();
        const double overlap = A.radius_m[ia] + B.radius_m[ib] - (A.x[0][ia] - B.x[0][ib]).norm();
        return hertz_energy_j(overlap, w.materials.effective_modulus_pa(A.material[ia], B.material[ib]),
            effective_radius_m(A.radius_m[ia], B.radius_m[ib]));
    });
    const auto& xw = w.of(BodyKind::wire).x[0];
    const WireChain& wire = w.wire;
    if (xw.size() >= 2) {
        // A removed segment holds no energy, nor do the joints at its ends
        // (forces/wire_forces.hpp); a whole wire has none removed.
        const std::vector<std::uint8_t> removed = w.wire_breaks.empty() ? std::vector<std::uint8_t>{} : removed_wire_segments(w);
        const auto whole = [&](std::size_t s) { return w.wire_breaks.empty() || removed[s] == 0; };
        e.wire_j = sum(pool, xw.size(), [&](std::size_t i) {
            double energy = 0.0;
            if (i + 1 < xw.size() && whole(i)) {
                const double dl = (xw[i + 1] - xw[i]).norm() - wire.segment_length_m;
                energy += 0.5 * wire.axial_stiffness_n_per_m * dl * dl;
            }
            if (i >= 1 && i + 1 < xw.size() && whole(i - 1) && whole(i)) {
                const Vec3 a = xw[i] - xw[i - 1], b = xw[i + 1] - xw[i];
                const double zeta = bend_angle_rad(a.cross(b).norm(), a.dot(b)); // the law's ζ (any scale of a, b)
                const double bend = zeta - w.wire_rest_angle_rad[i]; // plastic joints: ζ − ζ₀
                energy += 0.5 * wire.bending_stiffness_n_m * bend * bend;
            }
            return energy;
        });
    }
    const MembraneMesh& m = w.membrane;
    const auto& xm = w.of(BodyKind::membrane).x[0];
    e.membrane_j = sum(pool, m.edges.size(), [&](std::size_t k) {
        const double length_m = (xm[m.edges[k][1]] - xm[m.edges[k][0]]).norm();
        return membrane_edge_energy_j(length_m, m.edge_rest_m[k], m.edge_stiffness_n_per_m, m.edge_law);
    });
    return e;
}

double gravitational_energy_j(const World& w)
{
    double e = 0.0;
    for (int k = 0; k < body_kind_count; ++k) {
        if (!w.gravity_acts[k]) continue;
        const TranslationalState& body = w.bodies[k];
        for (std::size_t i = 0; i < body.size(); ++i)
            if (is_dynamic(body, i)) e -= body.mass_kg[i] * w.gravity_m_per_s2.dot(body.x[0][i]);
    }
    if (w.gravity_acts[static_cast<int>(BodyKind::grain)]) // clumps: their spheres weigh nothing
        for (std::size_t i = 0; i < w.clumps.size(); ++i) e -= w.clumps.mass_kg[i] * w.gravity_m_per_s2.dot(w.clumps.x[0][i]);
    return e;
}

} // namespace wiredem::engine
