// wiredem-chung-ooi: the sweeps of Chung & Ooi's oblique-impact benchmarks
// (tests 4–8) and the sphere–membrane-node case, through the engine, with the
// rigid-body lines beside them, as CSV on stdout. scripts/validation_figures.py
// plots them into docs/validation/ (docs/validation.md). Gear-5 at t_c/2000.
#include "impact.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

using namespace wiredem::engine;
using namespace wiredem::engine::validation;

namespace {

const Material aluminium_oxide{3.8e11, 0.23, 4000.0};
const Material aluminium_alloy{7.0e10, 0.33, 2700.0};
Material rigid(const Material& m) { return {1e3 * m.youngs_modulus_pa, m.poisson_ratio, m.density_kg_per_m3}; }

void row(const std::string& test, const std::string& material, double x, const ImpactCase& c)
{
    const ImpactResult r = run_impact(c);
    const RigidBodyImpact rb = rigid_body_impact(c);
    std::printf("%s,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", test.c_str(), material.c_str(), x,
        c.velocity1_m_per_s.x(), c.velocity1_m_per_s.z(), c.spin1_rad_per_s, c.radius1_m,
        r.velocity1_m_per_s.x(), r.velocity1_m_per_s.z(), r.spin1_rad_per_s,
        rb.velocity1_m_per_s.x(), rb.velocity1_m_per_s.z(), rb.spin1_rad_per_s, rb.slides_throughout ? 1 : 0);
}

} // namespace

int main()
{
    std::printf("test,material,x,vx0_m_per_s,vz0_m_per_s,spin0_rad_per_s,radius_m,vx_m_per_s,vz_m_per_s,spin_rad_per_s,"
                "rigid_vx_m_per_s,rigid_vz_m_per_s,rigid_spin_rad_per_s,rigid_slides\n");
    // Test 4: 3.9 m/s at θ = 1 … 89° from the normal, μ = 0.092.
    for (const auto& [name, m] : {std::pair{"aluminium_oxide", aluminium_oxide}, std::pair{"aluminium_alloy", aluminium_alloy}})
        for (int deg = 1; deg <= 89; deg += 2) {
            const double th = deg * std::numbers::pi / 180.0;
            ImpactCase c;
            c.material1 = m;
            c.material2 = rigid(m);
            c.radius1_m = 2.5e-3;
            c.friction_coeff = 0.092;
            c.velocity1_m_per_s = 3.9 * Vec3(std::sin(th), 0, -std::cos(th));
            row("4", name, deg, c);
        }
    // Test 6: head-on at 3.9 m/s with spin ω₀, |ω₀| R up to 10 v_n.
    for (int i = -40; i <= 40; ++i) {
        ImpactCase c;
        c.material1 = aluminium_oxide;
        c.material2 = rigid(aluminium_oxide);
        c.radius1_m = 2.5e-3;
        c.friction_coeff = 0.092;
        c.velocity1_m_per_s = Vec3(0, 0, -3.9);
        c.spin1_rad_per_s = i * 0.25 * 3.9 / c.radius1_m * 0.1;
        row("6", "aluminium_oxide", c.spin1_rad_per_s, c);
    }
    // Test 7: two equal spheres, the same angles as test 4.
    for (int deg = 1; deg <= 89; deg += 4) {
        const double th = deg * std::numbers::pi / 180.0;
        ImpactCase c;
        c.material1 = c.material2 = aluminium_oxide;
        c.radius1_m = c.radius2_m = 2.5e-3;
        c.target = Target::grain;
        c.friction_coeff = 0.092;
        c.velocity1_m_per_s = 3.9 * Vec3(std::sin(th), 0, -std::cos(th));
        row("7", "aluminium_oxide", deg, c);
    }
    // The paper's grain onto a free membrane node, 0.5 m/s at θ, μ = 0.3.
    for (int deg = 1; deg <= 89; deg += 4) {
        const double th = deg * std::numbers::pi / 180.0;
        ImpactCase c;
        c.material1 = Material{10e9, 0.3, 7800.0};
        c.radius1_m = 1.23e-3;
        c.target = Target::membrane_node;
        c.material2 = Material{0.1e9, 0.0, 1000.0};
        c.radius2_m = 0.5e-3;
        c.node_mass_kg = std::sqrt(3.0) / 2.0 * 1.25e-3 * 1.25e-3 * 1000.0 * 1e-3;
        c.friction_coeff = 0.3;
        c.velocity1_m_per_s = 0.5 * Vec3(std::sin(th), 0, -std::cos(th));
        row("membrane_node", "paper", deg, c);
    }
    return 0;
}
