// wiredem-thornton-fcc: Thornton's face-centred cubic array in the cuboid
// cell (fcc.hpp) at μ = 0, 0.1, …, 0.5, every row of each test as CSV on
// stdout: the loading curves σ₁/σ₃ against ε_a that
// scripts/validation_figures.py plots beside 2(1 + μ)/(1 − μ)
// (docs/validation.md). Optional arguments: the μ to run (one), e.g. 0.3;
// the unit cells per axis (2); verlet (else Gear-5); free (spins not held);
// dt=F (the time step, F × the auto step; 0.5 by default); v=V (the plate's
// speed [m/s]); alpha=A (the servo's relaxation factor); kt=K (k_t [1/m]); gt=G (γ_t [s/m]).
#include "fcc.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace wiredem::engine;
using namespace wiredem::engine::validation;

int main(int argc, char** argv)
{
    std::vector<double> frictions{0.0, 0.1, 0.2, 0.3, 0.4, 0.5};
    if (argc > 1) frictions = {std::atof(argv[1])};
    FccOptions options;
    CuboidSettings settings = fcc_settings();
    if (argc > 2) options.cells = std::atoi(argv[2]);
    for (int a = 3; a < argc; ++a) {
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
    }
    return failed == 0 ? 0 : 1;
}
