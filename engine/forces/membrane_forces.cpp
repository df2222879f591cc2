#include "forces/membrane_forces.hpp"

#include "forces/membrane_simd.hpp"
#include "laws/membrane_edge.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace wiredem::engine {

namespace {
/// Edges or triangles per parallel task of compute_membrane_forces (each
/// element is written by one task, so the blocking does not change a bit).
constexpr std::size_t membrane_block = 512;
} // namespace

void build_membrane(World& w, const MembraneSpec& spec)
{
    MembraneMesh& m = w.membrane;
    m = MembraneMesh{};
    m.radius_m = spec.radius_m;
    m.height_m = spec.height_m;
    m.base_z_m = spec.base_z_m;
    m.edge_stiffness_n_per_m = membrane_edge_stiffness_n_per_m(spec.youngs_modulus_pa, spec.thickness_m);
    m.edge_law = spec.edge_law;
    const std::uint8_t material = add_material(w, Material{spec.youngs_modulus_pa, spec.poisson_ratio, spec.density_kg_per_m3});

    // Columns from the circumference, rows so that the row spacing is
    // (√3/2) × the chord between neighbours (equilateral triangles).
    const std::size_t columns = std::max<std::size_t>(6, static_cast<std::size_t>(std::lround(2 * std::numbers::pi * spec.radius_m / spec.mesh_size_m)));
    const double chord = 2.0 * spec.radius_m * std::sin(std::numbers::pi / columns);
    const std::size_t rows = std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(spec.height_m / (std::sqrt(3.0) / 2.0 * chord))) + 1);
    const double dz = spec.height_m / static_cast<double>(rows - 1);
    m.columns = columns;
    m.rows = rows;
    m.node_area_m2 = chord * dz; // the cylinder's area shared equally among the nodes
    const double node_mass = spec.density_scale * m.node_area_m2 * spec.density_kg_per_m3 * spec.thickness_m;

    const std::size_t first = w.of(BodyKind::membrane).size();
    auto id = [&](std::size_t row, std::size_t col) {
        return static_cast<std::uint32_t>(first + row * columns + (col % columns));
    };
    for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < columns; ++c) {
            const double phi = 2.0 * std::numbers::pi * (static_cast<double>(c) + 0.5 * static_cast<double>(r % 2)) / columns;
            const Vec3 x(spec.radius_m * std::cos(phi), spec.radius_m * std::sin(phi), spec.base_z_m + r * dz);
            add_node(w, BodyKind::membrane, x, spec.contact_radius_m, 0.0, material); // rigid: no mass yet, so fixed
            m.node_fixed.push_back(r == 0 || r + 1 == rows ? 1 : 0);
            m.node_mass_kg.push_back(node_mass);
        }
    // Two triangles per quad between rows r and r+1. An odd row is turned by
    // +½ column, so (r, c) neighbours (r+1, c) and (r+1, c−1) when r is odd.
    for (std::size_t r = 0; r + 1 < rows; ++r)
        for (std::size_t c = 0; c < columns; ++c) {
            const bool odd = r % 2 == 1;
            const std::uint32_t a = id(r, c), b = id(r, c + 1);
            const std::uint32_t up = id(r + 1, c), up_next = id(r + 1, c + 1);
            if (!odd) { // (r+1, c) sits half a column after (r, c)
                m.triangles.push_back({a, b, up});
                m.triangles.push_back({b, up_next, up});
            } else {    // (r+1, c+1) sits half a column after (r, c)
                m.triangles.push_back({a, b, up_next});
                m.triangles.push_back({a, up_next, up});
            }
        }
    // Orient every triangle so that (b−a)×(c−a) points towards the axis.
    const auto& x = w.of(BodyKind::membrane).x[0];
    for (auto& t : m.triangles) {
        const Vec3 n = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
        Vec3 out = (x[t[0]] + x[t[1]] + x[t[2]]) / 3.0;
        out.z() = 0.0;
        if (n.dot(out) > 0.0) std::swap(t[1], t[2]);
    }
    // Unique edges, in ascending (i, j) order.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> unique;
    for (const auto& t : m.triangles)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t i = t[e], j = t[(e + 1) % 3];
            unique[{std::min(i, j), std::max(i, j)}] = 0;
        }
    for (const auto& [e, unused] : unique) {
        // Springs between two fixed rim nodes never act: leave them out.
        if (m.node_fixed[e.first - first] && m.node_fixed[e.second - first]) continue;
        m.edges.push_back({e.first, e.second});
        m.edge_rest_m.push_back((x[e.second] - x[e.first]).norm());
    }
    // Incidence lists (node → elements), ascending element id.
    const std::size_t nodes = first + rows * columns;
    auto build_csr = [&](std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& list, auto&& for_each_element,
                         std::size_t elements) {
        start.assign(nodes + 1, 0);
        for (std::size_t e = 0; e < elements; ++e) for_each_element(e, [&](std::uint32_t node, std::uint32_t) { ++start[node + 1]; });
        for (std::size_t n = 0; n < nodes; ++n) start[n + 1] += start[n];
        list.resize(start.back());
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t e = 0; e < elements; ++e)
            for_each_element(e, [&](std::uint32_t node, std::uint32_t code) { list[fill[node]++] = code; });
    };
    build_csr(m.edge_incidence_start, m.edge_incidence,
        [&](std::size_t e, auto&& visit) {
            visit(m.edges[e][0], static_cast<std::uint32_t>(2 * e));
            visit(m.edges[e][1], static_cast<std::uint32_t>(2 * e + 1));
        },
        m.edges.size());
    build_csr(m.triangle_incidence_start, m.triangle_incidence,
        [&](std::size_t t, auto&& visit) {
            for (int k = 0; k < 3; ++k) visit(m.triangles[t][k], static_cast<std::uint32_t>(t));
        },
        m.triangles.size());
    MembraneForces& slots = w.membrane_forces;
    slots.edge_force_n.assign(m.edges.size(), Vec3::Zero());
    slots.triangle_force_n.assign(m.triangles.size(), Vec3::Zero());
    slots.node_force_n.assign(nodes, Vec3::Zero());
    m.rigid = true;
}

