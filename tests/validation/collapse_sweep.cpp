// wiredem-collapse: the collapse of columns without wire against the scaling
// laws of axisymmetric granular collapse (tests/triaxial/column_collapse.hpp),
// as CSV on stdout: one row per column height and release speed, with the
// laws' values beside the measured ones. scripts/collapse_figure.py runs it
// and plots docs/validation/collapse.png (docs/validation.md).
//
//   wiredem-collapse [RADIUS_M [LAYERS,… [SPEED_RATIO,… [MU_R,…]]]]
//
// Defaults: the tests' 8 mm column, 3 to 21 layers, release speeds 5 √(g Hᵢ)
// (the experiments' quick lift) and 0.05 √(g Hᵢ) (a slow release), rolling
// resistance μ_r = 0 (the model's spheres) and 0.1.
#include "column_collapse.hpp"

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

std::vector<double> numbers(const char* text)
{
    std::vector<double> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) out.push_back(std::stod(item));
    return out;
}

} // namespace

int main(int argc, char** argv)
{
    const double radius_m = argc > 1 ? std::stod(argv[1]) : 8e-3;
    const std::vector<double> layers = argc > 2 ? numbers(argv[2]) : std::vector<double>{3, 5, 7, 9, 13, 17, 21};
    const std::vector<double> speeds = argc > 3 ? numbers(argv[3]) : std::vector<double>{5.0, 0.05};
    const std::vector<double> rolling = argc > 4 ? numbers(argv[4]) : std::vector<double>{0.0, 0.1};
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::printf("membrane_radius_m,layers,rolling_friction_coeff,release_speed_ratio,release_speed_m_per_s,grains,initial_height_m,initial_radius_m,"
                "aspect_ratio,final_height_m,runout_radius_m,max_radius_m,runout,final_height,lube_runout,lube_final_height,"
                "at_rest,time_to_rest_s,escaped_grains\n");
    for (double mu_r : rolling)
        for (double speed : speeds)
            for (double n : layers) {
                    CollapseCase c;
                    c.rolling_friction_coeff = mu_r;
                    c.layers = static_cast<int>(n);
                    c.membrane_radius_m = radius_m;
                    c.release_speed_ratio = speed;
                    const auto r = run_collapse(c, threads);
                    if (!r.ok()) {
                        std::fprintf(stderr, "wiredem-collapse: %d layers at %g: %s\n", c.layers, speed, r.error().c_str());
                        return 1;
                    }
                    const CollapseOutcome& o = r.value();
                    const double a = o.aspect_ratio();
                    std::printf("%.6g,%d,%.6g,%.6g,%.6g,%zu,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%.6g,%zu\n", radius_m, c.layers, mu_r,
                        speed, o.release_speed_m_per_s, o.grains, o.initial_height_m, o.initial_radius_m, a, o.deposit.height_m,
                        o.deposit.runout_radius_m, o.deposit.max_radius_m, o.runout(), o.final_height(), lube_runout(a),
                        lube_final_height(a), o.settling.at_rest ? 1 : 0, o.settling.time_to_rest_s, o.settling.escaped_grains);
                    std::fflush(stdout);
                }
    return 0;
}
