#include "specimen/wire_cuts.hpp"

#include "analysis/cut_selection.hpp"
#include "forces/wire_forces.hpp"
#include "triaxial/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wiredem::engine {

Result<std::vector<std::uint32_t>, std::string> wire_cut_segments(const World& w, const WireCuts& cuts)
{
    const auto& x = w.of(BodyKind::wire).x[0];
    const std::size_t segments = x.size() > 0 ? x.size() - 1 : 0;
    const double l0 = w.wire.segment_length_m;
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < cuts.at_m.size(); ++i) {
        const double at = cuts.at_m[i];
        const double s = std::floor(at / l0);
        if (!(at >= 0.0) || !(s < static_cast<double>(segments)))
            return Err("cut position [" + std::to_string(i) + "] at " + format_number(at)
                       + " m is not on the laid wire, whose rest length is " + format_number(static_cast<double>(segments) * l0)
                       + " m (" + std::to_string(segments) + " segments of " + format_number(l0) + " m)");
        out.push_back(static_cast<std::uint32_t>(s));
    }
    if (cuts.every_loops > 0 && segments > 0) {
        const double per_cut_rad = 2.0 * std::numbers::pi * static_cast<double>(cuts.every_loops);
        double winding_rad = 0.0;
        double cuts_made = 0.0;
        for (std::size_t s = 0; s < segments; ++s) {
            winding_rad += analysis::winding_step_rad(x[s], x[s + 1]); // in (−π, π]
            if (std::floor(std::abs(winding_rad) / per_cut_rad) > cuts_made) {
                ++cuts_made;
                out.push_back(static_cast<std::uint32_t>(s));
            }
        }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

Result<std::size_t, std::string> cut_wire(World& w, const WireCuts& cuts)
{
    auto segments = wire_cut_segments(w, cuts);
    if (!segments.ok()) return Err(segments.error());
    std::size_t made = 0;
    for (std::uint32_t s : segments.value())
        if (cut_wire_segment(w, s)) ++made;
    return made;
}

} // namespace wiredem::engine
