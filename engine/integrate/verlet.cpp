#include "integrate/verlet.hpp"

#include "integrate/flat_runs.hpp"
#include "integrate/rotation.hpp"

namespace wiredem::engine {

void verlet_first_half(World& w, ThreadPool& pool)
{
    for (auto& body : w.bodies) {
        parallel_for_blocks(pool, body.size(), integrate_block, [&](std::size_t begin, std::size_t end) {
            for_each_run(body.motion, Motion::dynamic, begin, end, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) {
                    body.x[0][i] += body.x[1][i] + body.x[2][i];
                    body.x[1][i] += body.x[2][i];
                }
            });
            move_kinematic(body.x, body.motion, begin, end);
        });
    }
    // Grains turn while they are dynamic (a kinematic or fixed grain does not).
    RotationalState& rot = w.grain_rotation;
    const std::vector<Motion>& grain_motion = w.of(BodyKind::grain).motion;
    parallel_for_blocks(pool, rot.orientation.size(), integrate_block, [&](std::size_t begin, std::size_t end) {
        for_each_run(grain_motion, Motion::dynamic, begin, end, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) rot.theta[1][i] += rot.theta[2][i];
            // q ← exp(½ ω δt) ⊗ q with the half-step ω (w₁ = δt ω)
            turn_all(rot.orientation.data() + b, rot.theta[1].data() + b, e - b);
        });
    });
}

bool verlet_second_half(World& w, ThreadPool& pool)
{
    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    bool finite = true;
    for (int k = 0; k < body_kind_count; ++k) {
        TranslationalState& body = w.bodies[k];
        const std::vector<Vec3>& force = w.body_force_n[k];
        const bool body_finite = reduce_blocks(
            pool, body.size(), true,
            [&](std::size_t begin, std::size_t end) {
                bool ok = true;
                for (std::size_t i = begin; i < end; ++i) {
                    if (!is_dynamic(body, i)) continue;
                    body.x[2][i] = half_dt2 * body.inv_mass_per_kg[i] * force[i];
                    body.x[1][i] += body.x[2][i];
                    ok = ok && body.x[0][i].allFinite() && body.x[1][i].allFinite();
                }
                return ok;
            },
            [](bool a, bool b) { return a && b; });
        finite = finite && body_finite;
    }
    RotationalState& rot = w.grain_rotation;
    parallel_for(pool, rot.orientation.size(), [&](std::size_t i) {
        if (!is_dynamic(w.of(BodyKind::grain), i)) return;
        rot.theta[2][i] = half_dt2 * rot.inv_inertia_per_kg_m2[i] * w.grain_torque_n_m[i];
        rot.theta[1][i] += rot.theta[2][i];
    });
    return finite;
}

} // namespace wiredem::engine
