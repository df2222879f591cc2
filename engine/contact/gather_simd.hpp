// The gather (engine/step.cpp, gather_forces) with AVX2: each body's force
// and torque held in 256-bit registers, every contact record read as two
// 256-bit halves (ContactOutput: the force with the overlap, n × F_t with
// |F_n|). The sums run in the scalar gather's order with its operations,
// component by component (the fourth lane carries what is not used), in a
// file built with -ffp-contract=off: the same bits.
#pragma once

#include "contact/contact_list.hpp"
#include "core/types.hpp"

#include <cstddef>

namespace wiredem::engine {

/// What the gather of one body kind reads and writes.
struct GatherInputs {
    const ContactList* contacts = nullptr;   ///< the records (ContactList::output)
    /// Each flat body's incidences to sum (NearPairs): CSR offsets and links.
    const std::uint32_t* incidence_start = nullptr;
    const Incidence* incidence = nullptr;
    std::size_t flat_offset = 0;         ///< flat index of the kind's first body
    const double* mass_kg = nullptr;
    const double* radius_m = nullptr;
    Vec3 gravity_m_per_s2 = Vec3::Zero(); ///< zero for a kind that gravity does not act on
    const Vec3* extra_force_n = nullptr;  ///< the wire's or membrane's own forces, or nullptr
    Vec3* force_n = nullptr;              ///< out: m g + Σ ±F + extra
    Vec3* torque_n_m = nullptr;           ///< out: Σ (r − ξ/2) n × F_t; nullptr for a kind that does not turn
    /// With the rolling law on (grains only): ContactList::rolling_torque_n_m,
    /// each contact's ± rolling torque added to the torque right after its
    /// (r − ξ/2) n × F_t; nullptr: none.
    const Vec3* rolling_torque_n_m = nullptr;
};

/// Gathers bodies [begin, end) of the kind in `in`.
using SimdGather = void (*)(const GatherInputs& in, std::size_t begin, std::size_t end);

/// The AVX2 gather where the SIMD paths run (simd_isa() is not none: every
/// CPU with AVX-512 has AVX2), else nullptr.
[[nodiscard]] SimdGather simd_gather();

} // namespace wiredem::engine
