// Energies of the whole system, for conservation checks and the quasi-static
// diagnostics (kinetic / elastic energy ratio, the model spec §4). All sums
// are block-ordered and therefore thread-count independent.
#pragma once

#include "parallel/thread_pool.hpp"
#include "state/world.hpp"

namespace wiredem::engine {

/// Elastic energies [J].
struct ElasticEnergy {
    double contacts_j = 0.0;   ///< Hertz: (8/15) E* √R* ξ^{5/2} per touching pair and wall contact
    double wire_j = 0.0;       ///< ½ k_elo Δl² per segment + ½ k_rot (ζ − ζ₀)² per interior node
                               ///< (removed segments and the joints at their ends hold none)
                               ///< (ζ₀ the joint's plastic rest angle; the work of yielding is gone)
    double membrane_j = 0.0;   ///< ½ k_m Δl² per edge
    [[nodiscard]] double total_j() const { return contacts_j + wire_j + membrane_j; }
};

[[nodiscard]] ElasticEnergy elastic_energy(const World& w, ThreadPool& pool);

/// Gravitational potential energy −Σ m g·x of the bodies gravity acts on [J].
[[nodiscard]] double gravitational_energy_j(const World& w);

} // namespace wiredem::engine