void set_membrane_rigid(World& w, bool rigid)
{
    MembraneMesh& m = w.membrane;
    TranslationalState& nodes = w.of(BodyKind::membrane);
    for (std::uint32_t i = 0; i < nodes.size(); ++i) {
        nodes.mass_kg[i] = m.node_mass_kg[i];
        nodes.inv_mass_per_kg[i] = 1.0 / m.node_mass_kg[i];
        set_motion(w, {BodyKind::membrane, i}, rigid || m.node_fixed[i] ? Motion::fixed : Motion::dynamic);
    }
    m.rigid = rigid;
    // A rebuild even when no node changed its motion: the list the preparation
    // continues with, hence its bits, depend on when it was built.
    invalidate_neighbours(w);
    if (rigid) { // compute_membrane_forces skips a rigid membrane: nothing it holds moves
        MembraneForces& slots = w.membrane_forces;
        std::fill(slots.edge_force_n.begin(), slots.edge_force_n.end(), Vec3::Zero());
        std::fill(slots.triangle_force_n.begin(), slots.triangle_force_n.end(), Vec3::Zero());
        std::fill(slots.node_force_n.begin(), slots.node_force_n.end(), Vec3::Zero());
    }
}

void compute_membrane_forces(World& w, ThreadPool& pool)
{
    const MembraneMesh& m = w.membrane;
    MembraneForces& slots = w.membrane_forces;
    const auto& x = w.of(BodyKind::membrane).x[0];
    // Held nodes do not move whatever their springs and the pressure do (the
    // preparation's rigid membrane: ~9 % of a paper-size pour's step time).
    if (x.empty() || m.rigid) return;
    const double k = m.edge_stiffness_n_per_m;
    // Four or eight elements at a time where the CPU can (same bits, membrane_simd.hpp).
    const MembraneSimdKernels simd = simd_membrane_kernels();
    const auto simd_part = [&](std::size_t begin, std::size_t end) { return simd ? (end - begin) / simd.lanes * simd.lanes : 0; };
    parallel_for_blocks(pool, m.edges.size(), membrane_block, [&](std::size_t begin, std::size_t end) {
        const std::size_t n = simd_part(begin, end);
        if (n > 0)
            simd.edges(x.data(), m.edges.data() + begin, m.edge_rest_m.data() + begin, k, m.edge_law,
                slots.edge_force_n.data() + begin, n);
        for (std::size_t e = begin + n; e < end; ++e)
            slots.edge_force_n[e] = membrane_edge_force_n(x[m.edges[e][0]], x[m.edges[e][1]], m.edge_rest_m[e], k, m.edge_law);
    });
    const double p = m.pressure_pa;
    parallel_for_blocks(pool, m.triangles.size(), membrane_block, [&](std::size_t begin, std::size_t end) {
        const std::size_t n = simd_part(begin, end);
        if (n > 0) simd.triangles(x.data(), m.triangles.data() + begin, p, slots.triangle_force_n.data() + begin, n);
        for (std::size_t t = begin + n; t < end; ++t) {
            const auto& tri = m.triangles[t];
            // ½ (b−a)×(c−a) = A n_in: the pressure force σ₃ A n_in, a third per node.
            slots.triangle_force_n[t] = p / 6.0 * (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);
        }
    });
    parallel_for(pool, x.size(), [&](std::size_t i) {
        Vec3 f = Vec3::Zero();
        for (std::uint32_t e = m.edge_incidence_start[i]; e < m.edge_incidence_start[i + 1]; ++e) {
            const std::uint32_t code = m.edge_incidence[e];
            f += (code & 1u) ? Vec3(-slots.edge_force_n[code >> 1]) : slots.edge_force_n[code >> 1];
        }
        for (std::uint32_t e = m.triangle_incidence_start[i]; e < m.triangle_incidence_start[i + 1]; ++e)
            f += slots.triangle_force_n[m.triangle_incidence[e]];
        slots.node_force_n[i] = f;
    });
}

