// Fifth-order Gear predictor–corrector for second-order equations of motion
// (Allen & Tildesley, appendix E; Pöschel & Schwager, ch. 2), on scaled
// derivatives x_k = δt^k/k! d^k x/dt^k. The rotational equations use the same
// scheme on the rotation vector (w_1 = δt ω, w_2 = δt²/2 dω/dt).
//
// Corrector coefficients for a 6-value method: c₀ = 3/16, c₁ = 251/360,
// c₂ = 1, c₃ = 11/18, c₄ = 1/6, c₅ = 1/60. Allen & Tildesley suggest
// c₀ = 3/20 when forces depend on velocity; measured on the undamped
// oscillator, 3/20 gains energy several times faster at ω δt ≥ 0.15 and is
// unstable from ω δt ≈ 0.35, so we keep 3/16 (as Pöschel & Schwager do) and
// let the contact damping be the only dissipation.
#pragma once

#include "parallel/thread_pool.hpp"
#include "state/world.hpp"

namespace wiredem::engine {

/// Gear-5 corrector coefficients.
inline constexpr double gear5_corrector[gear_order] = {
    3.0 / 16.0, 251.0 / 360.0, 1.0, 11.0 / 18.0, 1.0 / 6.0, 1.0 / 60.0};

/// Predicts every body's position x₀ and velocity x₁ one step ahead (Taylor /
/// Pascal triangle): takes the last corrector's prediction where it holds
/// (Caches::next_prediction), else reads the stored derivatives; x₂…x₅ are
/// predicted by gear5_correct, which must follow.
void gear5_predict(World& w, ThreadPool& pool);

/// Corrects every body with its acceleration F/m (and α = τ/I for grains),
/// advances orientations, predicts x₀ and x₁ of the next step into
/// Caches::next_prediction, and returns false if a position became non-finite.
[[nodiscard]] bool gear5_correct(World& w, ThreadPool& pool);

} // namespace wiredem::engine
