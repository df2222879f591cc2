#include "integrate/gear5.hpp"

#include "integrate/rotation.hpp"

#include <cmath>

namespace wiredem::engine {
namespace {

/// x_k ← Σ_{j≥k} C(j,k) x_j, done in place from the top (Pascal triangle).
inline void predict_one(std::array<std::vector<Vec3>, gear_order>& x, std::size_t i)
{
    Vec3& x0 = x[0][i];
    Vec3& x1 = x[1][i];
    Vec3& x2 = x[2][i];
    Vec3& x3 = x[3][i];
    Vec3& x4 = x[4][i];
    const Vec3& x5 = x[5][i];
    x0 += x1 + x2 + x3 + x4 + x5;
    x1 += 2.0 * x2 + 3.0 * x3 + 4.0 * x4 + 5.0 * x5;
    x2 += 3.0 * x3 + 6.0 * x4 + 10.0 * x5;
    x3 += 4.0 * x4 + 10.0 * x5;
    x4 += 5.0 * x5;
}

/// Applies the correction Δ = δt²/2 · a − x₂(predicted) to all derivatives.
inline void correct_one(std::array<std::vector<Vec3>, gear_order>& x, std::size_t i, const Vec3& half_a_dt2)
{
    const Vec3 delta = half_a_dt2 - x[2][i];
    for (int k = 0; k < gear_order; ++k) x[k][i] += gear5_corrector[k] * delta;
}

} // namespace

void gear5_predict(World& w, ThreadPool& pool)
{
    for (auto& body : w.bodies) {
        parallel_for(pool, body.size(), [&](std::size_t i) {
            if (body.inv_mass_per_kg[i] != 0.0) predict_one(body.x, i);
        });
    }
    RotationalState& rot = w.grain_rotation;
    parallel_for(pool, rot.orientation.size(), [&](std::size_t i) { predict_one(rot.w, i); });
}

bool gear5_correct(World& w, ThreadPool& pool)
{
    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    bool finite = true;
    for (auto& body : w.bodies) {
        const bool body_finite = reduce_blocks(
            pool, body.size(), true,
            [&](std::size_t begin, std::size_t end) {
                bool ok = true;
                for (std::size_t i = begin; i < end; ++i) {
                    if (body.inv_mass_per_kg[i] == 0.0) continue; // held fixed
                    correct_one(body.x, i, half_dt2 * body.inv_mass_per_kg[i] * body.force_n[i]);
                    ok = ok && body.x[0][i].allFinite();
                }
                return ok;
            },
            [](bool a, bool b) { return a && b; });
        finite = finite && body_finite;
    }
    RotationalState& rot = w.grain_rotation;
    parallel_for(pool, rot.orientation.size(), [&](std::size_t i) {
        correct_one(rot.w, i, half_dt2 * rot.inv_inertia_per_kg_m2[i] * rot.torque_n_m[i]);
        // q ← exp(½ ω δt) ⊗ q, with ω δt = w₁
        turn(rot.orientation[i], rot.w[1][i]);
    });
    return finite;
}

} // namespace wiredem::engine
