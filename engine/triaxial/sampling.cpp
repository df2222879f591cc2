// Sampling a column test; see sampling.hpp.
#include "triaxial/sampling.hpp"

#include "analysis/stress.hpp"
#include "energy.hpp"
#include "forces/membrane_forces.hpp"
#include "forces/wire_forces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wiredem::engine {

double plate_compression_n(const World& w, std::size_t wall)
{
    return -w.wall_loads[wall].total_force_n.dot(w.walls[wall].normal);
}

std::uint64_t steps_per_sample(double sample_interval_s, double dt_s)
{
    // Saturating: a hostile estimate's ratio can exceed what the cast holds.
    const double steps = std::max(1.0, std::round(sample_interval_s / dt_s));
    constexpr double largest = 18446744073709549568.0; // the largest double below 2⁶⁴
    return steps < largest ? static_cast<std::uint64_t>(steps) : std::numeric_limits<std::uint64_t>::max();
}

std::optional<std::string> sample_interval_warning(double sample_interval_s, double dt_s)
{
    if (std::round(sample_interval_s / dt_s) >= 1.0) return std::nullopt;
    return "sample_interval_s " + format_number(sample_interval_s) + " s is shorter than half the time step "
         + format_number(dt_s) + " s: the record has a row every step";
}

std::vector<double> snapshot_plan(double target_axial_strain, const std::vector<double>& requested)
{
    std::vector<double> plan{0.0, target_axial_strain};
    for (double e : requested) plan.push_back(std::clamp(e, 0.0, target_axial_strain));
    std::sort(plan.begin(), plan.end());
    plan.erase(std::unique(plan.begin(), plan.end()), plan.end());
    return plan;
}

void take_due_snapshots(const World& w, const std::vector<double>& plan, std::size_t& next, double axial_strain,
    double time_s, std::vector<TriaxialSnapshot>& out)
{
    while (next < plan.size() && axial_strain >= plan[next]) {
        TriaxialSnapshot snap = take_triaxial_snapshot(w);
        snap.requested_axial_strain = plan[next];
        snap.axial_strain = axial_strain;
        snap.time_s = time_s;
        out.push_back(std::move(snap));
        ++next;
    }
}

void TriaxialSeries::push_back(const TriaxialSample& s)
{
    time_s.push_back(s.time_s);
    phase.push_back(static_cast<std::uint8_t>(s.phase));
    axial_strain.push_back(s.axial_strain);
    height_m.push_back(s.height_m);
    top_plate_force_n.push_back(s.top_plate_force_n);
    bottom_plate_force_n.push_back(s.bottom_plate_force_n);
    column_radius_m.push_back(s.column_radius_m);
    confining_pressure_pa.push_back(s.confining_pressure_pa);
    sigma1_pa.push_back(s.sigma1_pa);
    sigma3_effective_pa.push_back(s.sigma3_effective_pa);
    deviatoric_stress_pa.push_back(s.deviatoric_stress_pa);
    stress_ratio.push_back(s.stress_ratio);
    kinetic_energy_j.push_back(s.kinetic_energy_j);
    elastic_energy_j.push_back(s.elastic_energy_j);
    contacts.push_back(s.contacts);
    sliding_contacts.push_back(s.sliding_contacts);
    membrane_contacts.push_back(s.membrane_contacts);
    wire_strain_mean.push_back(s.wire_strain_mean);
    wire_strain_max.push_back(s.wire_strain_max);
    inertial_number.push_back(s.inertial_number);
}

