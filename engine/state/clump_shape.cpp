#include "state/clump_shape.hpp"

#include "core/assert.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace wiredem::engine {
namespace {

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n from the
/// usual first guess cos(π(i − ¼)/(n + ½)); converged to rounding).
void gauss_legendre(int n, std::vector<double>& node, std::vector<double>& weight)
{
    node.assign(static_cast<std::size_t>(n), 0.0);
    weight.assign(static_cast<std::size_t>(n), 0.0);
    for (int i = 0; i < (n + 1) / 2; ++i) {
        double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
        double dp = 0.0;
        for (int iter = 0; iter < 100; ++iter) {
            double p0 = 1.0, p1 = x; // P_0, P_1
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            // P_n = p1, P_{n−1} = p0; P_n' = n (x P_n − P_{n−1})/(x² − 1)
            dp = n * (x * p1 - p0) / (x * x - 1.0);
            const double step = p1 / dp;
            x -= step;
            if (std::abs(step) < 1e-16) break;
        }
        const double w = 2.0 / ((1.0 - x * x) * dp * dp);
        node[static_cast<std::size_t>(i)] = x;
        node[static_cast<std::size_t>(n - 1 - i)] = -x;
        weight[static_cast<std::size_t>(i)] = weight[static_cast<std::size_t>(n - 1 - i)] = w;
    }
}

} // namespace

UnionMassProperties union_mass_properties(const std::vector<ClumpSphere>& spheres, int angular_nodes)
{
    WIREDEM_ASSERT(!spheres.empty() && angular_nodes >= 2, "spheres and at least two nodes");
    std::vector<double> mu, mu_weight;
    gauss_legendre(angular_nodes, mu, mu_weight);
    const int n_phi = 2 * angular_nodes;
    const double phi_weight = 2.0 * std::numbers::pi / n_phi;

    // Moments of the union about the template's origin: ∫ dV, ∫ p dV, ∫ p pᵀ dV.
    double volume = 0.0;
    Vec3 first = Vec3::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    std::vector<std::pair<double, double>> cut; // the radii along a ray inside earlier spheres
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        const Vec3 c = spheres[i].centre_m;
        const double big_r = spheres[i].radius_m;
        // The polar axis points at the earlier sphere that cuts the deepest
        // into this one, and cos θ is split where its cut's radial limits
        // are not smooth (the intersection circle; the rays tangent to it),
        // so a pair of spheres is integrated to Gauss's accuracy.
        Vec3 axis = Vec3::UnitZ();
        std::vector<double> breaks{-1.0, 1.0};
        double deepest = 0.0;
        for (std::size_t j = 0; j < i; ++j) {
            const Vec3 to = spheres[j].centre_m - c;
            const double d = to.norm(), rj = spheres[j].radius_m;
            const double depth = big_r + rj - d;
            if (depth <= deepest || d == 0.0) continue;
            deepest = depth;
            axis = to / d;
            breaks = {-1.0, 1.0};
            const double cos_circle = (d * d + big_r * big_r - rj * rj) / (2.0 * d * big_r);
            if (std::abs(cos_circle) < 1.0) breaks.push_back(cos_circle);
            if (d > rj) breaks.push_back(std::sqrt(1.0 - (rj / d) * (rj / d))); // tangent rays: sin θ = R_j/d
        }
        std::sort(breaks.begin(), breaks.end());
        const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
        for (std::size_t part = 0; part + 1 < breaks.size(); ++part) {
            const double lo_mu = breaks[part], hi_mu = breaks[part + 1];
            if (hi_mu <= lo_mu) continue;
            for (std::size_t a = 0; a < mu.size(); ++a) {
                const double m = 0.5 * (lo_mu + hi_mu) + 0.5 * (hi_mu - lo_mu) * mu[a];
                const double sin_theta = std::sqrt(std::max(0.0, 1.0 - m * m));
                for (int b = 0; b < n_phi; ++b) {
                    const double phi = (b + 0.5) * phi_weight;
                    const Vec3 u = sin_theta * (std::cos(phi) * e1 + std::sin(phi) * e2) + m * axis;
                    // |c + r u − c_j|² < R_j²: r² + 2 r (u·d) + |d|² − R_j² < 0, d = c − c_j.
                    cut.clear();
                    for (std::size_t j = 0; j < i; ++j) {
                        const Vec3 d = c - spheres[j].centre_m;
                        const double ud = u.dot(d);
                        const double disc = ud * ud - d.squaredNorm() + spheres[j].radius_m * spheres[j].radius_m;
                        if (disc <= 0.0) continue;
                        const double root = std::sqrt(disc);
                        const double lo = std::max(0.0, -ud - root), hi = std::min(big_r, -ud + root);
                        if (hi > lo) cut.emplace_back(lo, hi);
                    }
                    std::sort(cut.begin(), cut.end());
                    // ∫ r^k dr over [0, R] minus the merged cuts, k = 2, 3, 4.
                    double m0 = 0.0, m1 = 0.0, m2 = 0.0, from = 0.0;
                    const auto add = [&](double lo, double hi) {
                        if (hi <= lo) return;
                        const double lo3 = lo * lo * lo, hi3 = hi * hi * hi;
                        m0 += (hi3 - lo3) / 3.0;
                        m1 += (hi3 * hi - lo3 * lo) / 4.0;
                        m2 += (hi3 * hi * hi - lo3 * lo * lo) / 5.0;
                    };
                    for (const auto& [lo, hi] : cut) {
                        add(from, lo);
                        from = std::max(from, hi);
                    }
                    add(from, big_r);
                    const double w = 0.5 * (hi_mu - lo_mu) * mu_weight[a] * phi_weight;
                    volume += w * m0;
                    first += w * (m0 * c + m1 * u);
                    second += w * (m0 * c * c.transpose() + m1 * (c * u.transpose() + u * c.transpose())
                                      + m2 * u * u.transpose());
                }
            }
        }
    }
    UnionMassProperties p;
    p.volume_m3 = volume;
    p.centre_m = first / volume;
    const Eigen::Matrix3d about_centre = second - volume * p.centre_m * p.centre_m.transpose();
    p.inertia_m5 = about_centre.trace() * Eigen::Matrix3d::Identity() - about_centre;
    return p;
}

