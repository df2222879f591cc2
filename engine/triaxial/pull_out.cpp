// Pulling the wire out; see pull_out.hpp.
#include "triaxial/pull_out.hpp"

#include "core/assert.hpp"
#include "core/format.hpp"
#include "forces/wire_forces.hpp"

#include <cmath>
#include <numbers>
#include <algorithm>
#include <string>

namespace wiredem::engine {
namespace {

bool segment_removed(const World& w, std::uint32_t segment)
{
    for (const WireBreak& b : w.wire_breaks)
        if (b.segment == segment) return true;
    return false;
}

} // namespace


const char* to_string(PullOutEnd e) noexcept
{
    switch (e) {
    case PullOutEnd::length: return "length";
    case PullOutEnd::wire_out: return "wire_out";
    case PullOutEnd::time: return "time";
    case PullOutEnd::host: return "host";
    }
    return "time";
}

std::optional<SettingsError> pull_out_settings_error(const PullOutSettings& s)
{
    const auto error = [](const char* field, std::string message) {
        return std::optional<SettingsError>(SettingsError{field, std::move(message)});
    };
    const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
    if (!(s.direction.allFinite() && s.direction.norm() > 0.0))
        return error("direction", "must be a finite vector of nonzero length");
    if (!positive(s.speed_m_per_s)) return error("speed_m_per_s", format_number(s.speed_m_per_s) + " must be > 0");
    if (!(std::isfinite(s.ramp_time_s) && s.ramp_time_s >= 0.0))
        return error("ramp_time_s", format_number(s.ramp_time_s) + " must be ≥ 0");
    if (s.length_m && !positive(*s.length_m)) return error("length_m", format_number(*s.length_m) + " must be > 0");
    if (!positive(s.max_time_s)) return error("max_time_s", format_number(s.max_time_s) + " must be > 0");
    return std::nullopt;
}

std::uint32_t pulled_node(const World& w, WireEnd end)
{
    const std::size_t n = w.of(BodyKind::wire).size();
    WIREDEM_ASSERT(n > 0, "the wire has no node to pull");
    return end == WireEnd::first ? 0u : static_cast<std::uint32_t>(n - 1);
}

std::uint32_t end_segment_other_node(const World& w, WireEnd end)
{
    const std::size_t n = w.of(BodyKind::wire).size();
    WIREDEM_ASSERT(n > 1, "the wire has no end segment");
    return end == WireEnd::first ? 1u : static_cast<std::uint32_t>(n - 2);
}

double pull_speed_m_per_s(const PullOutSettings& s, double t_s) noexcept
{
    if (!(t_s < s.ramp_time_s)) return s.speed_m_per_s;
    return s.speed_m_per_s * 0.5 * (1.0 - std::cos(std::numbers::pi * t_s / s.ramp_time_s));
}

void drive_pulled_node(World& w, const PullOutSettings& s, double t_s)
{
    const BodyRef node{BodyKind::wire, pulled_node(w, s.end)};
    if (w.of(BodyKind::wire).motion[node.index()] != Motion::kinematic) set_motion(w, node, Motion::kinematic);
    set_velocity(w, node, pull_speed_m_per_s(s, t_s) * s.direction.normalized());
}

PullForces pull_forces(const World& w, WireEnd end, const Vec3& unit_direction)
{
    PullForces p;
    const std::uint32_t node = pulled_node(w, end);
    // The node moves at a constant velocity: the drive balances the rest.
    p.pull_force_n = -w.force_of(BodyKind::wire)[node].dot(unit_direction);
    const std::size_t n = w.of(BodyKind::wire).size();
    if (n < 2) return p;
    const std::uint32_t other = end_segment_other_node(w, end);
    const std::uint32_t segment = std::min(node, other);
    if (segment_removed(w, segment)) return p;
    const std::vector<Vec3>& x = w.of(BodyKind::wire).x[0];
    const Vec3 along = (x[segment + 1] - x[segment]).normalized();
    // segment_force_n[s] acts on node s: + along when the segment is stretched.
    p.end_tension_n = w.wire_forces.segment_force_n[segment].dot(along);
    p.end_tension_along_n = p.end_tension_n * (x[node] - x[other]).normalized().dot(unit_direction);
    return p;
}

bool ColumnRegion::contains(const Vec3& x) const noexcept
{
    return std::hypot(x.x(), x.y()) <= escape_distance_m && x.z() - bottom_m <= top_m;
}

double wire_in_region_m(const World& w, const ColumnRegion& region, std::optional<std::uint32_t> only_piece_of)
{
    const std::vector<Vec3>& x = w.of(BodyKind::wire).x[0];
    if (x.size() < 2) return 0.0;
    std::size_t first = 0, last = x.size() - 1; // nodes of the segments counted
    if (only_piece_of) {
        for (const WirePiece& p : wire_pieces(w))
            if (*only_piece_of >= p.first_node && *only_piece_of < p.first_node + p.nodes) {
                first = p.first_node;
                last = p.first_node + p.nodes - 1;
            }
    }
    const std::vector<std::uint8_t> removed = removed_wire_segments(w);
    std::size_t inside = 0;
    for (std::size_t s = first; s < last; ++s)
        if ((s >= removed.size() || removed[s] == 0) && region.contains(x[s]) && region.contains(x[s + 1])) ++inside;
    return static_cast<double>(inside) * w.wire.segment_length_m;
}

} // namespace wiredem::engine
