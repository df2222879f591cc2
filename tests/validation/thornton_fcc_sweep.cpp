// wiredem-thornton-fcc: Thornton's face-centred cubic array in the cuboid
// cell (fcc.hpp) at μ = 0, 0.1, …, 0.5, every row of each test as CSV on
// stdout: the loading curves σ₁/σ₃ against ε_a that
// scripts/validation_figures.py plots beside 2(1 + μ)/(1 − μ)
// (docs/validation.md). Optional arguments: the μ to run (one), e.g. 0.3;
// the unit cells per axis (2); verlet (else Gear-5); free (spins not held);
// dt=F (the time step, F × the auto step; 0.5 by default); v=V (the plate's
// speed [m/s]); alpha=A (the servo's relaxation factor); kt=K (k_t [1/m]); gt=G (γ_t [s/m]);
// end=E (the target axial strain, 0.015 by default); contacts (on stderr, the
// grain–grain contacts at the end by family: docs/validation.md, "After the
// first slip").
#include "fcc.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace wiredem::engine;
using namespace wiredem::engine::validation;

namespace {

/// The grain–grain contacts touching at the end, by family: the xy-plane ones
/// (normal ⟂ z, the loading axis) and the inclined ones, each split into the
/// contacts of two interior spheres and those with a sphere on a wall. Per
/// group: the count, the mean |F_n| over σ₃ r², the mobilisation |F_t|/(μ F_n)
/// (mean, and the shares at ≥ 0.99 and < 0.5), the share sliding, and, for the
/// inclined ones, the ratio 2 Σ(N + T)/Σ(N − T) they would give in the
/// infinite array (Thornton's 2(1 + μ)/(1 − μ) when every one has T = μ N).
void print_contact_families(const World& w, double mu)
{
    const ContactList& c = w.contacts;
    const auto& g = w.bodies[0];
    std::vector<char> on_wall(g.size(), 0);
    for (std::size_t k = 0; k < c.size(); ++k)
        if (c.touching[k] && is_wall(c.second[k])) on_wall[c.first[k].index()] = 1;
    struct Group { int n = 0, full = 0, half = 0, sliding = 0; double fn = 0, mob = 0, up = 0, down = 0; };
    Group groups[2][2]; // [inclined][boundary]
    const double r = g.radius_m[0];
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (!c.touching[k] || is_wall(c.second[k])) continue;
        const std::uint32_t i = c.first[k].index(), j = c.second[k].index();
        const Vec3 n = (g.x[0][j] - g.x[0][i]).normalized();
        const bool inclined = std::abs(n.z()) > 0.3;
        Group& gr = groups[inclined][on_wall[i] || on_wall[j]];
        const double fn = c.output[k].normal_force_n, ft = c.output[k].normal_x_tangential_n.norm();
        const double m = mu > 0.0 && fn > 0.0 ? ft / (mu * fn) : 0.0;
        ++gr.n;
        gr.fn += fn / (sigma3_pa * r * r);
        gr.mob += m;
        gr.full += m >= 0.99;
        gr.half += m < 0.5;
        gr.sliding += !c.tangential[k].sticking;
        gr.up += fn + ft;
        gr.down += fn - ft;
    }
    for (int inclined = 0; inclined < 2; ++inclined)
        for (int boundary = 0; boundary < 2; ++boundary) {
            const Group& gr = groups[inclined][boundary];
            if (gr.n == 0) continue;
            std::fprintf(stderr, "  %s, %s: %d contacts, F_n/(sigma3 r^2) %.3f, T/(mu N) mean %.3f, >= 0.99: %.2f, < 0.5: %.2f, "
                                 "sliding %.2f%s\n",
                inclined ? "inclined" : "xy-plane", boundary ? "a sphere on a wall" : "interior", gr.n, gr.fn / gr.n,
                gr.mob / gr.n, double(gr.full) / gr.n, double(gr.half) / gr.n, double(gr.sliding) / gr.n,
                inclined ? (", 2 sum(N+T)/sum(N-T) " + std::to_string(2 * gr.up / gr.down)).c_str() : "");
        }
}

} // namespace

int main(int argc, char** argv)
{
    std::vector<double> frictions{0.0, 0.1, 0.2, 0.3, 0.4, 0.5};
    if (argc > 1) frictions = {std::atof(argv[1])};
    FccOptions options;
    CuboidSettings settings = fcc_settings();
    bool contacts = false;
    if (argc > 2) options.cells = std::atoi(argv[2]);
    for (int a = 3; a < argc; ++a) {
        if (std::string(argv[a]) == "contacts") contacts = true;
        if (std::string(argv[a]).starts_with("end=")) settings.triaxial.target_axial_strain = std::atof(argv[a] + 4);
        if (std::string(argv[a]) == "verlet") options.integrator = Integrator::verlet;
        if (std::string(argv[a]) == "free") options.spins_held = false;
        if (std::string(argv[a]).starts_with("dt=")) options.time_step_fraction = std::atof(argv[a] + 3);
        if (std::string(argv[a]).starts_with("kt=")) options.tangential_stiffness_per_m = std::atof(argv[a] + 3);
        if (std::string(argv[a]).starts_with("gt=")) options.tangential_damping_s_per_m = std::atof(argv[a] + 3);
        if (std::string(argv[a]).starts_with("v=")) settings.triaxial.plate_speed_m_per_s = std::atof(argv[a] + 2);
        if (std::string(argv[a]).starts_with("alpha=")) settings.servo_relaxation = std::atof(argv[a] + 6);
    }
    std::printf("mu,phase,time_s,axial_strain,sigma1_pa,sigma_x_pa,sigma_y_pa,width_x_m,width_y_m,height_m,"
                "kinetic_energy_j,elastic_energy_j,sliding_contacts,contacts\n");
    int failed = 0;
    for (const double mu : frictions) {
        const FccRun run = run_fcc(mu, 1, options, settings);
        if (!run.error.empty()) {
            std::fprintf(stderr, "mu = %g: %s\n", mu, run.error.c_str());
            ++failed;
            continue;
        }
        const CuboidResult& r = run.result;
        const TriaxialSeries& s = r.triaxial.series;
        for (std::size_t i = 0; i < s.size(); ++i)
            std::printf("%g,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%llu,%llu\n", mu, int(s.phase[i]),
                s.time_s[i], s.axial_strain[i], s.sigma1_pa[i], r.sigma_x_pa[i], r.sigma_y_pa[i], r.width_x_m[i],
                r.width_y_m[i], s.height_m[i], s.kinetic_energy_j[i], s.elastic_energy_j[i],
                static_cast<unsigned long long>(s.sliding_contacts[i]), static_cast<unsigned long long>(s.contacts[i]));
        std::fprintf(stderr, "mu = %g: peak sigma1/sigma3 = %.6g (closed form %.6g) at strain %.4g; servo mean %.3g max %.3g\n",
            mu, run.peak_ratio, 2 * (1 + mu) / (1 - mu), s.axial_strain[run.peak_row], r.servo_mean_deviation,
            r.servo_max_deviation);
        if (contacts) print_contact_families(run.world, mu);
    }
    return failed == 0 ? 0 : 1;
}
