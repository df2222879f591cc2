#include "forces/membrane_forces.hpp"

#include "forces/membrane_simd.hpp"
#include "core/assert.hpp"
#include "laws/membrane_edge.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wiredem::engine {

void build_membrane(World& w, const MembraneSpec& spec)
{
    MembraneMesh& m = w.membrane;
    WIREDEM_ASSERT(w.of(BodyKind::membrane).size() == 0, "one membrane per World");
    m = MembraneMesh{};
    m.radius_m = spec.radius_m;
    m.height_m = spec.height_m;
    m.base_z_m = spec.base_z_m;
    m.edge_stiffness_n_per_m = membrane_edge_stiffness_n_per_m(spec.youngs_modulus_pa, spec.thickness_m);
    m.edge_law = spec.edges;
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

    for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < columns; ++c) {
            const double phi = 2.0 * std::numbers::pi * (static_cast<double>(c) + 0.5 * static_cast<double>(r % 2)) / columns;
            const Vec3 x(spec.radius_m * std::cos(phi), spec.radius_m * std::sin(phi), spec.base_z_m + r * dz);
            add_node(w, BodyKind::membrane, x, spec.contact_radius_m, 0.0, material); // rigid: no mass yet, so fixed
            m.node_fixed.push_back(r == 0 || r + 1 == rows ? 1 : 0);
            m.node_mass_kg.push_back(node_mass);
        }
    // The elements in grid order (state/membrane.hpp), at rest in the cylinder.
    const auto& x = w.of(BodyKind::membrane).x[0];
    m.edges = membrane_grid_edges(rows, columns);
    for (const auto& e : m.edges) m.edge_rest_m.push_back((x[e[1]] - x[e[0]]).norm());
    m.triangles = membrane_grid_triangles(rows, columns);
    w.membrane_forces.node_force_n.assign(rows * columns, Vec3::Zero());
    m.rigid = true;
}

namespace {

/// Node (row, column) of a grid, the column wrapping around (from −columns on).
std::uint32_t grid_node(std::size_t columns, std::size_t row, std::ptrdiff_t column)
{
    const auto n = static_cast<std::ptrdiff_t>(columns);
    return static_cast<std::uint32_t>(row * columns + static_cast<std::size_t>((column + n) % n));
}

} // namespace

std::vector<std::array<std::uint32_t, 2>> membrane_grid_edges(std::size_t rows, std::size_t columns)
{
    std::vector<std::array<std::uint32_t, 2>> edges(membrane_edge_count(rows, columns));
    for (std::size_t r = 0; r + 1 < rows; ++r)
        for (std::size_t c = 0; c < columns; ++c) {
            const auto column = static_cast<std::ptrdiff_t>(c);
            if (r > 0) // between the rims
                edges[membrane_edge_index(rows, columns, MembraneEdge::along, r, c)] = {grid_node(columns, r, column), grid_node(columns, r, column + 1)};
            for (const bool second : {false, true})
                edges[membrane_edge_index(rows, columns, second ? MembraneEdge::up_second : MembraneEdge::up_first, r, c)]
                    = {grid_node(columns, r, column), grid_node(columns, r + 1, membrane_up_column(r, column, second))};
        }
    return edges;
}

std::vector<std::array<std::uint32_t, 3>> membrane_grid_triangles(std::size_t rows, std::size_t columns)
{
    std::vector<std::array<std::uint32_t, 3>> triangles(membrane_triangle_count(rows, columns));
    for (std::size_t r = 0; r + 1 < rows; ++r)
        for (std::size_t c = 0; c < columns; ++c)
            for (int which = 0; which < 2; ++which) {
                auto& t = triangles[membrane_triangle_index(rows, columns, which, r, c)];
                const auto corners = membrane_triangle(r, which);
                for (int k = 0; k < 3; ++k)
                    t[k] = grid_node(columns, r + corners[k][0], static_cast<std::ptrdiff_t>(c) + corners[k][1]);
            }
    return triangles;
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
        std::vector<Vec3>& f = w.membrane_forces.node_force_n;
        std::fill(f.begin(), f.end(), Vec3::Zero());
    }
}

namespace {

/// The three components at `at`, `stride` doubles apart.
Vec3 components_at(const double* at, std::ptrdiff_t stride) { return {at[0], at[stride], at[2 * stride]}; }
Vec3 column_of(const MembraneRow& r, std::size_t c) { return components_at(r.data + c, r.stride); }
void put_column(const MembraneRow& r, std::size_t c, const Vec3& v) { r.x()[c] = v.x(), r.y()[c] = v.y(), r.z()[c] = v.z(); }

// The scalar kernels: what MembraneSimdKernels does lanes at a time, column
// by column in the same order.
void scalar_edges(MembraneRow a, MembraneRow b, const double* rest_m, double stiffness_n_per_m, MembraneEdgeLaw law,
    MembraneRow out, std::size_t count)
{
    for (std::size_t c = 0; c < count; ++c)
        put_column(out, c, membrane_edge_force_n(column_of(a, c), column_of(b, c), rest_m[c], stiffness_n_per_m, law));
}

void scalar_triangles(MembraneRow a, MembraneRow b, MembraneRow c, double pressure_pa, MembraneRow out, std::size_t count)
{
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3 xa = column_of(a, i);
        // ½ (b−a)×(c−a) = A n_in: the pressure force σ₃ A n_in, a third per node.
        put_column(out, i, pressure_pa / 6.0 * (column_of(b, i) - xa).cross(column_of(c, i) - xa));
    }
}

