// Pressure, a phase of the triaxial test (engine/triaxial/triaxial.hpp): the
// confining pressure σ₃ on the membrane rises from 0 to its target without a
// jump in rate at either end, then holds.
#pragma once

namespace wiredem::engine {

/// σ₃(t) [Pa] during the ramp: ½(1 − cos(π t/T)) of the target, the target
/// from T on (a ramp time of 0 is a step).
[[nodiscard]] double ramped_pressure_pa(double target_pa, double t_s, double ramp_s) noexcept;

} // namespace wiredem::engine
