// The time integrator (the model spec §4): the engine's vocabulary, which the
// job spec reads its "engine.integrator" into directly (api/job_spec.hpp)
// through integrator_names. Apart from world.hpp so that the api's headers
// can name it without the World.
#pragma once

#include "core/name_table.hpp"

#include <cstdint>
#include <string_view>

namespace wiredem::engine {

/// Time integrator (the model spec §4). JSON: "gear5", "verlet".
enum class Integrator : std::uint8_t {
    gear5,  ///< fifth-order Gear predictor–corrector: the reference
    verlet, ///< velocity Verlet: cheaper per step, symplectic
};

/// The names of Integrator: the job spec's and the engine's.
inline constexpr NameTable<Integrator, 2> integrator_names{{
    {"gear5", Integrator::gear5},
    {"verlet", Integrator::verlet},
}};

[[nodiscard]] constexpr std::string_view to_string(Integrator i) noexcept { return name_in(integrator_names, i); }

} // namespace wiredem::engine