ClumpBody clump_body(const std::vector<ClumpSphere>& template_spheres, int angular_nodes)
{
    const UnionMassProperties p = union_mass_properties(template_spheres, angular_nodes);
    // Symmetrised: the sums above are symmetric up to rounding.
    const Eigen::Matrix3d inertia = 0.5 * (p.inertia_m5 + p.inertia_m5.transpose());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(inertia);
    Eigen::Matrix3d axes = eigen.eigenvectors(); // columns: principal axes, eigenvalues ascending
    if (axes.determinant() < 0.0) axes.col(2) = -axes.col(2); // a rotation, not a reflection
    ClumpBody body;
    body.volume_m3 = p.volume_m3;
    body.principal_inertia_m5 = eigen.eigenvalues();
    body.template_axes = axes;
    body.template_centre_m = p.centre_m;
    for (const ClumpSphere& s : template_spheres)
        body.spheres.push_back({axes.transpose() * (s.centre_m - p.centre_m), s.radius_m});
    return body;
}

ClumpBody scaled_clump(const ClumpBody& body, double factor)
{
    ClumpBody s = body;
    for (ClumpSphere& sphere : s.spheres) {
        sphere.centre_m *= factor;
        sphere.radius_m *= factor;
    }
    const double f2 = factor * factor;
    s.volume_m3 *= f2 * factor;
    s.principal_inertia_m5 *= f2 * f2 * factor;
    s.template_centre_m *= factor;
    return s;
}

double ClumpBody::equivalent_radius_m() const
{
    return std::cbrt(3.0 * volume_m3 / (4.0 * std::numbers::pi));
}

double ClumpBody::bounding_radius_m() const
{
    double r = 0.0;
    for (const ClumpSphere& s : spheres) r = std::max(r, s.centre_m.norm() + s.radius_m);
    return r;
}

double ClumpBody::smallest_radius_m() const
{
    double r = spheres.empty() ? 0.0 : spheres.front().radius_m;
    for (const ClumpSphere& s : spheres) r = std::min(r, s.radius_m);
    return r;
}

ClumpBody unit_clump_shape(const std::vector<ClumpSphere>& template_spheres, int angular_nodes)
{
    const ClumpBody body = clump_body(template_spheres, angular_nodes);
    return scaled_clump(body, 1.0 / body.equivalent_radius_m());
}

Quat uniform_orientation(double u1, double u2, double u3)
{
    const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
    const double t2 = 2.0 * std::numbers::pi * u2, t3 = 2.0 * std::numbers::pi * u3;
    return Quat(b * std::cos(t3), a * std::sin(t2), a * std::cos(t2), b * std::sin(t3));
}

std::optional<std::vector<ClumpSphere>> builtin_clump_template(std::string_view name)
{
    if (name == "elongated") return std::vector<ClumpSphere>{{Vec3(-1.1, 0, 0), 1.0}, {Vec3(0, 0, 0), 1.0}, {Vec3(1.1, 0, 0), 1.0}};
    if (name == "flat")
        return std::vector<ClumpSphere>{
            {Vec3(-0.75, -0.75, 0), 1.0}, {Vec3(0.75, -0.75, 0), 1.0}, {Vec3(0.75, 0.75, 0), 1.0}, {Vec3(-0.75, 0.75, 0), 1.0}};
    if (name == "tetrahedral") {
        // Vertices of a regular tetrahedron of edge 1.5: (±1, ±1, ±1) with an even number of minus signs, × 1.5/(2√2).
        const double s = 1.5 / (2.0 * std::numbers::sqrt2);
        return std::vector<ClumpSphere>{{Vec3(s, s, s), 1.0}, {Vec3(s, -s, -s), 1.0}, {Vec3(-s, s, -s), 1.0}, {Vec3(-s, -s, s), 1.0}};
    }
    if (name == "crushed")
        return std::vector<ClumpSphere>{{Vec3(0.0, 0.0, 0.0), 1.0}, {Vec3(0.95, 0.25, 0.05), 0.8},
            {Vec3(-0.7, 0.55, 0.3), 0.7}, {Vec3(0.2, -0.75, 0.35), 0.65}, {Vec3(0.3, 0.35, -0.55), 0.6}};
    return std::nullopt;
}

} // namespace wiredem::engine