MembraneLoad membrane_contact_load(const World& w, ThreadPool& pool)
{
    const ContactList& c = w.contacts;
    MembraneLoad load = reduce_blocks(
        pool, c.size(), MembraneLoad{},
        [&](std::size_t begin, std::size_t end) {
            MembraneLoad part;
            for (std::size_t p = begin; p < end; ++p) {
                // The specimen's contacts: grain– and wire–membrane (a membrane
                // node is always `second`, BodyKind::membrane being the last kind).
                if (!c.touching[p] || c.second[p].kind() != BodyKind::membrane || c.first[p].kind() == BodyKind::membrane)
                    continue;
                // force_n is the force on the grain or wire node; the membrane node feels −force_n.
                Vec3 radial = w.of(BodyKind::membrane).x[0][c.second[p].index()];
                radial.z() = 0.0;
                const double rho = radial.norm();
                part.normal_force_n += c.output[p].normal_force_n;
                if (rho > 0.0) part.radial_force_n += -c.output[p].force_n.dot(radial) / rho;
                ++part.contacts;
            }
            return part;
        },
        [](MembraneLoad a, const MembraneLoad& b) {
            a.normal_force_n += b.normal_force_n;
            a.radial_force_n += b.radial_force_n;
            a.contacts += b.contacts;
            return a;
        });
    // Nodes touched by at least one grain.
    const std::size_t off = w.flat_offset(BodyKind::membrane);
    const std::size_t n = w.of(BodyKind::membrane).size();
    if (c.incidence_start.size() >= off + n + 1) {
        load.nodes_in_contact = reduce_blocks(
            pool, n, std::size_t{0},
            [&](std::size_t begin, std::size_t end) {
                std::size_t count = 0;
                for (std::size_t i = begin; i < end; ++i)
                    for (std::uint32_t e = c.incidence_start[off + i]; e < c.incidence_start[off + i + 1]; ++e)
                        if (c.touching[c.incidence[e].contact()] && c.incidence[e].contact() < c.pair_count()) { // not a wall
                            ++count;
                            break;
                        }
                return count;
            },
            [](std::size_t a, std::size_t b) { return a + b; });
    }
    load.area_in_contact_m2 = static_cast<double>(load.nodes_in_contact) * w.membrane.node_area_m2;
    return load;
}

double membrane_volume_m3(const World& w)
{
    const MembraneMesh& m = w.membrane;
    const auto& x = w.of(BodyKind::membrane).x[0];
    // Divergence theorem with the field (x, y, 0)/2: V = Σ_faces ∫ (x n_x + y n_y)/2 dA;
    // the flat rims contribute nothing. Triangle normals point inwards, hence the sign.
    double v = 0.0;
    for (const auto& t : m.triangles) {
        const Vec3 area_n = 0.5 * (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]); // A n_in
        const Vec3 centre = (x[t[0]] + x[t[1]] + x[t[2]]) / 3.0;
        v -= 0.5 * (centre.x() * area_n.x() + centre.y() * area_n.y());
    }
    return v;
}

} // namespace wiredem::engine
