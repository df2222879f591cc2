// `wiredem run`: the campaign runner (docs/api.md, "the runner contract").
//
//   1. prepares one specimen (engine/specimen/preparation.hpp),
//   2. runs one triaxial test per confining pressure, each on a copy of the
//      prepared World, one after another (deterministic),
//   3. fits the Mohr–Coulomb envelope to the peak states (σ₁, σ₃,eff) and takes
//      the autocorrelation of the wire's segment strains at the end of the
//      test at the highest pressure,
//   4. writes OUT/result.h5 (layout: docs/results.md) and OUT/summary.json,
//      each under a temporary name first, then renamed.
//
// Progress: overall fraction 0–1 (preparation and tests share 0–0.95 in
// proportion to their estimated steps, the tests equally; analysis and
// writing the rest), at most every half second.
// SIGTERM/SIGINT set a flag that the engine checks every step (exit 128 + sig).
#include "run_command.hpp"

#include "analysis/autocorrelation.hpp"
#include "analysis/mohr_coulomb.hpp"
#include "analysis/strength.hpp"
#include "api/derived.hpp"
#include "api/engine_settings.hpp"
#include "forces/membrane_forces.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"
#include "simulation.hpp"
#include "specimen/preparation.hpp"
#include "timestep.hpp"
#include "triaxial/triaxial.hpp"

#include <boost/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace json = boost::json;
namespace eng = wiredem::engine;
namespace api = wiredem::api;

