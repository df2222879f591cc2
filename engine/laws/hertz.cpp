#include "laws/hertz.hpp"

#include <array>

namespace wiredem::engine {

double hertz_restitution(double m, double v0, double e_star, double r_star, double gamma)
{
    // Scale time by the undamped contact time so that one step size fits every
    // pair: 20000 RK4 steps per contact resolve e to ~1e-8.
    const double tc = hertz_contact_time_s(m, v0, e_star, r_star);
    const double h = tc / 20000.0;
    const double k = (4.0 / 3.0) * e_star * std::sqrt(r_star);
    auto accel = [&](double xi, double rate) {
        if (xi <= 0.0) return 0.0;
        const double f = k * std::sqrt(xi) * (xi + gamma * rate);
        return -std::max(f, 0.0) / m;
    };
    double xi = 0.0, rate = v0;
    for (int step = 0; step < 400000; ++step) {
        const std::array<double, 2> k1{rate, accel(xi, rate)};
        const std::array<double, 2> k2{rate + 0.5 * h * k1[1], accel(xi + 0.5 * h * k1[0], rate + 0.5 * h * k1[1])};
        const std::array<double, 2> k3{rate + 0.5 * h * k2[1], accel(xi + 0.5 * h * k2[0], rate + 0.5 * h * k2[1])};
        const std::array<double, 2> k4{rate + h * k3[1], accel(xi + h * k3[0], rate + h * k3[1])};
        xi += h / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]);
        rate += h / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]);
        // The contact ends when ξ returns to zero, or earlier when the damped
        // force reaches zero while separating (ξ + γ ξ̇ ≤ 0): from then on the
        // bodies only separate.
        if (rate < 0.0 && (xi <= 0.0 || xi + gamma * rate <= 0.0)) break;
    }
    return std::clamp(-rate / v0, 0.0, 1.0);
}

double hertz_damping_for_restitution_s(double restitution, double m, double v0, double e_star, double r_star)
{
    if (restitution >= 1.0) return 0.0;
    // Bracket: e(0) = 1, grow the upper bound until e drops below the target.
    const double tc = hertz_contact_time_s(m, v0, e_star, r_star);
    double lo = 0.0, hi = tc * 1e-3;
    while (hertz_restitution(m, v0, e_star, r_star, hi) > restitution && hi < 1e3 * tc) hi *= 2.0;
    for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (hertz_restitution(m, v0, e_star, r_star, mid) > restitution ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

} // namespace wiredem::engine
