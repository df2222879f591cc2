// Formatting only; every lookup tolerates a missing or mistyped field,
// because a summary from an older or newer runner must still print.
#include "display.hpp"

#include "api/utf8.hpp"
#include "engine/core/format.hpp"

#include <boost/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <sstream>
#include <vector>

namespace wiredem::client {
namespace json = boost::json;

namespace {

const json::value* at(const json::value& v, std::initializer_list<std::string_view> path)
{
    const json::value* cur = &v;
    for (auto key : path) {
        const auto* obj = cur->if_object();
        if (!obj) return nullptr;
        auto it = obj->find(key);
        if (it == obj->end()) return nullptr;
        cur = &it->value();
    }
    return cur;
}

std::optional<double> number(const json::value* v)
{
    if (!v) return std::nullopt;
    if (v->is_double()) return v->get_double();
    if (v->is_int64()) return static_cast<double>(v->get_int64());
    if (v->is_uint64()) return static_cast<double>(v->get_uint64());
    return std::nullopt;
}

std::string text(const json::value* v, std::string fallback = "-")
{
    if (!v || !v->is_string() || v->get_string().empty()) return fallback;
    return printable(v->get_string());
}

/// `v` to `decimals` after the point (engine::fixed_number), then `unit`;
/// "-" when the value is missing.
std::string fixed(int decimals, const char* unit, std::optional<double> v)
{
    if (!v || !std::isfinite(*v)) return "-";
    return engine::fixed_number(*v, decimals) + unit;
}

/// `v` to `digits` significant digits (engine::format_number), then `unit`;
/// "-" when the value is missing.
std::string significant(int digits, const char* unit, std::optional<double> v)
{
    if (!v || !std::isfinite(*v)) return "-";
    return engine::format_number(*v, digits) + unit;
}

/// v·factor, or nullopt (std::optional::transform is C++23).
std::optional<double> scaled(std::optional<double> v, double factor)
{
    return v ? std::optional<double>(*v * factor) : std::nullopt;
}

std::string pad_left(const std::string& s, std::size_t w) { return s.size() >= w ? s : std::string(w - s.size(), ' ') + s; }
std::string pad_right(const std::string& s, std::size_t w) { return s.size() >= w ? s : s + std::string(w - s.size(), ' '); }

std::string percent(const json::value& job)
{
    return fixed(0, "%", scaled(number(at(job, {"progress"})), 100.0));
}

std::string eta(const json::value& job)
{
    const auto e = number(at(job, {"eta_s"}));
    return e ? "eta " + format_duration(*e) : std::string();
}

} // namespace

namespace {

/// "32.0 ± 2.0 (3)", "40.0 (1)", "- (0)": a spread object {mean, sd, n} scaled.
std::string mean_sd(const json::value* spread, double factor, int decimals)
{
    const auto mean = scaled(number(at(*spread, {"mean"})), factor);
    const auto sd = scaled(number(at(*spread, {"sd"})), factor);
    const auto n = number(at(*spread, {"n"}));
    std::string s = fixed(decimals, "", mean);
    if (sd) s += " ± " + fixed(decimals, "", sd);
    return s + " (" + fixed(0, "", n.value_or(0.0)) + ")";
}

/// The values of a point or group: `specimen.wire.pattern=helix seed=1`.
std::string values_text(const json::value* values)
{
    std::string s;
    if (!values || !values->is_object()) return "-";
    for (const auto& kv : values->as_object()) {
        if (!s.empty()) s += ' ';
        std::string value;
        if (kv.value().is_string()) {
            value = kv.value().as_string();
        } else if (kv.value().is_double()) {
            value = engine::exact_number(kv.value().as_double());
        } else {
            value = json::serialize(kv.value());
        }
        s += printable(kv.key()) + "=" + printable(value);
    }
    return s.empty() ? "(all)" : s;
}

} // namespace

std::string format_study_summary(const json::value& summary)
{
    std::ostringstream out;
    const json::value* points = at(summary, {"points"});
    const json::value* groups = at(summary, {"groups"});
    std::size_t n = 0, ok = 0;
    if (points && points->is_array())
        for (const json::value& p : points->as_array()) {
            ++n;
            ok += text(at(p, {"state"})) == "succeeded";
        }
    out << "study " << text(at(summary, {"name"})) << ": " << n << " points, " << ok << " succeeded\n";
    if (groups && groups->is_array() && !groups->as_array().empty()) {
        out << "\nover the seeds (mean ± sd (n), Mohr-Coulomb through the yield states)\n";
        std::size_t w = 5;
        for (const json::value& g : groups->as_array()) w = std::max(w, values_text(at(g, {"values"})).size());
        out << "  " << pad_right("group", w) << "  " << pad_left("phi [deg]", 20) << "  " << pad_left("c [kPa]", 20) << "\n";
        for (const json::value& g : groups->as_array()) {
            const json::value* phi = at(g, {"friction_angle_deg"});
            const json::value* c = at(g, {"cohesion_pa"});
            out << "  " << pad_right(values_text(at(g, {"values"})), w) << "  "
                << pad_left(phi ? mean_sd(phi, 1.0, 1) : "-", 20) << "  "
                << pad_left(c ? mean_sd(c, 1e-3, 2) : "-", 20) << "\n";
        }
    }
    if (points && points->is_array()) {
        out << "\npoints\n";
        std::size_t w = 6;
        for (const json::value& p : points->as_array()) w = std::max(w, values_text(at(p, {"values"})).size());
        out << "  " << pad_left("#", 4) << "  " << pad_right("values", w) << "  " << pad_right("state", 10) << "  "
            << pad_left("phi [deg]", 9) << "  " << pad_left("c [kPa]", 8) << "  " << pad_left("R2", 5) << "\n";
        for (const json::value& p : points->as_array()) {
            out << "  " << pad_left(fixed(0, "", number(at(p, {"index"}))), 4) << "  "
                << pad_right(values_text(at(p, {"values"})), w) << "  " << pad_right(text(at(p, {"state"})), 10) << "  "
                << pad_left(fixed(1, "", number(at(p, {"friction_angle_deg"}))), 9) << "  "
                << pad_left(fixed(2, "", scaled(number(at(p, {"cohesion_pa"})), 1e-3)), 8) << "  "
                << pad_left(fixed(3, "", number(at(p, {"r_squared"}))), 5);
            // A fit with caveats (negative c, two pressures, ...): an unconstrained line, said so.
            if (const json::value* cs = at(p, {"fit_caveats"}); cs && cs->is_array() && !cs->get_array().empty()) {
                out << "  (!)";
                for (const json::value& c : cs->get_array()) out << ' ' << text(&c);
            }
            if (const std::string e = text(at(p, {"error"}), ""); !e.empty()) out << "  " << e;
            out << "\n";
        }
    }
    return out.str();
}

std::string printable(std::string_view text)
{
    std::string out;
    out.reserve(text.size());
    char buf[16];
    for (std::size_t i = 0; i < text.size();) {
        const auto b = static_cast<unsigned char>(text[i]);
        if (b < 0x20 || b == 0x7f) { // C0 controls (tab included: it moves the cursor) and DEL
            std::snprintf(buf, sizeof buf, "\\x%02x", b);
            out += buf;
            ++i;
            continue;
        }
        if (b < 0x80) {
            out += static_cast<char>(b);
            ++i;
            continue;
        }
        char32_t cp = 0;
        const std::size_t n = api::utf8_sequence_at(text, i, cp);
        if (n == 0) {
            std::snprintf(buf, sizeof buf, "\\x%02x", b);
            out += buf;
            ++i;
            continue;
        }
        const bool control = (cp >= 0x80 && cp <= 0x9f) || cp == 0x200e || cp == 0x200f || cp == 0x2028 || cp == 0x2029
                          || (cp >= 0x202a && cp <= 0x202e) || (cp >= 0x2066 && cp <= 0x2069);
        if (control) {
            std::snprintf(buf, sizeof buf, "\\u{%04x}", static_cast<unsigned>(cp));
            out += buf;
        } else {
            out.append(text.substr(i, n));
        }
        i += n;
    }
    return out;
}

std::string format_duration(double seconds)
{
    if (!std::isfinite(seconds) || seconds < 0) return "-";
    const long s = std::lround(seconds);
    char buf[32];
    if (s < 60) std::snprintf(buf, sizeof buf, "%lds", s);
    else if (s < 3600) std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
    else std::snprintf(buf, sizeof buf, "%ldh%02ldm", s / 3600, (s % 3600) / 60);
    return buf;
}

std::string format_summary(const json::value& summary)
{
    std::ostringstream out;
    const auto kpa = [](std::optional<double> pa) { return scaled(pa, 1e-3); };

    // Yield (the maximum of the stress ratio, with its Mohr circle) first,
    // the maximum of q beside it; each with the shape of its curve, since a
    // maximum at the last sample of a rising curve is no strength.
    out << "Triaxial tests (yield: maximum of the stress ratio eta; max q beside it)\n";
    const std::vector<std::pair<std::string, std::size_t>> cols{{"sigma3 [kPa]", 12}, {"yield eta", 9},
        {"shape", 8}, {"at [%]", 6}, {"sigma1 [kPa]", 12}, {"sigma3' [kPa]", 13}, {"max q [kPa]", 11}, {"shape", 8},
        {"at [%]", 6}, {"residual eta", 12}};
    out << "  ";
    for (const auto& [name, w] : cols) out << pad_left(name, w) << "  ";
    out << '\n';
    const auto* tests = at(summary, {"tests"});
    if (!tests || !tests->is_array() || tests->get_array().empty()) out << "  (no tests in the summary)\n";
    else
        for (const auto& t : tests->get_array()) {
            const std::vector<std::string> cells{fixed(1, "", kpa(number(at(t, {"confining_pressure_pa"})))),
                fixed(3, "", number(at(t, {"yield", "stress_ratio"}))), text(at(t, {"yield", "shape"})),
                fixed(2, "", scaled(number(at(t, {"yield", "axial_strain"})), 100.0)),
                fixed(1, "", kpa(number(at(t, {"yield", "sigma1_pa"})))),
                fixed(1, "", kpa(number(at(t, {"yield", "sigma3_effective_pa"})))),
                fixed(1, "", kpa(number(at(t, {"peak_deviatoric_stress_pa"})))), text(at(t, {"max_q_shape"})),
                fixed(2, "", scaled(number(at(t, {"peak_axial_strain"})), 100.0)),
                fixed(3, "", number(at(t, {"residual_stress_ratio"})))};
            out << "  ";
            for (std::size_t c = 0; c < cols.size(); ++c) out << pad_left(cells[c], cols[c].second) << "  ";
            out << '\n';
        }

    // The unconstrained fit, marked when it has caveats (negative c or phi,
    // two pressures, a narrow band: engine/analysis/mohr_coulomb.hpp), each
    // caveat's sentence below it, and the constrained fits beside it; all
    // read from summary.json, none recomputed.
    const auto envelope = [&](const char* title, std::string_view key) {
        const json::value* caveats = at(summary, {key, "caveats"});
        const bool flagged = caveats && caveats->is_array() && !caveats->get_array().empty();
        const char* mark = flagged ? "  (!) unconstrained fit: see below" : "";
        const auto constrained = [&](std::string_view which) {
            return "phi = " + fixed(2, " deg", number(at(summary, {key, which, "friction_angle_deg"})))
                 + ", c = " + fixed(2, " kPa", kpa(number(at(summary, {key, which, "cohesion_pa"}))))
                 + ", R^2 = " + fixed(4, "", number(at(summary, {key, which, "r_squared"})));
        };
        out << '\n' << title << '\n'
            << "  friction angle phi  " << fixed(2, " deg", number(at(summary, {key, "friction_angle_deg"}))) << mark << '\n'
            << "  cohesion c          " << fixed(2, " kPa", kpa(number(at(summary, {key, "cohesion_pa"})))) << mark << '\n'
            << "  fit R^2             " << fixed(4, "", number(at(summary, {key, "r_squared"}))) << mark << '\n'
            << "  top-line angle      " << fixed(2, " deg", number(at(summary, {key, "paper_top_line_angle_deg"})))
            << "  (the paper's reading: atan of the circle tops' slope)\n";
        if (const json::value* nn = at(summary, {key, "nonnegative"}); nn && nn->is_object())
            out << "  with c >= 0, phi >= 0  " << constrained("nonnegative") << '\n'
                << "  with c = 0             " << constrained("cohesionless") << '\n';
        if (flagged)
            for (const auto& c : caveats->get_array()) out << "  (!) " << text(at(c, {"message"})) << '\n';
    };
    envelope("Mohr-Coulomb envelope through the yield states", "mohr_coulomb");
    if (at(summary, {"mohr_coulomb_max_q"})) envelope("Mohr-Coulomb envelope through the maxima of q", "mohr_coulomb_max_q");

    // The free-standing test (summary.free_standing), when the job ran one.
    if (const auto* f = at(summary, {"free_standing"}); f && f->is_object()) {
        const auto yes_no = [](const json::value* v) { return v && v->is_bool() ? (v->get_bool() ? "yes" : "no") : "-"; };
        out << "\nFree-standing test (formwork removed, settled, compressed unconfined)\n"
            << "  stands                 " << yes_no(at(*f, {"settling", "stands"})) << " (at rest: "
            << yes_no(at(*f, {"settling", "at_rest"})) << " after "
            << significant(3, " s", number(at(*f, {"settling", "time_to_rest_s"}))) << ")\n"
            << "  grains' bulk height    " << significant(4, " m", number(at(*f, {"settling", "bulk_height_before_m"}))) << " -> "
            << significant(4, " m", number(at(*f, {"settling", "bulk_height_m"}))) << " (loss "
            << fixed(1, " %", scaled(number(at(*f, {"settling", "bulk_height_loss"})), 100.0)) << ")\n"
            << "  top (grain or wire)    " << significant(4, " m", number(at(*f, {"settling", "height_before_m"}))) << " -> "
            << significant(4, " m", number(at(*f, {"settling", "height_m"}))) << " (loss "
            << fixed(1, " %", scaled(number(at(*f, {"settling", "height_loss"})), 100.0)) << ")\n"
            << "  radius                 " << significant(4, " m", number(at(*f, {"settling", "radius_before_m"}))) << " -> "
            << significant(4, " m", number(at(*f, {"settling", "radius_m"}))) << '\n'
            << "  grains that left it    " << fixed(0, "", number(at(*f, {"settling", "escaped_grains"}))) << " of "
            << fixed(0, "", number(at(*f, {"settling", "grains"}))) << " ("
            << fixed(1, " %", scaled(number(at(*f, {"settling", "lost_fraction"})), 100.0)) << " of the volume)\n"
            << "  base force / weight    " << significant(4, " N", number(at(*f, {"settling", "base_force_n"}))) << " / "
            << significant(4, " N", number(at(*f, {"settling", "weight_n"}))) << " (within "
            << significant(3, " N", number(at(*f, {"settling", "base_force_tolerance_n"}))) << " at rest)\n";
        if (at(*f, {"dead_load", "force_n"}))
            out << "  dead load              " << significant(4, " N", number(at(*f, {"dead_load", "force_n"}))) << ": holds "
                << yes_no(at(*f, {"dead_load", "holds"})) << ", creep "
                << fixed(3, " %", scaled(number(at(*f, {"dead_load", "creep_strain"})), 100.0)) << '\n';
        if (const auto* p = at(*f, {"pull_out"}); p && p->is_object()) {
            out << "  peak pull force        " << significant(4, " N", number(at(*p, {"peak_pull_force_n"}))) << " (at "
                << significant(4, " m", number(at(*p, {"pulled_length_at_peak_m"}))) << " pulled)\n"
                << "  pulled out             " << significant(4, " m", number(at(*p, {"pulled_length_m"}))) << ", ended by "
                << text(at(*p, {"end"})) << "; wire in the column "
                << significant(4, " m", number(at(*p, {"wire_in_column_before_m"}))) << " -> "
                << significant(4, " m", number(at(*p, {"wire_in_column_m"}))) << ", wire broke " << yes_no(at(*p, {"wire_broke"}))
                << '\n';
        } else {
            out << "  unconfined strength    " << fixed(3, " kPa", kpa(number(at(*f, {"compression", "unconfined_strength_pa"}))))
                << " (" << text(at(*f, {"compression", "shape"})) << ", at "
                << fixed(2, " %", scaled(number(at(*f, {"compression", "strain_at_failure"})), 100.0)) << " strain)\n"
                << "  predicted by envelope  "
                << fixed(3, " kPa", kpa(number(at(*f, {"compression", "predicted_unconfined_strength_pa"}))))
                << " (2c cos phi / (1 - sin phi))\n"
                << "  quasi-static           " << yes_no(at(*f, {"compression", "quasi_static"})) << '\n';
            // How it failed (docs/model.md, "How it failed") and, with a breakable wire, what gave way at the peak.
            if (const auto* mode = at(*f, {"compression", "failure_mode"}); mode && mode->is_string())
                out << "  how it failed          " << text(mode) << " (grains spilled "
                    << fixed(1, " %", scaled(number(at(*f, {"compression", "spilled_fraction"})), 100.0))
                    << " of the volume, widest slice "
                    << significant(3, " m", number(at(*f, {"compression", "bulge_m"}))) << " wider)\n";
            if (const auto* gave = at(*f, {"compression", "peak_failure"}); gave && gave->is_string())
                out << "  gave way at the peak   " << text(gave) << '\n';
        }
    }

    const std::string cell = text(at(summary, {"specimen", "cell"}));
    out << "\nSpecimen\n"
        << "  triaxial cell          "
        << (cell == "cuboid" ? "cuboid (six rigid walls; its side walls confine)"
               : cell == "membrane" ? "membrane (flexible, pressurised)" : cell) << '\n'
        << "  grain volume fraction  "
        << fixed(4, "", number(at(summary, {"specimen", "grain_volume_fraction"}))) << '\n'
        << "  wire volume fraction   " << fixed(5, "", number(at(summary, {"specimen", "wire_volume_fraction"}))) << '\n'
        << "  wire per volume        "
        << significant(4, " m/m^3", number(at(summary, {"specimen", "wire_length_per_volume_m_per_m3"}))) << '\n'
        << "  sample volume          " << significant(4, " m^3", number(at(summary, {"specimen", "sample_volume_m3"}))) << '\n'
        << "  grains                 " << fixed(0, "", number(at(summary, {"specimen", "grains"}))) << '\n'
        << "  wire nodes             " << fixed(0, "", number(at(summary, {"specimen", "wire_nodes"}))) << '\n'
        << "  wire autocorr. lag     " << significant(4, " m", number(at(summary, {"wire", "autocorrelation_lag_m"})))
        << " (first maximum), " << significant(4, " m", number(at(summary, {"wire", "autocorrelation_prominent_lag_m"})))
        << " (first prominent maximum)\n";

    out << "\nEngine\n"
        << "  time step              " << significant(3, " s", number(at(summary, {"engine", "time_step_s"}))) << '\n'
        << "  steps                  " << fixed(0, "", number(at(summary, {"engine", "steps"}))) << '\n'
        << "  wall time              "
        << (number(at(summary, {"engine", "wall_time_s"})) ? format_duration(*number(at(summary, {"engine", "wall_time_s"}))) : "-")
        << '\n'
        << "  body-steps per second  " << significant(3, "", number(at(summary, {"engine", "body_steps_per_second"}))) << '\n';

    if (const auto* w = at(summary, {"warnings"}); w && w->is_array() && !w->get_array().empty()) {
        out << "\nWarnings\n";
        for (const auto& item : w->get_array()) out << "  - " << printable(item.is_string() ? std::string(item.get_string()) : json::serialize(item)) << '\n';
    }
    return out.str();
}

std::string format_job(const json::value& job)
{
    std::ostringstream out;
    const std::string state = text(at(job, {"state"}));
    std::string progress = percent(job);
    if (const auto stage = text(at(job, {"stage"}), ""); !stage.empty()) progress = stage + "  " + progress;
    if (const auto e = eta(job); !e.empty() && (state == "preparing" || state == "running")) progress += "  " + e;
    out << "id        " << text(at(job, {"id"})) << '\n'
        << "name      " << text(at(job, {"name"})) << '\n'
        << "state     " << state << '\n'
        << "progress  " << progress << '\n'
        << "message   " << text(at(job, {"message"})) << '\n'
        << "attempts  " << fixed(0, "", number(at(job, {"attempts"}))) << '\n'
        << "created   " << text(at(job, {"created_at"})) << '\n'
        << "started   " << text(at(job, {"started_at"})) << '\n'
        << "finished  " << text(at(job, {"finished_at"})) << '\n';
    if (const auto err = text(at(job, {"error"}), ""); !err.empty()) out << "error     " << err << '\n';
    return out.str();
}

std::string format_job_list(const json::value& page)
{
    std::ostringstream out;
    out << pad_right("ID", 26) << pad_right("STATE", 11) << pad_right("PROGRESS", 10) << pad_right("CREATED", 26) << "NAME\n";
    if (const auto* jobs = at(page, {"jobs"}); jobs && jobs->is_array())
        for (const auto& j : jobs->get_array())
            out << pad_right(text(at(j, {"id"})), 26) << pad_right(text(at(j, {"state"})), 11)
                << pad_right(percent(j), 10) << pad_right(text(at(j, {"created_at"})), 26) << text(at(j, {"name"}), "") << '\n';
    return out.str();
}

std::string format_progress_bar(const json::value& job, int width)
{
    const double p = std::clamp(number(at(job, {"progress"})).value_or(0.0), 0.0, 1.0);
    const int filled = static_cast<int>(p * width);
    std::string bar = "[";
    for (int i = 0; i < width; ++i) bar += i < filled ? '=' : (i == filled ? '>' : ' ');
    bar += "] ";
    bar += pad_left(fixed(0, "%", 100.0 * p), 4);
    const std::string stage = text(at(job, {"stage"}), text(at(job, {"state"})));
    bar += "  " + pad_right(stage, 10);
    if (const auto e = eta(job); !e.empty()) bar += "  " + e;
    return bar;
}

std::string format_progress_line(const json::value& job)
{
    std::string line = pad_right(text(at(job, {"state"})), 10) + pad_right(text(at(job, {"stage"}), ""), 10) + pad_left(percent(job), 5);
    if (const auto e = eta(job); !e.empty()) line += "  " + e;
    if (const auto m = text(at(job, {"message"}), ""); !m.empty()) line += "  " + m;
    return line;
}

} // namespace wiredem::client