void scalar_sums(const double* const* terms, std::ptrdiff_t stride, Vec3* out, std::size_t count)
{
    for (std::size_t c = 0; c < count; ++c) {
        Vec3 f = Vec3::Zero();
        for (std::size_t t = 0; t < membrane_added_terms; ++t) f += components_at(terms[t] + c, stride);
        for (std::size_t t = membrane_added_terms; t < membrane_terms; ++t) f -= components_at(terms[t] + c, stride);
        out[c] = f;
    }
}

void scalar_split(const Vec3* x, MembraneRow out, std::size_t count)
{
    for (std::size_t c = 0; c < count; ++c) put_column(out, c, x[c]);
}

/// Rows of the grid as compute_membrane_forces keeps them: `padded` columns
/// (a whole number of SIMD blocks) plus one column on either side, each
/// holding the value of the column it stands for modulo `columns`. The
/// storage is the thread's own, kept from call to call; every column a kernel
/// reads is written first.
class RowStore {
public:
    RowStore(std::size_t columns, std::size_t padded, std::size_t rows) : columns_(columns), stride_(padded + 2)
    {
        thread_local std::vector<double> storage;
        if (storage.size() < 3 * stride_ * rows) storage.resize(3 * stride_ * rows);
        data_ = storage.data();
    }
    /// Row k of the store; column c at [c], c from −1 to padded.
    [[nodiscard]] MembraneRow row(std::size_t k) const
    {
        return {data_ + 3 * stride_ * k + 1, static_cast<std::ptrdiff_t>(stride_)};
    }
    /// Fills the columns past the row's end and before its start from the
    /// ones they stand for.
    void wrap(MembraneRow r) const
    {
        for (double* v : {r.x(), r.y(), r.z()}) {
            v[-1] = v[columns_ - 1];
            for (std::size_t c = columns_; c + 1 < stride_; ++c) v[c] = v[c - columns_];
        }
    }
    void clear(MembraneRow r) const
    {
        for (double* v : {r.x(), r.y(), r.z()}) std::fill(v - 1, v + stride_ - 1, 0.0);
    }

private:
    std::size_t columns_, stride_;
    double* data_ = nullptr;
};

/// Rows processed per task: each task also works out the elements of the row
/// below its first (what one row's nodes take from the row below).
constexpr std::size_t membrane_rows_per_task = 16;

} // namespace