QuasiStaticVerdict quasi_static_verdict(const TriaxialSeries& s, std::size_t loading_start)
{
    QuasiStaticVerdict v;
    double ratio_sum = 0.0;
    std::size_t rows = 0;
    for (std::size_t i = loading_start; i < s.size(); ++i, ++rows) {
        v.max_inertial_number = std::max(v.max_inertial_number, s.inertial_number[i]);
        const double ratio = s.elastic_energy_j[i] > 0.0 ? s.kinetic_energy_j[i] / s.elastic_energy_j[i]
                                                         : std::numeric_limits<double>::infinity();
        v.max_kinetic_to_elastic = std::max(v.max_kinetic_to_elastic, ratio);
        ratio_sum += ratio;
    }
    v.mean_kinetic_to_elastic = rows > 0 ? ratio_sum / static_cast<double>(rows) : 0.0;
    if (v.max_inertial_number > max_quasi_static_inertial_number)
        v.warning = "inertial number reached " + format_number(v.max_inertial_number) + " (quasi-static below "
                  + format_number(max_quasi_static_inertial_number) + ")";
    if (v.mean_kinetic_to_elastic > max_quasi_static_energy_ratio)
        v.warning += std::string(v.warning.empty() ? "" : "; ") + "kinetic/elastic energy averaged "
                   + format_number(v.mean_kinetic_to_elastic) + " over the loading (quasi-static below "
                   + format_number(max_quasi_static_energy_ratio) + ")";
    v.quasi_static = v.warning.empty();
    return v;
}

std::vector<double> volumetric_strains(const TriaxialSeries& s, double initial_volume_m3)
{
    std::vector<double> e(s.size());
    for (std::size_t i = 0; i < s.size(); ++i)
        e[i] = analysis::volumetric_strain(
            initial_volume_m3, analysis::cylinder_volume_m3(s.column_radius_m[i], s.height_m[i]));
    return e;
}

void measure_energies_and_contacts(const World& w, ThreadPool& pool, TriaxialSample& s)
{
    const ContactList& c = w.contacts;
    s.kinetic_energy_j = kinetic_energy_j(w, pool);
    s.elastic_energy_j = elastic_energy(w, pool).total_j(); // held bodies carry none

    struct Count {
        std::uint64_t touching = 0, sliding = 0;
    };
    const Count pairs = reduce_blocks(
        pool, c.size(), Count{},
        [&](std::size_t b, std::size_t e) {
            Count n;
            for (std::size_t p = b; p < e; ++p)
                if (c.touching[p]) {
                    ++n.touching;
                    if (!c.tangential[p].sticking) ++n.sliding;
                }
            return n;
        },
        [](Count a, const Count& b) {
            a.touching += b.touching;
            a.sliding += b.sliding;
            return a;
        });
    s.contacts = pairs.touching; // body pairs and body–wall contacts
    s.sliding_contacts = pairs.sliding;

    const std::vector<double>& strain = w.wire_forces.segment_strain;
    if (!strain.empty()) {
        double sum = 0.0, max = strain.front();
        for (double e : strain) {
            sum += e;
            max = std::max(max, e);
        }
        s.wire_strain_mean = sum / static_cast<double>(strain.size());
        s.wire_strain_max = max;
    }
}

TriaxialSample measure_triaxial_sample(const World& w, ThreadPool& pool, std::size_t top_plate_wall,
    std::size_t bottom_plate_wall, double initial_height_m)
{
    TriaxialSample s;
    const Wall& top = w.walls[top_plate_wall];
    const Wall& bottom = w.walls[bottom_plate_wall];
    s.height_m = top.point_m.z() - bottom.point_m.z();
    s.axial_strain = analysis::axial_strain(initial_height_m, s.height_m);
    s.top_plate_force_n = plate_compression_n(w, top_plate_wall);
    s.bottom_plate_force_n = plate_compression_n(w, bottom_plate_wall);

    // Column radius (the model spec §6.3): grains touching the membrane, each
    // counted once. The grain–membrane pairs are one group of the list,
    // sorted by (grain, node) (pair_key), so a grain's are consecutive.
    const TranslationalState& grains = w.of(BodyKind::grain);
    const ContactList& c = w.contacts;
    std::vector<double> radial_m;
    std::uint32_t previous = std::numeric_limits<std::uint32_t>::max();
    for (std::size_t p = 0; p < c.size(); ++p) {
        if (!c.touching[p] || c.first[p].kind() != BodyKind::grain || c.second[p].kind() != BodyKind::membrane) continue;
        const std::uint32_t g = c.first[p].index();
        if (g == previous) continue;
        previous = g;
        const Vec3& x = grains.x[0][g];
        radial_m.push_back(std::hypot(x.x(), x.y()));
    }
    double radius_sum_m = 0.0, enclosing_m = 0.0;
    for (std::size_t i = 0; i < grains.size(); ++i) {
        radius_sum_m += grains.radius_m[i];
        const Vec3& x = grains.x[0][i];
        enclosing_m = std::max(enclosing_m, std::hypot(x.x(), x.y()) + grains.radius_m[i]);
    }
    const double mean_grain_radius_m = grains.size() ? radius_sum_m / static_cast<double>(grains.size()) : 0.0;
    s.column_radius_m = analysis::column_radius_m(radial_m, mean_grain_radius_m).value_or(enclosing_m);

    const MembraneLoad load = membrane_contact_load(w, pool);
    s.membrane_contacts = load.contacts;
    s.sigma1_pa = analysis::axial_stress_pa(s.top_plate_force_n, s.column_radius_m);
    s.sigma3_effective_pa = analysis::effective_confining_pressure_pa(load.normal_force_n, s.column_radius_m, s.height_m);
    s.deviatoric_stress_pa = analysis::deviatoric_stress_pa(s.sigma1_pa, s.sigma3_effective_pa);
    s.stress_ratio = analysis::stress_ratio(s.sigma1_pa, s.sigma3_effective_pa);
    s.volume_m3 = analysis::cylinder_volume_m3(s.column_radius_m, s.height_m);
    measure_energies_and_contacts(w, pool, s);
    return s;
}