namespace {

std::atomic<bool> g_cancel{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

extern "C" void on_stop_signal(int sig)
{
    g_signal.store(sig);
    g_cancel.store(true);
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// A finite number, or JSON null.
json::value number_or_null(double x) { return std::isfinite(x) ? json::value(x) : json::value(nullptr); }

/// A length for a message, e.g. "0.105 m".
std::string format_metres(double m)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g m", m);
    return buf;
}

/// Steps one triaxial test of the job is expected to take: ramp, hold and
/// loading to the target strain of a column as tall as the grains' estimated
/// fill, at the job's time step (or the auto step of the deformable system).
double estimated_test_steps(const api::JobSpec& spec)
{
    const double dt = spec.engine.time_step_s ? *spec.engine.time_step_s : api::stable_time_step(spec).auto_s;
    const double height_m = eng::estimated_fill_height_m(api::preparation_spec(spec));
    const double any_pressure_pa = spec.triaxial.confining_pressures_pa.front(); // the step count does not depend on it
    return static_cast<double>(
        eng::expected_triaxial_steps(api::triaxial_settings(spec, any_pressure_pa), height_m, dt));
}

/// Below this fraction of its path laid as wire, the nozzle is reported as
/// blocked (it feeds no wire where a grain or earlier wire is in the way).
constexpr double min_laid_fraction = 0.8;

/// Progress reports: JSON lines on stdout, or a plain line on stderr (a
/// redrawn bar on a TTY).
class Progress {
public:
    explicit Progress(bool json_lines) : json_(json_lines), tty_(!json_lines && ::isatty(2)), start_(Clock::now()) {}

    /// Reports `fraction` of the whole run; throttled unless `force`.
    void report(const char* stage, double fraction, const std::string& message, bool force = false)
    {
        fraction = std::clamp(fraction, 0.0, 1.0);
        const auto now = Clock::now();
        if (!force && now - last_ < std::chrono::milliseconds(500)) return;
        last_ = now;
        const double elapsed = seconds_since(start_);
        std::optional<double> eta;
        if (fraction >= 0.01 && fraction < 1.0) eta = elapsed * (1.0 - fraction) / fraction;
        if (json_) {
            json::object o;
            o["stage"] = stage;
            o["progress"] = fraction;
            o["eta_s"] = eta ? json::value(*eta) : json::value(nullptr);
            o["message"] = message;
            std::cout << json::serialize(o) << '\n' << std::flush;
        } else if (tty_) {
            constexpr int width = 30;
            const int filled = static_cast<int>(fraction * width);
            std::string bar(static_cast<std::size_t>(filled), '#');
            bar.resize(width, '.');
            std::fprintf(stderr, "\r[%s] %5.1f%% %-9s %s%s\033[K", bar.c_str(), 100.0 * fraction, stage, message.c_str(),
                eta ? (" (eta " + std::to_string(static_cast<long>(*eta)) + " s)").c_str() : "");
            std::fflush(stderr);
            dirty_ = true;
        } else {
            std::fprintf(stderr, "%s %5.1f%% %s%s\n", stage, 100.0 * fraction, message.c_str(),
                eta ? (" (eta " + std::to_string(static_cast<long>(*eta)) + " s)").c_str() : "");
        }
    }

    /// Ends a redrawn bar line before other output.
    void finish_line()
    {
        if (dirty_) std::fputc('\n', stderr);
        dirty_ = false;
    }

private:
    bool json_;
    bool tty_;
    bool dirty_ = false;
    Clock::time_point start_;
    Clock::time_point last_{};
};

std::size_t body_count(const eng::World& w)
{
    return w.of(eng::BodyKind::grain).size() + w.of(eng::BodyKind::wire).size() + w.of(eng::BodyKind::membrane).size();
}

/// "10000", "1500000", "12345.5": the pressure in a group name.
std::string pressure_name(double pa)
{
    std::ostringstream o;
    o.precision(17);
    o << pa;
    return "sigma3_" + o.str();
}

void write_units(eng::io::Dataset d, std::string_view units) { d.write_string_attribute("units", units); }

void write_snapshot(eng::io::Group g, const eng::TriaxialSnapshot& s)
{
    g.write_double_attribute("requested_axial_strain", s.requested_axial_strain);
    g.write_double_attribute("axial_strain", s.axial_strain);
    g.write_double_attribute("time_s", s.time_s);
    write_units(g.write_dataset("grain_position_m", std::span<const eng::Vec3>(s.grain_position_m)), "m");
    write_units(g.write_dataset("grain_radius_m", std::span<const double>(s.grain_radius_m)), "m");
    write_units(g.write_dataset("grain_velocity_m_per_s", std::span<const eng::Vec3>(s.grain_velocity_m_per_s)), "m/s");
    write_units(g.write_dataset("wire_node_position_m", std::span<const eng::Vec3>(s.wire_node_position_m)), "m");
    write_units(g.write_dataset("wire_segment_strain", std::span<const double>(s.wire_segment_strain)), "1");
    write_units(g.write_dataset("membrane_node_position_m", std::span<const eng::Vec3>(s.membrane_node_position_m)), "m");
    std::vector<std::uint32_t> tri;
    tri.reserve(3 * s.membrane_triangles.size());
    for (const auto& t : s.membrane_triangles) tri.insert(tri.end(), t.begin(), t.end());
    write_units(g.write_dataset("membrane_triangles", std::span<const std::uint32_t>(tri), 3), "1");

    const eng::ForceNetwork& f = s.forces;
    std::vector<std::uint32_t> pairs;
    pairs.reserve(4 * f.first.size());
    for (std::size_t i = 0; i < f.first.size(); ++i) {
        pairs.push_back(static_cast<std::uint32_t>(f.first[i].kind()));
        pairs.push_back(f.first[i].index());
        pairs.push_back(static_cast<std::uint32_t>(f.second[i].kind()));
        pairs.push_back(f.second[i].index());
    }
    write_units(g.write_dataset("contact_bodies", std::span<const std::uint32_t>(pairs), 4), "1");
    write_units(g.write_dataset("contact_force_n", std::span<const eng::Vec3>(f.force_n)), "N");
    write_units(g.write_dataset("contact_normal_force_n", std::span<const double>(f.normal_force_n)), "N");
    std::vector<std::uint32_t> walls;
    walls.reserve(3 * f.wall.size());
    for (std::size_t i = 0; i < f.wall.size(); ++i) {
        walls.push_back(f.wall[i]);
        walls.push_back(static_cast<std::uint32_t>(f.wall_body[i].kind()));
        walls.push_back(f.wall_body[i].index());
    }
    write_units(g.write_dataset("wall_contact_bodies", std::span<const std::uint32_t>(walls), 3), "1");
    write_units(g.write_dataset("wall_contact_force_n", std::span<const eng::Vec3>(f.wall_force_n)), "N");
}

void write_test(eng::io::Group g, double pressure_pa, const eng::TriaxialResult& r)
{
    g.write_double_attribute("confining_pressure_pa", pressure_pa);
    g.write_double_attribute("peak_deviatoric_stress_pa", r.peak_deviatoric_stress_pa);
    g.write_double_attribute("peak_axial_strain", r.peak_axial_strain);
    g.write_double_attribute("peak_sigma1_pa", r.peak_sigma1_pa);
    g.write_double_attribute("peak_sigma3_effective_pa", r.peak_sigma3_effective_pa);
    g.write_int_attribute("peak_sample", static_cast<std::int64_t>(r.peak_sample));
    if (r.strength) {
        const eng::analysis::StrengthReading& y = *r.strength;
        g.write_string_attribute("max_q_shape", eng::analysis::to_string(y.deviatoric.shape));
        g.write_string_attribute("yield_shape", eng::analysis::to_string(y.stress_ratio.shape));
        g.write_double_attribute("yield_stress_ratio", y.stress_ratio.value);
        g.write_double_attribute("yield_axial_strain", y.yield_axial_strain);
        g.write_double_attribute("yield_sigma1_pa", y.yield_sigma1_pa);
        g.write_double_attribute("yield_sigma3_effective_pa", y.yield_sigma3_pa);
        g.write_int_attribute("yield_sample", static_cast<std::int64_t>(y.stress_ratio.index));
        g.write_double_attribute("residual_stress_ratio", y.residual_stress_ratio);
    }
    g.write_double_attribute("hold_time_s", r.hold_time_s);
    g.write_double_attribute("consolidated_sigma1_pa", r.consolidated_sigma1_pa);
    g.write_double_attribute("initial_height_m", r.initial_height_m);
    g.write_double_attribute("initial_volume_m3", r.initial_volume_m3);
    g.write_int_attribute("quasi_static", r.verdict.quasi_static ? 1 : 0);
    g.write_double_attribute("max_inertial_number", r.verdict.max_inertial_number);
    g.write_double_attribute("mean_kinetic_to_elastic", r.verdict.mean_kinetic_to_elastic);
    g.write_double_attribute("max_kinetic_to_elastic", r.verdict.max_kinetic_to_elastic);
    g.write_int_attribute("steps", static_cast<std::int64_t>(r.steps));
    g.write_double_attribute("time_step_s", r.time_step_s);
    g.write_double_attribute("simulated_time_s", r.simulated_time_s);
    g.write_double_attribute("wall_time_s", r.wall_time_s);

    const eng::TriaxialSeries& s = r.series;
    const auto d = [&](const char* name, const std::vector<double>& v, std::string_view units) {
        write_units(g.write_dataset(name, std::span<const double>(v)), units);
    };
    const auto u = [&](const char* name, const std::vector<std::uint64_t>& v) {
        write_units(g.write_dataset(name, std::span<const std::uint64_t>(v)), "1");
    };
    d("time_s", s.time_s, "s");
    std::vector<std::int32_t> phase(s.phase.begin(), s.phase.end());
    write_units(g.write_dataset("phase", std::span<const std::int32_t>(phase)), "0 ramp, 1 hold, 2 loading");
    d("axial_strain", s.axial_strain, "1");
    d("height_m", s.height_m, "m");
    d("top_plate_force_n", s.top_plate_force_n, "N");
    d("bottom_plate_force_n", s.bottom_plate_force_n, "N");
    d("column_radius_m", s.column_radius_m, "m");
    d("confining_pressure_pa", s.confining_pressure_pa, "Pa");
    d("sigma1_pa", s.sigma1_pa, "Pa");
    d("sigma3_effective_pa", s.sigma3_effective_pa, "Pa");
    d("deviatoric_stress_pa", s.deviatoric_stress_pa, "Pa");
    d("stress_ratio", s.stress_ratio, "1");
    d("volumetric_strain", s.volumetric_strain, "1");
    d("kinetic_energy_j", s.kinetic_energy_j, "J");
    d("elastic_energy_j", s.elastic_energy_j, "J");
    u("contacts", s.contacts);
    u("sliding_contacts", s.sliding_contacts);
    u("membrane_contacts", s.membrane_contacts);
    d("wire_strain_mean", s.wire_strain_mean, "1");
    d("wire_strain_max", s.wire_strain_max, "1");
    d("inertial_number", s.inertial_number, "1");

    eng::io::Group snaps = g.create_group("snapshots");
    for (std::size_t i = 0; i < r.snapshots.size(); ++i)
        write_snapshot(snaps.create_group("snapshot_" + std::to_string(i)), r.snapshots[i]);
}

void write_result_h5(const std::filesystem::path& path, const api::JobSpec& spec, const eng::World& prepared,
    const eng::PreparationReport& prep, const std::vector<double>& pressures,
    const std::vector<eng::TriaxialResult>& tests)
{
    eng::io::File file = eng::io::File::create(path);
    eng::io::Group root = file.root();
    root.write_string_attribute("format", "wiredem-result-1");
    root.write_string_dataset("job_spec", json::serialize(api::to_json(spec)));

    eng::io::Group sp = root.create_group("specimen");
    sp.write_int_attribute("grains", static_cast<std::int64_t>(prep.grains));
    sp.write_int_attribute("wire_nodes", static_cast<std::int64_t>(prep.wire_nodes));
    sp.write_double_attribute("wire_length_m", prep.wire_length_m);
    sp.write_double_attribute("nozzle_path_m", prep.nozzle_path_m);
    sp.write_double_attribute("pile_height_m", prep.pile_height_m);
    sp.write_double_attribute("sample_volume_m3", prep.sample_volume_m3);
    sp.write_double_attribute("grain_volume_fraction", prep.grain_volume_fraction);
    sp.write_double_attribute("wire_volume_fraction", prep.wire_volume_fraction);
    sp.write_double_attribute("core_grain_volume_fraction", prep.core_grain_volume_fraction);
    sp.write_double_attribute("core_wire_volume_fraction", prep.core_wire_volume_fraction);
    sp.write_double_attribute("simulated_time_s", prep.simulated_time_s);
    sp.write_double_attribute("wall_time_s", prep.wall_time_s);
    sp.write_int_attribute("steps", static_cast<std::int64_t>(prep.steps));
    sp.write_double_attribute("time_step_s", prep.time_step_s);
    sp.write_int_attribute("settled", prep.settled ? 1 : 0);
    const eng::TranslationalState& g = prepared.of(eng::BodyKind::grain);
    write_units(sp.write_dataset("grain_position_m", std::span<const eng::Vec3>(g.x[0])), "m");
    write_units(sp.write_dataset("grain_radius_m", std::span<const double>(g.radius_m)), "m");
    const eng::TranslationalState& wn = prepared.of(eng::BodyKind::wire);
    write_units(sp.write_dataset("wire_node_position_m", std::span<const eng::Vec3>(wn.x[0])), "m");
    // The plastic joints' rest angles are part of the wire's state (docs/model.md, "Wire").
    write_units(sp.write_dataset("wire_rest_angle_rad", std::span<const double>(prepared.wire.rest_angle_rad)), "rad");
    const eng::TranslationalState& mn = prepared.of(eng::BodyKind::membrane);
    write_units(sp.write_dataset("membrane_node_position_m", std::span<const eng::Vec3>(mn.x[0])), "m");

    eng::io::Group all = root.create_group("tests");
    for (std::size_t i = 0; i < tests.size(); ++i) write_test(all.create_group(pressure_name(pressures[i])), pressures[i], tests[i]);
    file.close();
}

/// A Mohr–Coulomb fit as the summary reports it, with the states it went through.
json::object mohr_coulomb_json(const eng::Result<eng::analysis::MohrCoulombFit, std::string>& fit, std::string_view states)
{
    json::object mc;
    if (fit.ok()) {
        const auto& f = fit.value();
        mc["friction_angle_deg"] = number_or_null(f.friction_angle_rad * 180.0 / std::numbers::pi);
        mc["cohesion_pa"] = number_or_null(f.cohesion_pa);
        mc["cohesion_fixed_at_zero"] = f.cohesion_fixed_at_zero;
        mc["r_squared"] = f.r_squared ? number_or_null(*f.r_squared) : json::value(nullptr);
        mc["paper_top_line_angle_deg"] = number_or_null(f.paper_top_line_angle_rad * 180.0 / std::numbers::pi);
    } else {
        for (const char* k : {"friction_angle_deg", "cohesion_pa", "r_squared", "paper_top_line_angle_deg"})
            mc[k] = nullptr;
        mc["error"] = fit.error();
    }
    mc["states"] = states;
    return mc;
}

/// What the summary's strength figures mean, with the tolerances used.
json::object definitions_json()
{
    const eng::analysis::CurveTolerances tol;
    json::object d;
    d["yield"] = "the maximum of the stress ratio (sigma1 - sigma3_eff)/(sigma1 + sigma3_eff) of sigma1 and sigma3_eff "
                 "smoothed over smoothing_strain of axial strain, with the Mohr circle of that state";
    d["max_q"] = "the largest raw sample of q = sigma1 - sigma3_eff during loading (tests[].peak_*)";
    d["shape"] = "peak: the smoothed curve drops by more than shape_tolerance of its maximum after it; rising: it rose "
                 "by more than that over the last end_window_strain (the value is a lower bound); plateau: neither";
    d["residual_stress_ratio"] = "mean of the raw stress ratio over the last end_window_strain of axial strain";
    d["smoothing_strain"] = tol.smoothing_strain;
    d["shape_tolerance"] = tol.shape_tolerance;
    d["end_window_strain"] = tol.end_window_strain;
    d["friction_angle"] = "tangent fit: sin(phi) = slope of the least-squares line through the circle tops (p, t), "
                          "c = intercept / cos(phi); paper_top_line_angle_deg = atan(slope), the paper's reading";
    return d;
}

void write_text_file(const std::filesystem::path& path, const std::string& text)
{
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

/// Restores the previous signal handlers when the run ends.
class SignalGuard {
public:
    SignalGuard()
    {
        g_cancel.store(false);
        g_signal.store(0);
        struct sigaction sa {};
        sa.sa_handler = on_stop_signal;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGTERM, &sa, &old_term_);
        sigaction(SIGINT, &sa, &old_int_);
    }
    ~SignalGuard()
    {
        sigaction(SIGTERM, &old_term_, nullptr);
        sigaction(SIGINT, &old_int_, nullptr);
    }
    SignalGuard(const SignalGuard&) = delete;
    SignalGuard& operator=(const SignalGuard&) = delete;

private:
    struct sigaction old_term_ {};
    struct sigaction old_int_ {};
};

int fail(Progress& progress, const std::string& reason)
{
    progress.finish_line();
    if (g_cancel.load()) {
        const int sig = g_signal.load();
        std::cerr << "stopped by signal " << sig << '\n';
        return 128 + (sig ? sig : SIGTERM);
    }
    std::cerr << "wiredem run: " << reason << '\n';
    return 1;
}

int run_campaign(const api::JobSpec& spec, const std::filesystem::path& out_dir, unsigned threads, Progress& progress)
{
    const auto t_start = Clock::now();
    constexpr double tests_end = 0.95;
    // The preparation's share of the progress, set at its first report (which
    // brings its estimated steps) against the tests' estimated steps.
    double prep_share = 0.0;
    const double test_steps_estimate = estimated_test_steps(spec);
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) return fail(progress, "cannot create " + out_dir.string() + ": " + ec.message());

    // 1. Preparation.
    const eng::PreparationSpec prep_spec = api::preparation_spec(spec);
    eng::Simulation prep_sim(threads);
    eng::RunControl control;
    control.cancel = &g_cancel;
    control.progress_every = 500;
    control.progress = [&](std::uint64_t done, std::uint64_t total) {
        if (prep_share == 0.0 && total > 0) {
            const double tests = test_steps_estimate * static_cast<double>(spec.triaxial.confining_pressures_pa.size());
            prep_share = std::clamp(tests_end * static_cast<double>(total) / (static_cast<double>(total) + tests), 0.01, 0.5);
        }
        // Settling may take longer than estimated: the share is not exceeded.
        const double f = total ? std::min(1.0, static_cast<double>(done) / static_cast<double>(total)) : 0.0;
        progress.report("preparing", prep_share * f,
            "pouring " + std::to_string(prep_spec.grain_count) + " grains, step " + std::to_string(done));
    };
    progress.report("preparing", 0.0, "preparing the specimen", true);
    auto prepared = eng::prepare_specimen(prep_sim, prep_spec, control);
    if (!prepared.ok()) return fail(progress, "preparation failed: " + prepared.error());
    const eng::PreparationReport prep = prepared.value();
    std::vector<std::string> warnings;
    if (!prep.settled)
        warnings.push_back("the specimen did not settle within max_preparation_time_s; it was tested as it was");
    if (prep.wire_length_m < min_laid_fraction * prep.nozzle_path_m)
        warnings.push_back("the nozzle laid " + format_metres(prep.wire_length_m) + " of wire along "
                           + format_metres(prep.nozzle_path_m)
                           + " of its path: it fell behind the pile and was blocked; lower "
                             "specimen.pouring.fill_rate_m_per_s");

    // Time step of the tests: the given one, or the auto fraction of the
    // deformable system's critical step (the pouring's is set by impacts).
    eng::World prepared_world = prep_sim.world;
    if (!spec.engine.time_step_s)
        eng::set_time_step(prepared_world,
            eng::stable_time_step(eng::stability_inputs(prepared_world, eng::MembraneAs::deformable)).auto_s);
    const std::size_t bodies = body_count(prepared_world);
    double body_steps = static_cast<double>(prep.steps) * static_cast<double>(bodies);
    double stepping_wall_s = prep.wall_time_s;
    std::uint64_t steps = prep.steps;

    // 2. One test per confining pressure, each on a copy of the specimen.
    const std::vector<double>& pressures = spec.triaxial.confining_pressures_pa;
    const double per_test = (tests_end - prep_share) / static_cast<double>(pressures.size());
    std::vector<eng::TriaxialResult> tests;
    for (std::size_t i = 0; i < pressures.size(); ++i) {
        eng::Simulation sim(threads);
        sim.world = prepared_world;
        const double base = prep_share + per_test * static_cast<double>(i);
        char label[96];
        std::snprintf(label, sizeof label, "test %zu/%zu at sigma3 = %g Pa", i + 1, pressures.size(), pressures[i]);
        control.progress = [&](std::uint64_t done, std::uint64_t total) {
            const double f = total ? std::min(1.0, static_cast<double>(done) / static_cast<double>(total)) : 0.0;
            progress.report("testing", base + per_test * f, std::string(label) + ", step " + std::to_string(done));
        };
        progress.report("testing", base, label, true);
        auto r = eng::run_triaxial(sim, prep.top_plate_wall, api::triaxial_settings(spec, pressures[i]), control);
        if (!r.ok()) return fail(progress, std::string(label) + " failed: " + r.error());
        for (const std::string& w : r.value().warnings) warnings.push_back(std::string(label) + ": " + w);
        steps += r.value().steps;
        body_steps += static_cast<double>(r.value().steps) * static_cast<double>(body_count(sim.world));
        stepping_wall_s += r.value().wall_time_s;
        tests.push_back(std::move(r.value()));
    }
    if (g_cancel.load()) return fail(progress, "cancelled");

    // 3. Analysis.
    progress.report("analysing", tests_end, "Mohr-Coulomb fit and wire autocorrelation", true);
    // Two envelopes: through the yield states (the maximum of the stress
    // ratio; docs/model.md, "How yield is read") and, beside it, through the
    // states at the maximum of q.
    std::vector<eng::analysis::PeakState> yield_states, max_q_states;
    for (const auto& t : tests) {
        max_q_states.push_back({t.peak_sigma1_pa, t.peak_sigma3_effective_pa});
        if (t.strength) yield_states.push_back({t.strength->yield_sigma1_pa, t.strength->yield_sigma3_pa});
    }
    using Fit = eng::Result<eng::analysis::MohrCoulombFit, std::string>;
    const Fit fit = yield_states.size() == tests.size() ? eng::analysis::fit_mohr_coulomb(yield_states)
                                                        : Fit(eng::Err(std::string("a test has no yield state")));
    if (!fit.ok()) warnings.push_back("Mohr-Coulomb fit (yield states): " + fit.error());
    const auto fit_max_q = eng::analysis::fit_mohr_coulomb(max_q_states);
    if (!fit_max_q.ok()) warnings.push_back("Mohr-Coulomb fit (maximum of q): " + fit_max_q.error());
    std::size_t rising = 0;
    for (const auto& t : tests) rising += t.strength && t.strength->stress_ratio.shape == eng::analysis::CurveShape::rising;
    if (rising > 0)
        warnings.push_back(std::to_string(rising) + " of " + std::to_string(tests.size())
                           + " tests: the stress ratio was still rising at the end; their yield states are lower "
                             "bounds (raise triaxial.target_axial_strain)");
    std::optional<double> lag_m;
    const bool with_wire = spec.specimen.wire.pattern != api::WirePattern::none && prep.wire_nodes > 1;
    // At the end of the test at the highest pressure (the first of equals):
    // the wire's strain is largest and most developed there.
    const std::size_t strained = static_cast<std::size_t>(
        std::max_element(pressures.begin(), pressures.end()) - pressures.begin());
    if (with_wire && strained < tests.size() && !tests[strained].snapshots.empty()) {
        const auto ac = eng::analysis::autocorrelation(
            tests[strained].snapshots.back().wire_segment_strain, spec.specimen.wire.segment_length_m);
        if (!ac.ok())
            warnings.push_back("wire autocorrelation: " + ac.error());
        else if (!ac.value().first_maximum_lag_m)
            warnings.push_back("wire autocorrelation: no local maximum after lag 0");
        else
            lag_m = ac.value().first_maximum_lag_m;
    }

    // 4. Writing: result.h5, then summary.json (its presence marks success).
    progress.report("writing", 0.97, "writing result.h5 and summary.json", true);
    const std::filesystem::path h5 = out_dir / "result.h5", h5_tmp = out_dir / "result.h5.tmp";
    const std::filesystem::path sj = out_dir / "summary.json", sj_tmp = out_dir / "summary.json.tmp";
    try {
        write_result_h5(h5_tmp, spec, prepared_world, prep, pressures, tests);
        std::filesystem::rename(h5_tmp, h5);
        eng::io::write_xdmf(h5, out_dir / "result.xdmf");  // ParaView's view of result.h5

        json::object summary;
        json::array jt;
        for (std::size_t i = 0; i < tests.size(); ++i) {
            const auto& t = tests[i];
            json::object o;
            o["confining_pressure_pa"] = pressures[i];
            o["peak_deviatoric_stress_pa"] = number_or_null(t.peak_deviatoric_stress_pa);
            o["peak_axial_strain"] = number_or_null(t.peak_axial_strain);
            o["sigma1_pa"] = number_or_null(t.peak_sigma1_pa);
            o["sigma3_effective_pa"] = number_or_null(t.peak_sigma3_effective_pa);
            if (t.strength) {
                const eng::analysis::StrengthReading& y = *t.strength;
                o["max_q_shape"] = eng::analysis::to_string(y.deviatoric.shape);
                json::object yo;
                yo["shape"] = eng::analysis::to_string(y.stress_ratio.shape);
                yo["stress_ratio"] = number_or_null(y.stress_ratio.value);
                yo["axial_strain"] = number_or_null(y.yield_axial_strain);
                yo["sigma1_pa"] = number_or_null(y.yield_sigma1_pa);
                yo["sigma3_effective_pa"] = number_or_null(y.yield_sigma3_pa);
                yo["deviatoric_stress_pa"] = number_or_null(y.yield_sigma1_pa - y.yield_sigma3_pa);
                o["yield"] = std::move(yo);
                o["residual_stress_ratio"] = number_or_null(y.residual_stress_ratio);
            } else {
                o["max_q_shape"] = nullptr;
                o["yield"] = nullptr;
                o["residual_stress_ratio"] = nullptr;
            }
            o["hold_time_s"] = t.hold_time_s;
            o["consolidated_sigma1_pa"] = number_or_null(t.consolidated_sigma1_pa);
            o["quasi_static"] = t.verdict.quasi_static;
            o["max_inertial_number"] = number_or_null(t.verdict.max_inertial_number);
            o["mean_kinetic_to_elastic"] = number_or_null(t.verdict.mean_kinetic_to_elastic);
            o["max_kinetic_to_elastic"] = number_or_null(t.verdict.max_kinetic_to_elastic);
            o["steps"] = t.steps;
            o["wall_time_s"] = t.wall_time_s;
            jt.push_back(std::move(o));
        }
        summary["name"] = spec.name;
        summary["tests"] = std::move(jt);

        summary["mohr_coulomb"] = mohr_coulomb_json(fit, "yield states: (sigma1, sigma3_effective) at the maximum of the smoothed stress ratio (tests[].yield)");
        summary["mohr_coulomb_max_q"] = mohr_coulomb_json(fit_max_q, "(sigma1, sigma3_effective) at the maximum of q (tests[].peak_*)");
        summary["definitions"] = definitions_json();

        json::object sp;
        sp["grain_volume_fraction"] = prep.grain_volume_fraction;
        sp["wire_volume_fraction"] = prep.wire_volume_fraction;
        sp["core_grain_volume_fraction"] = prep.core_grain_volume_fraction;
        sp["core_wire_volume_fraction"] = prep.core_wire_volume_fraction;
        sp["sample_volume_m3"] = prep.sample_volume_m3;
        sp["grains"] = prep.grains;
        sp["wire_nodes"] = prep.wire_nodes;
        sp["wire_length_m"] = prep.wire_length_m;
        sp["nozzle_path_m"] = prep.nozzle_path_m;
        sp["pile_height_m"] = prep.pile_height_m;
        sp["settled"] = prep.settled;
        sp["preparation_time_step_s"] = prep.time_step_s;
        sp["preparation_steps"] = prep.steps;
        summary["specimen"] = std::move(sp);

        json::object wire;
        wire["pattern"] = api::to_string(spec.specimen.wire.pattern);
        wire["autocorrelation_lag_m"] = lag_m ? json::value(*lag_m) : json::value(nullptr);
        summary["wire"] = std::move(wire);

        json::array jw;
        for (const auto& w : warnings) jw.emplace_back(w);
        summary["warnings"] = std::move(jw);

        json::object e;
        e["time_step_s"] = prepared_world.dt_s;
        e["steps"] = steps;
        e["wall_time_s"] = seconds_since(t_start);
        e["body_steps_per_second"] = stepping_wall_s > 0.0 ? json::value(body_steps / stepping_wall_s) : json::value(nullptr);
        e["threads"] = prep_sim.threads();
        e["density_scale"] = spec.engine.density_scale;
        summary["engine"] = std::move(e);

        write_text_file(sj_tmp, json::serialize(summary) + "\n");
        std::filesystem::rename(sj_tmp, sj);
    } catch (const std::exception& ex) {
        std::filesystem::remove(h5_tmp, ec);
        std::filesystem::remove(sj_tmp, ec);
        return fail(progress, std::string("writing the results failed: ") + ex.what());
    }
    progress.report("writing", 1.0, "done in " + std::to_string(seconds_since(t_start)) + " s", true);
    progress.finish_line();
    return 0;
}

} // namespace

int run_campaign_main(const api::JobSpec& spec, const std::filesystem::path& out_dir, unsigned threads, bool json_progress)
{
    SignalGuard guard;
    Progress progress(json_progress);
    try {
        return run_campaign(spec, out_dir, threads, progress);
    } catch (const std::exception& ex) {
        return fail(progress, ex.what());
    }
}