void compute_membrane_forces(World& w, ThreadPool& pool)
{
    const MembraneMesh& m = w.membrane;
    const auto& x = w.of(BodyKind::membrane).x[0];
    // Held nodes do not move whatever their springs and the pressure do (the
    // preparation's rigid membrane: ~9 % of a paper-size pour's step time).
    if (x.empty() || m.rigid) return;
    std::vector<Vec3>& node_force = w.membrane_forces.node_force_n;
    // Columns lanes at a time where the CPU can (same bits, membrane_simd.hpp).
    const MembraneSimdKernels simd = simd_membrane_kernels();
    const MembraneSimdKernels kernels = simd ? simd : MembraneSimdKernels{1, &scalar_edges, &scalar_triangles, &scalar_sums, &scalar_split};
    const std::size_t rows = m.rows, columns = m.columns;
    const std::size_t padded = simd ? (columns + simd.lanes - 1) / simd.lanes * simd.lanes : columns;
    const double k = m.edge_stiffness_n_per_m, p = m.pressure_pa;

    parallel_for_blocks(pool, rows, membrane_rows_per_task, [&](std::size_t begin, std::size_t end) {
        // The rows this task keeps: positions of rows r and r+1; the
        // elements of row r (along, up first, up second, triangle 0, 1) and
        // the up edges and triangles of row r−1; the rest lengths of the last
        // block of each kind of edge.
        enum : std::size_t { pos_low, pos_high, along, up0, up1, tri0, tri1, below_up0, below_up1, below_tri0, below_tri1, rest, store_rows };
        RowStore store(columns, padded, store_rows);
        MembraneRow pos[2] = {store.row(pos_low), store.row(pos_high)};
        MembraneRow here[5] = {store.row(along), store.row(up0), store.row(up1), store.row(tri0), store.row(tri1)};
        MembraneRow below[4] = {store.row(below_up0), store.row(below_up1), store.row(below_tri0), store.row(below_tri1)};
        const MembraneRow rest_rows = store.row(rest);
        double* rest_of[3] = {rest_rows.x(), rest_rows.y(), rest_rows.z()};

        // Whole blocks of lanes by the kernel, the rest column by column.
        const std::size_t whole = columns / kernels.lanes * kernels.lanes;
        const auto load_positions = [&](std::size_t r, MembraneRow into) {
            kernels.split(x.data() + r * columns, into, whole);
            scalar_split(x.data() + r * columns + whole, into.shifted(static_cast<std::ptrdiff_t>(whole)), columns - whole);
            store.wrap(into);
        };
        // The elements node (r, c) owns, for every column: `low` holds row r's
        // positions, `high` row r+1's.
        const auto elements = [&](std::size_t r, MembraneRow low, MembraneRow high, MembraneRow* out) {
            if (r + 1 >= rows) { // the top row owns nothing
                for (int e = 0; e < 5; ++e) store.clear(out[e]);
                return;
            }
            // The edges of one kind: the whole blocks read their rest lengths
            // where the mesh keeps them; the last, padded block from a copy
            // (the row's end may be the list's).
            const auto edges = [&](MembraneEdge kind, MembraneRow other, MembraneRow into) {
                const double* rest = m.edge_rest_m.data() + membrane_edge_index(rows, columns, kind, r, 0);
                kernels.edges(low, other, rest, k, m.edge_law, into, whole);
                if (whole == padded) return;
                double* tail = rest_of[static_cast<int>(kind)];
                for (std::size_t c = whole; c < padded; ++c) tail[c - whole] = rest[c % columns];
                const auto from = static_cast<std::ptrdiff_t>(whole);
                kernels.edges(low.shifted(from), other.shifted(from), tail, k, m.edge_law, into.shifted(from), padded - whole);
            };
            if (r > 0) edges(MembraneEdge::along, low.shifted(1), out[0]); // between the rims
            else store.clear(out[0]);
            for (int second = 0; second < 2; ++second)
                edges(second ? MembraneEdge::up_second : MembraneEdge::up_first,
                    high.shifted(membrane_up_column(r, 0, second == 1)), out[1 + second]);
            for (int which = 0; which < 2; ++which) {
                const auto corners = membrane_triangle(r, which);
                MembraneRow at[3];
                for (int i = 0; i < 3; ++i) at[i] = (corners[i][0] == 0 ? low : high).shifted(corners[i][1]);
                kernels.triangles(at[0], at[1], at[2], p, out[3 + which], padded);
            }
            for (int e = 0; e < 5; ++e) store.wrap(out[e]);
        };

        // Start from the row below the first: its up edges and triangles.
        for (int e = 0; e < 4; ++e) store.clear(below[e]);
        if (begin > 0) {
            MembraneRow scratch[5] = {here[0], below[0], below[1], below[2], below[3]};
            load_positions(begin - 1, pos[0]);
            load_positions(begin, pos[1]);
            elements(begin - 1, pos[0], pos[1], scratch);
            std::swap(pos[0], pos[1]);
        } else {
            load_positions(begin, pos[0]);
        }
        for (std::size_t r = begin; r < end; ++r) {
            if (r + 1 < rows) load_positions(r + 1, pos[1]);
            elements(r, pos[0], pos[1], here);
            // Node (r, c)'s twelve terms, in this order: added, its along
            // edge, its up edges, the triangles of row r, then of row r−1,
            // with a corner at it; subtracted, the along edge of (r, c−1)
            // and the up edges of row r−1 that end at it.
            std::array<const double*, membrane_terms> terms;
            std::size_t t = 0;
            terms[t++] = here[0].data;
            terms[t++] = here[1].data;
            terms[t++] = here[2].data;
            for (int lower = 1; lower >= 0; --lower) { // row r's quads (lower corners), then row r−1's (upper corners)
                const std::size_t quad_row = lower ? r : r + 1; // only its parity counts: r−1 ≡ r+1
                for (int which = 0; which < 2; ++which)
                    for (const auto& corner : membrane_triangle(quad_row, which))
                        if (corner[0] == (lower ? 0 : 1)) terms[t++] = (lower ? here[3 + which] : below[2 + which]).data - corner[1];
            }
            WIREDEM_ASSERT(t == membrane_added_terms, "nine terms added");
            terms[t++] = here[0].data - 1;
            for (int second = 0; second < 2; ++second) // row r−1's column c' ends at c' + membrane_up_column(r−1, 0, …)
                terms[t++] = below[second].data - membrane_up_column(r + 1, 0, second == 1);
            WIREDEM_ASSERT(t == membrane_terms, "twelve terms per node");
            Vec3* out = node_force.data() + r * columns;
            const std::ptrdiff_t stride = here[0].stride; // every row of the store's
            kernels.sums(terms.data(), stride, out, whole);
            for (const double*& term : terms) term += whole;
            scalar_sums(terms.data(), stride, out + whole, columns - whole);
            // Row r is the next row's row below.
            for (int e = 0; e < 4; ++e) std::swap(below[e], here[1 + e]);
            std::swap(pos[0], pos[1]);
        }
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