TriaxialSnapshot take_triaxial_snapshot(const World& w)
{
    TriaxialSnapshot snap;
    const TranslationalState& g = w.of(BodyKind::grain);
    snap.grain_position_m = g.x[0];
    snap.grain_radius_m = g.radius_m;
    snap.grain_velocity_m_per_s.reserve(g.size());
    for (const Vec3& v : g.x[1]) snap.grain_velocity_m_per_s.push_back(v / w.dt_s);
    snap.wire_node_position_m = w.of(BodyKind::wire).x[0];
    snap.wire_segment_strain = w.wire_forces.segment_strain;
    snap.membrane_node_position_m = w.of(BodyKind::membrane).x[0];
    snap.membrane_triangles = w.membrane.triangles;

    ForceNetwork& f = snap.forces;
    const ContactList& c = w.contacts;
    for (std::size_t p = 0; p < c.pair_count(); ++p) {
        if (!c.touching[p]) continue;
        f.first.push_back(c.first[p]);
        f.second.push_back(c.second[p]);
        f.force_n.push_back(c.output[p].force_n);
        f.normal_force_n.push_back(c.output[p].normal_force_n);
    }
    for (std::size_t p = c.pair_count(); p < c.size(); ++p) { // by wall, then body
        if (c.output[p].force_n.isZero(0.0)) continue;
        f.wall.push_back(c.second[p].index());
        f.wall_body.push_back(c.first[p]);
        f.wall_force_n.push_back(c.output[p].force_n);
    }
    return snap;
}

void record_wire_breaks(const World& w, std::size_t breaks_before_test, double test_time_s, double axial_strain,
    std::vector<TestWireBreak>& recorded)
{
    for (std::size_t i = breaks_before_test + recorded.size(); i < w.wire_breaks.size(); ++i) {
        const WireBreak& b = w.wire_breaks[i];
        recorded.push_back({.event = b, .test_time_s = test_time_s, .axial_strain = axial_strain,
            .position_m = wire_segment_position_m(w.wire, b.segment)});
    }
}

const char* to_string(PeakFailure f)
{
    switch (f) {
    case PeakFailure::grains: return "grains";
    case PeakFailure::wire: return "wire";
    case PeakFailure::grains_after_break: return "grains_after_break";
    }
    return "?";
}

PeakFailure peak_failure(const TriaxialSeries& series, std::size_t peak, const std::vector<TestWireBreak>& breaks)
{
    if (breaks.empty() || peak >= series.size()) return PeakFailure::grains;
    const double first = breaks.front().test_time_s;
    const double before = peak > 0 ? series.time_s[peak - 1] : -std::numeric_limits<double>::infinity();
    const double after = peak + 1 < series.size() ? series.time_s[peak + 1] : std::numeric_limits<double>::infinity();
    if (first <= before) return PeakFailure::grains_after_break;
    if (first <= after) return PeakFailure::wire;
    return PeakFailure::grains;
}

} // namespace wiredem::engine
