#include "stages.hpp"

#include "stage_lock.hpp"

#include "analysis/autocorrelation.hpp"
#include "analysis/mohr_coulomb.hpp"
#include "analysis/strength.hpp"
#include "api/derived.hpp"
#include "api/engine_settings.hpp"
#include "api/json_text.hpp"
#include "api/progress_line.hpp"
#include "core/format.hpp"
#include "forces/wire_forces.hpp"
#include "io/atomic_file.hpp"
#include "io/snapshot.hpp"
#include "io/xdmf.hpp"
#include "simulation.hpp"
#include "specimen/box_preparation.hpp"
#include "specimen/wire_cuts.hpp"
#include "timestep.hpp"
#include "triaxial/cuboid.hpp"

#include <boost/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <mutex>
#include <numbers>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

namespace wiredem::campaign {

namespace json = boost::json;
namespace eng = engine;
namespace io = engine::io;
/// The stages a progress line names (the runner contract): one list, api/progress_line.hpp.
namespace progress_stage = api::progress_line;

namespace {

using Clock = std::chrono::steady_clock;
using api::finite_or_null;

/// Below this fraction of its path laid as wire, the nozzle is reported as
/// blocked (it feeds no wire where a grain or earlier wire is in the way).
constexpr double min_laid_fraction = 0.8;

/// Below this height per diameter a membrane specimen is reported as squat:
/// between rough plates a column shorter than about 1.5 diameters is held by
/// its ends and reads stronger (Bishop & Green, "The influence of end
/// restraint on the compression strength of a cohesionless soil",
/// Géotechnique 15 (1965)); triaxial standards ask for 2 to 2.5, and the
/// paper's column has 2.1.
constexpr double min_height_per_diameter = 1.5;

/// The summary's warning when the first local maximum of the wire's
/// autocorrelation is not its first prominent one (engine/analysis/autocorrelation.hpp).
std::string noise_band_warning(const eng::analysis::Autocorrelation& ac)
{
    const std::size_t k = *ac.first_maximum_lag;
    std::string w = "wire autocorrelation: the first local maximum at " + eng::format_number(*ac.first_maximum_lag_m * 1e3, 4)
                  + " mm is below the noise band (prominence "
                  + eng::format_number(eng::analysis::peak_prominence(ac.coefficients, k, k), 2) + ", band "
                  + eng::format_number(eng::analysis::white_noise_band_95(ac.samples, k), 2) + "); ";
    if (ac.prominent_maximum_lag_m)
        w += "the first prominent maximum is at " + eng::format_number(*ac.prominent_maximum_lag_m * 1e3, 4) + " mm";
    else
        w += "no maximum after it rises above the band";
    return w;
}

void report(const StageControl& c, const char* stage, double fraction, const std::string& message)
{
    if (c.progress) c.progress(stage, std::clamp(fraction, 0.0, 1.0), message);
}

/// The engine's run control of a stage: `control`'s cancel, and every 500
/// steps the progress of `stage` as done / total, at most `cap` (a
/// preparation's settling runs past the steps the engine expected: short of
/// done until it has returned), with the message text(done).
eng::RunControl stage_run_control(const StageControl& control, const char* stage, double cap,
    std::function<std::string(std::uint64_t done)> text)
{
    eng::RunControl rc;
    rc.cancel = control.cancel;
    rc.progress_every = 500;
    rc.progress = [&control, stage, cap, text = std::move(text)](std::uint64_t done, std::uint64_t total) {
        const double f = total ? std::min(cap, static_cast<double>(done) / static_cast<double>(total)) : 0.0;
        report(control, stage, f, text(done));
    };
    return rc;
}

/// What a preparation in `phase` is doing, for a progress message.
std::string preparation_phase_text(eng::PreparationPhase phase, std::size_t grains)
{
    switch (phase) {
    case eng::PreparationPhase::pouring: return "pouring " + std::to_string(grains) + " grains";
    case eng::PreparationPhase::settling: return "settling in the mould";
    case eng::PreparationPhase::lowering_lid: return "lowering the top plate";
    case eng::PreparationPhase::settling_under_lid: return "settling under the top plate";
    case eng::PreparationPhase::following_lid: return "the top plate following the column down";
    }
    return "preparing";
}

std::size_t body_count(const eng::World& w)
{
    return w.of(eng::BodyKind::grain).size() + w.of(eng::BodyKind::wire).size() + w.of(eng::BodyKind::membrane).size();
}

std::string test_label(std::size_t k, std::size_t n, double pa)
{
    return "test " + std::to_string(k + 1) + "/" + std::to_string(n) + " at sigma3 = " + eng::format_number(pa, 6) + " Pa";
}


/// What a running stage hands its driver between two steps: saves the World
/// and the driver's state `State` (written by `write_state` into /host) to
/// `path` every `control.checkpoint_interval_s` of wall time, and once more
/// when the stage is stopped (SIGTERM: a server shutting down), so that the
/// next start loses nothing. Nothing when checkpoints are off.
template <class State>
std::function<void(const eng::World&, const State&)> checkpointer(const StageControl& control,
    std::filesystem::path path, std::string what, std::function<void(io::Group&, const State&)> write_state)
{
    if (!(control.checkpoint_interval_s > 0.0)) return {};
    return [&control, path = std::move(path), what = std::move(what), write_state = std::move(write_state),
               last_save = Clock::now(), failed = false](const eng::World& w, const State& st) mutable {
        const bool stopping = control.cancel && control.cancel->load(std::memory_order_relaxed);
        if (!stopping && std::chrono::duration<double>(Clock::now() - last_save).count() < control.checkpoint_interval_s)
            return;
        auto saved = eng::save_snapshot(w, path, [&](io::Group& host) { write_state(host, st); });
        if (!saved.ok() && !failed) {
            // The stage goes on; only its resumability is lost. Said once.
            failed = true;
            std::cerr << "wiredem: " << what << ": cannot write a checkpoint, it goes on without: " << saved.error() << '\n';
        }
        last_save = Clock::now();
    };
}

/// How a test stage continues (one way for every kind of test): from its
/// checkpoint at `path` when there is one — the World and the driver's state
/// `State` saved there (read_state reads /host) — else from `start` (the
/// specimen's World); and, as it runs, saving both there (checkpointer,
/// write_state writes /host). `Continuation` is the engine's
/// (TriaxialContinuation, CuboidContinuation, FreeStandingContinuation).
template <class State, class Continuation>
StageError continue_from_checkpoint(eng::Simulation& sim, eng::World&& start, const std::filesystem::path& path,
    const std::string& label, const StageControl& control, Continuation& continuation,
    std::function<void(io::Group&, const State&)> write_state, std::function<State(const io::Group&)> read_state)
{
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) {
        State state;
        auto w = eng::restore_snapshot(path, [&](const io::Group& host) { state = read_state(host); });
        if (!w.ok()) return "cannot continue " + label + " from its checkpoint: " + w.error();
        sim.world = std::move(w.value());
        continuation.from = std::move(state);
    } else {
        sim.world = std::move(start);
    }
    continuation.between_steps = checkpointer<State>(control, path, label, std::move(write_state));
    return std::nullopt;
}

std::string job_text(const api::JobSpec& spec) { return json::serialize(api::to_json(spec)) + "\n"; }

} // namespace

eng::Result<Specimen, std::string> read_specimen(const JobDir& dir)
{
    Specimen s;
    auto w = eng::restore_snapshot(dir.specimen(), [&](const io::Group& host) {
        s.report = read_preparation_report(host);
        s.threads = host.read_int_attribute("threads");
    });
    if (!w.ok()) return eng::Err(w.error() + " (is the directory prepared? `wiredem prepare JOB.json -o DIR`)");
    s.world = std::move(w.value());
    if (s.report.top_plate_wall >= s.world.walls.size())
        return eng::Err(dir.specimen().string() + ": the top plate's wall index is past the walls");
    return s;
}

eng::Result<api::JobSpec, std::string> read_job(const JobDir& dir)
{
    std::ifstream in(dir.job(), std::ios::binary);
    if (!in) return eng::Err(dir.job().string() + ": cannot read (not a job directory?)");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Written by wiredem (job_text), perhaps an older one: its missing
    // fields are read as it ran.
    auto spec = api::parse_written_job_spec(std::string_view(text));
    if (!spec.ok()) {
        std::string msg = dir.job().string() + ": not a valid job:";
        for (const auto& e : spec.error()) {
            msg += ' ';
            if (!e.path.empty()) msg.append(e.path).append(": ");
            msg.append(e.message).append(";");
        }
        return eng::Err(msg);
    }
    return spec.value();
}

std::optional<std::string> specimen_difference(const api::JobSpec& a, const api::JobSpec& b)
{
    auto specimen_part = [](const api::JobSpec& spec) {
        json::object o = api::to_json(spec).as_object();
        for (const char* key : {"triaxial", "free_standing", "name", "comment"}) o.erase(key);
        if (auto* engine = o.if_contains("engine"); engine && engine->is_object()) engine->as_object().erase("threads");
        // The cuboid cell's specimen is its box, compacted to the lowest
        // pressure: those belong to the specimen (a membrane job's part is as
        // it was).
        if (spec.triaxial.cell == api::CellKind::cuboid) {
            json::object t = api::to_json(spec).at("triaxial").as_object();
            o["triaxial"] = json::object{{"cell", t.at("cell")}, {"cuboid", t.at("cuboid")},
                {"lowest_confining_pressure_pa", spec.triaxial.confining_pressures_pa.front()}};
        }
        return o;
    };
    const json::object x = specimen_part(a), y = specimen_part(b);
    // The first difference, depth first, as a dotted path.
    std::function<std::optional<std::string>(const json::value&, const json::value&, const std::string&)> first
        = [&](const json::value& u, const json::value& v, const std::string& path) -> std::optional<std::string> {
        if (u.is_object() && v.is_object()) {
            const json::object &p = u.as_object(), &q = v.as_object();
            for (const auto& [key, value] : p) {
                const std::string at = path.empty() ? std::string(key) : path + "." + std::string(key);
                const json::value* other = q.if_contains(key);
                if (!other) return at;
                if (auto d = first(value, *other, at)) return d;
            }
            for (const auto& [key, value] : q)
                if (!p.contains(key)) return path.empty() ? std::string(key) : path + "." + std::string(key);
            return std::nullopt;
        }
        if (u != v) return path;
        return std::nullopt;
    };
    return first(x, y, "");
}

namespace {

/// Takes the specimen of control.specimen_from into `dir` (prepare's lock held).
StageError take_specimen(const api::JobSpec& spec, const JobDir& dir, const StageControl& control, const std::string& text)
{
    const JobDir from{control.specimen_from};
    const std::string what = "--specimen-from " + from.root.string();
    auto other = read_job(from);
    if (!other.ok()) return what + ": " + other.error();
    std::error_code ec;
    if (!std::filesystem::exists(from.specimen(), ec)) return what + ": no specimen.h5 there (prepare it first)";
    if (auto d = specimen_difference(spec, other.value()))
        return what + ": its job prepares another specimen (they differ in " + *d + ")";
    try {
        io::replace_file_atomically(dir.specimen(), [&](const std::filesystem::path& partial) {
            std::error_code copy_ec;
            std::filesystem::copy_file(from.specimen(), partial, std::filesystem::copy_options::overwrite_existing, copy_ec);
            if (copy_ec == std::errc::no_space_on_device) throw io::WriteError(copy_ec.value(), dir.specimen());
            if (copy_ec) throw std::filesystem::filesystem_error("cannot copy", from.specimen(), partial, copy_ec);
        });
    } catch (const std::exception& e) {
        return io::write_failure_text(
            "cannot copy " + from.specimen().string() + " to " + dir.specimen().string() + ": ", e);
    }
    try {
        io::write_text_file_atomically(dir.job(), text);
    } catch (const std::exception& e) {
        return std::string(e.what());
    }
    return std::nullopt;
}

/// The cuboid cell's specimen (triaxial.cell = cuboid): the grains compacted
/// in the box (engine/specimen/box_preparation.hpp), saved as a poured one
/// is, with the report's fields a box has (no wire; its core a grain
/// diameter inside all six walls, as the column's is inside the membrane and
/// the plates). Not checkpointed: the preparation is a pure function of the
/// job, prepared again (the same bits) if it was stopped.
StageError prepare_box(const api::JobSpec& spec, const JobDir& dir, const StageControl& control)
{
    const auto box_spec = api::box_preparation_spec(spec);
    if (!box_spec.ok()) return "preparation failed: " + box_spec.error();
    eng::Simulation sim(control.threads);
    eng::RunControl rc = stage_run_control(control, progress_stage::preparing, 0.99, [&](std::uint64_t done) {
        return "compacting " + std::to_string(box_spec.value().grain_count) + " grains in the box, step " + std::to_string(done);
    });
    report(control, progress_stage::preparing, 0.0, "preparing the specimen in the box");
    auto prepared = eng::prepare_box_specimen(sim, box_spec.value(), rc);
    if (!prepared.ok()) return "preparation failed: " + prepared.error();
    const eng::BoxPreparationReport& box = prepared.value();
    report(control, progress_stage::preparing, 1.0, "specimen prepared in " + std::to_string(box.steps) + " steps");
    eng::PreparationReport prep;
    prep.grains = box.grains;
    prep.pile_height_m = box.box.height_m;
    prep.sample_volume_m3 = box.sample_volume_m3;
    prep.grain_volume_fraction = box.grain_volume_fraction;
    prep.core_grain_volume_fraction = box.core_grain_volume_fraction;
    prep.simulated_time_s = box.simulated_time_s;
    prep.wall_time_s = box.wall_time_s;
    prep.steps = box.steps;
    prep.time_step_s = box.time_step_s;
    prep.settled = box.at_rest;
    prep.top_plate_wall = box.walls.top;
    prep.grain_sizes = box.grain_sizes;
    auto saved = eng::save_snapshot(sim.world, dir.specimen(), [&](io::Group& host) {
        write_preparation_report(host, prep);
        host.write_int_attribute("threads", sim.threads());
    });
    if (!saved.ok()) return saved.error();
    return std::nullopt;
}

} // namespace

StageError prepare(const api::JobSpec& spec, const JobDir& dir, const StageControl& control)
{
    std::error_code ec;
    std::filesystem::create_directories(dir.root, ec);
    if (ec) return "cannot create " + dir.root.string() + ": " + ec.message();
    auto lock = StageLock::acquire(
        dir.specimen_lock(), "the preparation of " + dir.root.string(), control.lock_wait_s, control.cancel);
    if (!lock.ok()) return lock.error();
    const std::string text = job_text(spec);
    if (std::filesystem::exists(dir.job(), ec)) {
        std::ifstream in(dir.job(), std::ios::binary);
        const std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        // The same text, or the same job written by an older wiredem (a
        // field it did not have yet, read as it ran).
        if (old != text) {
            const auto held = api::parse_written_job_spec(old);
            if (!held.ok() || !(held.value() == spec))
                return dir.root.string() + " holds another job (its job.json differs from this one); use another directory";
        }
        if (std::filesystem::exists(dir.specimen(), ec)) { // prepared already (a checkpoint left by a kill just after: stale)
            std::filesystem::remove(dir.specimen_checkpoint(), ec);
            return std::nullopt;
        }
    }
    std::filesystem::create_directories(dir.tests(), ec);
    if (ec) return "cannot create " + dir.tests().string() + ": " + ec.message();
    if (!control.specimen_from.empty()) return take_specimen(spec, dir, control, text);
    try {
        io::write_text_file_atomically(dir.job(), text);
    } catch (const std::exception& e) {
        return std::string(e.what());
    }
    if (spec.triaxial.cell == api::CellKind::cuboid) return prepare_box(spec, dir, control);

    const eng::PreparationSpec prep_spec = api::preparation_spec(spec);
    eng::Simulation sim(control.threads);
    eng::PreparationContinuation continuation;
    if (std::filesystem::exists(dir.specimen_checkpoint(), ec)) {
        eng::PreparationDriverState state;
        auto w = eng::restore_snapshot(dir.specimen_checkpoint(), [&](const io::Group& host) { state = read_preparation_state(host); });
        if (!w.ok()) return "cannot continue the preparation from its checkpoint: " + w.error();
        sim.world = std::move(w.value());
        continuation.from = state;
    }
    // The phase the preparation is in, for the progress messages: seen
    // between steps (with the checkpoints, when there are any).
    eng::PreparationPhase phase = continuation.from ? continuation.from->phase : eng::PreparationPhase::pouring;
    continuation.between_steps = [&phase,
                                     save = checkpointer<eng::PreparationDriverState>(control, dir.specimen_checkpoint(),
                                         "the preparation", [](io::Group& host, const eng::PreparationDriverState& st) {
                                             write_preparation_state(host, st);
                                         })](const eng::World& w, const eng::PreparationDriverState& st) {
        phase = st.phase;
        if (save) save(w, st);
    };
    // The engine's total is the pour's expected steps; the settling phases
    // after it take as long as the column needs.
    eng::RunControl rc = stage_run_control(control, progress_stage::preparing, 0.99, [&](std::uint64_t done) {
        return preparation_phase_text(phase, prep_spec.grain_count) + ", step " + std::to_string(done);
    });
    report(control, progress_stage::preparing, 0.0, "preparing the specimen");
    auto prepared = eng::prepare_specimen(sim, prep_spec, rc, std::move(continuation));
    if (!prepared.ok()) return "preparation failed: " + prepared.error();
    const eng::PreparationReport prep = prepared.value();
    report(control, progress_stage::preparing, 1.0, "specimen prepared in " + std::to_string(prep.steps) + " steps");
    // Cuts the job asks for, before any test (specimen.wire.cuts_at_m, cut_every_loops).
    if (const eng::WireCuts cuts = api::wire_cuts(spec); !cuts.at_m.empty() || cuts.every_loops > 0)
        if (auto cut = eng::cut_wire(sim.world, cuts); !cut.ok()) return "specimen.wire.cuts_at_m: " + cut.error();

    // Time step of the tests: the given one, or the auto fraction of the
    // deformable system's critical step (the pouring's is set by impacts).
    if (!spec.engine.time_step_s)
        eng::set_time_step(
            sim.world, eng::stable_time_step(eng::stability_inputs(sim.world, eng::MembraneAs::deformable)).auto_s);
    auto saved = eng::save_snapshot(sim.world, dir.specimen(), [&](io::Group& host) {
        write_preparation_report(host, prep);
        host.write_int_attribute("threads", sim.threads());
    });
    if (!saved.ok()) return saved.error();
    std::filesystem::remove(dir.specimen_checkpoint(), ec);
    return std::nullopt;
}

StageError run_test(const JobDir& dir, std::size_t index, const StageControl& control)
{
    auto job = read_job(dir);
    if (!job.ok()) return job.error();
    const api::JobSpec& spec = job.value();
    const std::vector<double>& pressures = spec.triaxial.confining_pressures_pa;
    if (index >= pressures.size())
        return "test index " + std::to_string(index) + " is out of range: the job has " + std::to_string(pressures.size())
             + " confining pressures (0 to " + std::to_string(pressures.size() - 1) + ")";
    std::error_code ec;
    if (std::filesystem::exists(dir.test(index), ec)) return std::nullopt; // done already
    const std::string label = test_label(index, pressures.size(), pressures[index]);
    auto lock = StageLock::acquire(dir.test_lock(index), label + " of " + dir.root.string(), control.lock_wait_s, control.cancel);
    if (!lock.ok()) return lock.error();
    if (std::filesystem::exists(dir.test(index), ec)) return std::nullopt; // finished while we waited for the lock

    auto specimen = read_specimen(dir);
    if (!specimen.ok()) return specimen.error();
    const std::size_t top_plate = specimen.value().report.top_plate_wall;
    eng::Simulation sim(control.threads);
    eng::RunControl rc = stage_run_control(
        control, progress_stage::testing, 1.0, [&](std::uint64_t done) { return label + ", step " + std::to_string(done); });
    auto write_test = [&](const eng::TriaxialResult& result) -> StageError {
        try {
            io::write_file_atomically(dir.test(index), [&](io::Group& root) {
                io::Group g = root.create_group(test_file_group);
                g.write_double_attribute("confining_pressure_pa", pressures[index]);
                g.write_int_attribute("threads", sim.threads());
                write_triaxial_result(g, result);
            });
        } catch (const std::exception& e) {
            return io::write_failure_text("cannot write " + dir.test(index).string() + ": ", e);
        }
        std::filesystem::remove(dir.checkpoint(index), ec);
        return std::nullopt;
    };
    if (spec.triaxial.cell == api::CellKind::cuboid) {
        // The box's walls in add_cuboid_walls' order on the box's World
        // (bottom, top, x_min, x_max, y_min, y_max; run_cuboid_triaxial
        // checks their normals). Checkpointed as the membrane cell's tests.
        const eng::CuboidWalls walls{0, top_plate, {2, 3, 4, 5}};
        eng::CuboidSettings settings;
        settings.triaxial = api::triaxial_settings(spec, index);
        eng::CuboidContinuation continuation;
        if (auto e = continue_from_checkpoint<eng::CuboidDriverState>(sim, std::move(specimen.value().world),
                dir.checkpoint(index), label, control, continuation,
                [](io::Group& host, const eng::CuboidDriverState& st) { write_cuboid_driver_state(host, st); },
                [](const io::Group& host) { return read_cuboid_driver_state(host); }))
            return e;
        report(control, progress_stage::testing, 0.0, label);
        auto r = eng::run_cuboid_triaxial(sim, walls, settings, rc, std::move(continuation));
        if (!r.ok()) return label + " failed: " + r.error();
        return write_test(r.value().triaxial);
    }
    eng::TriaxialContinuation continuation;
    if (auto e = continue_from_checkpoint<eng::TriaxialDriverState>(sim, std::move(specimen.value().world),
            dir.checkpoint(index), label, control, continuation,
            [](io::Group& host, const eng::TriaxialDriverState& st) { write_driver_state(host, st); },
            [](const io::Group& host) { return read_driver_state(host); }))
        return e;
    report(control, progress_stage::testing, 0.0, label);
    auto r = eng::run_triaxial(sim, top_plate, api::triaxial_settings(spec, index), rc, std::move(continuation));
    if (!r.ok()) return label + " failed: " + r.error();
    return write_test(r.value());
}

StageError run_free_standing_test(const JobDir& dir, const StageControl& control)
{
    auto job = read_job(dir);
    if (!job.ok()) return job.error();
    const api::JobSpec& spec = job.value();
    if (!spec.free_standing.enabled) return std::nullopt;
    std::error_code ec;
    if (std::filesystem::exists(dir.free_standing(), ec)) return std::nullopt; // done already
    const std::string label = "the free-standing test";
    auto lock = StageLock::acquire(dir.free_standing_lock(), label + " of " + dir.root.string(), control.lock_wait_s, control.cancel);
    if (!lock.ok()) return lock.error();
    if (std::filesystem::exists(dir.free_standing(), ec)) return std::nullopt;
    auto specimen = read_specimen(dir);
    if (!specimen.ok()) return specimen.error();
    const std::size_t top_plate = specimen.value().report.top_plate_wall;
    eng::Simulation sim(control.threads);
    eng::FreeStandingContinuation continuation;
    if (auto e = continue_from_checkpoint<eng::FreeStandingDriverState>(sim, std::move(specimen.value().world),
            dir.free_standing_checkpoint(), label, control, continuation,
            [](io::Group& host, const eng::FreeStandingDriverState& st) { write_free_standing_driver_state(host, st); },
            [](const io::Group& host) { return read_free_standing_driver_state(host); }))
        return e;
    eng::RunControl rc = stage_run_control(
        control, progress_stage::testing, 1.0, [&](std::uint64_t done) { return label + ", step " + std::to_string(done); });
    report(control, progress_stage::testing, 0.0, label);
    auto r = eng::run_free_standing(sim, top_plate, api::free_standing_settings(spec), rc, std::move(continuation));
    if (!r.ok()) return label + " failed: " + r.error();
    try {
        io::write_file_atomically(dir.free_standing(), [&](io::Group& root) {
            io::Group g = root.create_group(free_standing_group);
            g.write_int_attribute("threads", sim.threads());
            write_free_standing_result(g, r.value());
        });
    } catch (const std::exception& e) {
        return io::write_failure_text("cannot write " + dir.free_standing().string() + ": ", e);
    }
    std::filesystem::remove(dir.free_standing_checkpoint(), ec);
    return std::nullopt;
}

namespace {

/// One envelope's figures: φ [deg], c [Pa] and R² (null when the fit leaves no degree of freedom).
json::object envelope_json(const eng::analysis::MohrEnvelope& e)
{
    json::object o;
    o["friction_angle_deg"] = finite_or_null(e.friction_angle_rad * 180.0 / std::numbers::pi);
    o["cohesion_pa"] = finite_or_null(e.cohesion_pa);
    o["r_squared"] = e.r_squared ? finite_or_null(*e.r_squared) : json::value(nullptr);
    return o;
}

/// A Mohr–Coulomb fit as the summary reports it, with the states it went through.
/// summary.json's specimen.grain_sizes: the drawn grains against the curve.
json::object grain_sizes_json(const eng::GrainSizeReport& z)
{
    auto figures = [](const eng::GradingFigures& f) {
        return json::object{{"d10_m", f.d10_m}, {"d50_m", f.d50_m}, {"d60_m", f.d60_m},
            {"uniformity_coefficient", f.uniformity_coefficient}};
    };
    return json::object{{"requested", figures(z.requested)}, {"drawn", figures(z.drawn)}, {"ks_distance", z.ks_distance},
        {"ks_critical_1pct", z.ks_critical_1pct}, {"grains", z.grains}};
}

json::object mohr_coulomb_json(const eng::Result<eng::analysis::MohrCoulombFit, std::string>& fit, std::string_view states)
{
    // The same keys either way (the OpenAPI schema requires them): every
    // figure null, and `error`, when the fit is impossible.
    const eng::analysis::MohrCoulombFit* f = fit.ok() ? &fit.value() : nullptr;
    const auto figure = [&](auto of) { return f ? of(*f) : json::value(nullptr); };
    json::object mc;
    mc["friction_angle_deg"] = figure([](const auto& g) { return finite_or_null(g.friction_angle_rad * 180.0 / std::numbers::pi); });
    mc["cohesion_pa"] = figure([](const auto& g) { return finite_or_null(g.cohesion_pa); });
    mc["cohesion_fixed_at_zero"] = figure([](const auto& g) { return json::value(g.cohesion_fixed_at_zero); });
    mc["r_squared"] = figure([](const auto& g) { return g.r_squared ? finite_or_null(*g.r_squared) : json::value(nullptr); });
    mc["paper_top_line_angle_deg"]
        = figure([](const auto& g) { return finite_or_null(g.paper_top_line_angle_rad * 180.0 / std::numbers::pi); });
    json::array caveats;
    if (f)
        for (const eng::analysis::FitCaveat c : f->caveats)
            caveats.push_back(json::object{{"code", eng::analysis::to_string(c)}, {"message", eng::analysis::describe(c, *f)}});
    mc["caveats"] = std::move(caveats);
    mc["nonnegative"] = figure([](const auto& g) { return json::value(envelope_json(g.nonnegative)); });
    mc["cohesionless"] = figure([](const auto& g) { return json::value(envelope_json(g.cohesionless)); });
    if (!f) mc["error"] = fit.error();
    mc["states"] = states;
    return mc;
}

/// The fit's caveats as warnings, each after `what` ("Mohr-Coulomb fit (yield states)").
void warn_of_caveats(std::vector<std::string>& warnings, const eng::Result<eng::analysis::MohrCoulombFit, std::string>& fit,
    std::string_view what)
{
    if (!fit.ok()) {
        warnings.push_back(std::string(what) + ": " + fit.error());
        return;
    }
    for (const eng::analysis::FitCaveat c : fit.value().caveats)
        warnings.push_back(std::string(what) + ": " + eng::analysis::describe(c, fit.value()));
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
    d["loading_start"] = "the column as loading started: sigma1 and sigma3_eff averaged over the last consolidation window "
                         "(5 ms), their stress ratio, and the axial and radial strains of the ramp and hold (> 0 shortened, "
                         "narrowed); rebound_axial_strain: how much it lengthened after its shortest (extension flow under "
                         "sigma3_eff > sigma1)";
    d["consolidated"] = "tests[].consolidated: consolidated_sigma1_pa within max_consolidation_mismatch of "
                        "consolidation_target_pa (sigma3, or sigma3_eff for triaxial.consolidation = effective)";
    d["max_consolidation_mismatch"] = eng::max_consolidation_mismatch;
    d["smoothing_strain"] = tol.smoothing_strain;
    d["shape_tolerance"] = tol.shape_tolerance;
    d["end_window_strain"] = tol.end_window_strain;
    d["autocorrelation_lag"] = "wire.autocorrelation_lag_m: the first local maximum after lag 0 of the autocorrelation "
                               "R(k) of the segment strains; wire.autocorrelation_prominent_lag_m: the first local maximum "
                               "whose topographic prominence exceeds the white-noise 95 % band 1.96/sqrt(N - k) (a lower "
                               "bound of the band of a correlated signal)";
    d["friction_angle"] = "tangent fit: sin(phi) = slope of the least-squares line through the circle tops (p, t), "
                          "c = intercept / cos(phi); paper_top_line_angle_deg = atan(slope), the paper's reading";
    d["constrained_fits"] = "the same least squares of t = c cos(phi) + p sin(phi) over the circle tops, constrained: "
                            "nonnegative with c >= 0 and phi >= 0, cohesionless with c = 0 (one parameter); r_squared "
                            "1 - SS_res/SS_tot with SS_tot about the mean t of the tops, null when the fit leaves no "
                            "degree of freedom";
    d["caveats"] = "single_pressure: c = 0 imposed; two_pressures: the line is exact by construction (no r_squared); "
                   "narrow_band: the circles' centres span less than the smallest centre's distance from sigma = 0; "
                   "negative_cohesion: c < 0; negative_friction_angle: phi < 0";
    return d;
}

// The names of result.h5 (engine/triaxial/result_names.hpp).
using P = eng::ResultPlace;
using eng::result_name;
using eng::result_name_spec;

/// Whether the job's wire can fall into pieces (breakable or cut): only then
/// do result.h5 and the summary report pieces and breaks, so that other jobs'
/// files stay as they were.
bool wire_can_part(const api::JobSpec& spec)
{
    const api::WireSpec& w = spec.specimen.wire;
    return w.pattern != api::WirePattern::none && (w.breaking_strain || !w.cuts_at_m.empty() || w.cut_every_loops > 0);
}

/// The prepared wire's pieces and the segments removed from it (cuts, and
/// breaks during the preparation), into the specimen group.
void write_wire_pieces(io::Group& sp, const eng::World& w)
{
    io::Group g = sp.create_group(result_name(P::specimen, "wire_pieces"));
    std::vector<std::int64_t> first, nodes;
    std::vector<double> rest, length;
    for (const eng::WirePiece& p : eng::wire_pieces(w)) {
        first.push_back(p.first_node);
        nodes.push_back(p.nodes);
        rest.push_back(p.rest_length_m);
        length.push_back(p.length_m);
    }
    write_named(g, result_name_spec(P::wire_pieces, "first_node"), std::span<const std::int64_t>(first));
    write_named(g, result_name_spec(P::wire_pieces, "nodes"), std::span<const std::int64_t>(nodes));
    write_named(g, result_name_spec(P::wire_pieces, "rest_length_m"), std::span<const double>(rest));
    write_named(g, result_name_spec(P::wire_pieces, "length_m"), std::span<const double>(length));
    std::vector<eng::TestWireBreak> removed;
    for (const eng::WireBreak& b : w.wire_breaks)
        removed.push_back({.event = b, .test_time_s = b.time_s, .axial_strain = 0.0,
            .position_m = eng::wire_segment_position_m(w.wire, b.segment)});
    write_wire_breaks(sp, removed);
}

/// The breaks of a test for the summary.
json::array wire_breaks_json(const std::vector<eng::TestWireBreak>& breaks)
{
    json::array a;
    for (const eng::TestWireBreak& b : breaks) {
        json::object o;
        o["time_s"] = b.test_time_s;
        o["axial_strain"] = finite_or_null(b.axial_strain);
        o["position_m"] = b.position_m;
        o["segment"] = b.event.segment;
        o["cause"] = b.event.cause == eng::WireBreakCause::cut ? "cut" : "broke";
        o["segment_strain"] = finite_or_null(b.event.strain);
        o["released_energy_j"] = finite_or_null(b.event.released_energy_j);
        a.push_back(std::move(o));
    }
    return a;
}

/// result.h5's contents, into its root group.
void write_result(io::Group& root, const api::JobSpec& spec, const Specimen& specimen,
    const std::vector<eng::TriaxialResult>& tests, const std::optional<eng::FreeStandingResult>& free_standing)
{
    root.write_string_attribute(result_name(P::root, "format"), eng::result_format);
    root.write_string_dataset(result_name(P::root, "job_spec"), json::serialize(api::to_json(spec)));

    io::Group sp = root.create_group(result_name(P::root, "specimen"));
    write_preparation_report(sp, specimen.report);
    const eng::World& w = specimen.world;
    const eng::TranslationalState& g = w.of(eng::BodyKind::grain);
    write_named(sp, result_name_spec(P::specimen, "grain_position_m"), std::span<const eng::Vec3>(g.x[0]));
    write_named(sp, result_name_spec(P::specimen, "grain_radius_m"), std::span<const double>(g.radius_m));
    // Clumps: every sphere is a grain above; which clump it belongs to
    // (−1: a free grain), so that a viewer can colour or pick a clump. Only
    // with clumps: every other result.h5 stays as it was.
    if (!w.clumps.empty()) {
        std::vector<std::int64_t> clump(g.size(), -1);
        for (std::size_t i = 0; i < g.size(); ++i)
            if (w.clumps.is_member(i)) clump[i] = w.clumps.member_clump[i];
        write_named(sp, result_name_spec(P::specimen, "grain_clump"), std::span<const std::int64_t>(clump));
    }
    const eng::TranslationalState& wn = w.of(eng::BodyKind::wire);
    write_named(sp, result_name_spec(P::specimen, "wire_node_position_m"), std::span<const eng::Vec3>(wn.x[0]));
    // The plastic joints' rest angles are part of the wire's state (docs/model.md, "Wire").
    write_named(sp, result_name_spec(P::specimen, "wire_rest_angle_rad"), std::span<const double>(w.wire_rest_angle_rad));
    const eng::TranslationalState& mn = w.of(eng::BodyKind::membrane);
    write_named(sp, result_name_spec(P::specimen, "membrane_node_position_m"), std::span<const eng::Vec3>(mn.x[0]));
    if (wire_can_part(spec)) write_wire_pieces(sp, w);

    io::Group all = root.create_group(result_name(P::root, "tests"));
    const std::vector<double>& pressures = spec.triaxial.confining_pressures_pa;
    for (std::size_t i = 0; i < tests.size(); ++i) {
        io::Group t = all.create_group(test_group_name(pressures[i]));
        t.write_double_attribute(result_name(P::test, "confining_pressure_pa"), pressures[i]);
        write_triaxial_result(t, tests[i]);
        if (spec.specimen.wire.breaking_strain)
            t.write_string_attribute(result_name(P::record, "peak_failure"), eng::to_string(eng::peak_failure(tests[i].series, tests[i].peak_sample, tests[i].wire_breaks)));
    }
    if (free_standing) {
        io::Group f = root.create_group(free_standing_group);
        write_free_standing_result(f, *free_standing);
        if (spec.specimen.wire.breaking_strain && free_standing->compression)
            f.write_string_attribute(result_name(P::record, "peak_failure"), eng::to_string(eng::peak_failure(free_standing->series,
                free_standing->compression->max_sigma1_sample, free_standing->wire_breaks)));
    }
}

/// The free-standing test as the summary reports it, with the unconfined
/// strength the envelope `fit` predicts beside the measured one.
json::object free_standing_json(const eng::FreeStandingResult& r,
    const eng::Result<eng::analysis::MohrCoulombFit, std::string>& fit, std::int64_t threads)
{
    const eng::SettlingReading& s = r.settling;
    json::object settling;
    settling["stands"] = s.stands;
    settling["at_rest"] = s.at_rest;
    settling["time_to_rest_s"] = finite_or_null(s.time_to_rest_s);
    settling["height_before_m"] = finite_or_null(s.height_before_m);
    settling["height_m"] = finite_or_null(s.height_m);
    settling["height_loss"] = finite_or_null(s.height_loss);
    settling["radius_before_m"] = finite_or_null(s.radius_before_m);
    settling["radius_m"] = finite_or_null(s.radius_m);
    settling["bulk_height_before_m"] = finite_or_null(s.bulk_height_before_m);
    settling["bulk_height_m"] = finite_or_null(s.bulk_height_m);
    settling["bulk_height_loss"] = finite_or_null(s.bulk_height_loss);
    settling["grains"] = s.grains;
    settling["escaped_grains"] = s.escaped_grains;
    settling["lost_fraction"] = finite_or_null(s.lost_fraction);
    settling["weight_n"] = finite_or_null(s.weight_n);
    settling["base_force_n"] = finite_or_null(s.base_force_n);
    settling["base_force_tolerance_n"] = finite_or_null(s.base_force_tolerance_n);
    settling["max_removal_kinetic_energy_j"] = finite_or_null(s.max_removal_kinetic_energy_j);
    json::object o;
    o["settling"] = std::move(settling);
    if (r.dead_load) {
        json::object d;
        d["force_n"] = r.dead_load->force_n;
        d["stress_pa"] = finite_or_null(r.dead_load->stress_pa);
        d["holds"] = r.dead_load->holds;
        d["strain_at_load"] = finite_or_null(r.dead_load->strain_at_load);
        d["creep_strain"] = finite_or_null(r.dead_load->creep_strain);
        o["dead_load"] = std::move(d);
    } else {
        o["dead_load"] = nullptr;
    }
    json::object c;
    if (r.compression) {
        const eng::CompressionReading& k = *r.compression;
        c["unconfined_strength_pa"] = finite_or_null(k.strength.value);
        c["shape"] = eng::analysis::to_string(k.strength.shape);
        c["strain_at_failure"] = finite_or_null(k.strength_axial_strain);
        c["max_sigma1_pa"] = finite_or_null(k.max_sigma1_pa);
        c["failed"] = k.failed;
        c["failure_mode"] = k.failure_mode ? json::value(eng::to_string(*k.failure_mode)) : json::value(nullptr);
        c["spilled_fraction"] = finite_or_null(k.spilled_fraction);
        c["bulge_m"] = finite_or_null(k.bulge_m);
    } else {
        c["unconfined_strength_pa"] = nullptr;
        c["shape"] = nullptr;
        c["strain_at_failure"] = nullptr;
        c["max_sigma1_pa"] = nullptr;
        c["failed"] = nullptr;
        c["failure_mode"] = nullptr;
        c["spilled_fraction"] = nullptr;
        c["bulge_m"] = nullptr;
    }
    c["predicted_unconfined_strength_pa"] = fit.ok() ? finite_or_null(eng::analysis::unconfined_strength_pa(
                                                           fit.value().friction_angle_rad, fit.value().cohesion_pa))
                                                     : json::value(nullptr);
    c["definition"] = "unconfined_strength_pa: the maximum of sigma1 = F_top / (pi r0^2) (r0 the settled column's "
                      "equivalent radius) smoothed over definitions.smoothing_strain, its shape read as the yield's; "
                      "predicted_unconfined_strength_pa: 2 c cos(phi) / (1 - sin(phi)) of mohr_coulomb";
    c["quasi_static"] = r.verdict.quasi_static;
    c["max_inertial_number"] = finite_or_null(r.verdict.max_inertial_number);
    c["mean_kinetic_to_elastic"] = finite_or_null(r.verdict.mean_kinetic_to_elastic);
    o["compression"] = std::move(c);
    if (r.pull_out) { // only with a pull-out: the summaries of other jobs stay as they were
        const eng::PullOutReading& p = *r.pull_out;
        json::object q;
        q["peak_pull_force_n"] = finite_or_null(p.peak_pull_force_n);
        q["pulled_length_at_peak_m"] = finite_or_null(p.pulled_length_at_peak_m);
        q["pulled_length_m"] = finite_or_null(p.pulled_length_m);
        q["wire_in_column_before_m"] = finite_or_null(p.wire_in_column_before_m);
        q["wire_in_column_m"] = finite_or_null(p.wire_in_column_m);
        q["grains_in_column"] = p.grains_in_column;
        q["wire_broke"] = p.wire_broke;
        q["ramp_inertia_n"] = finite_or_null(p.ramp_inertia_n);
        q["end"] = eng::to_string(p.end);
        q["pulled_node"] = p.pulled_node;
        q["definition"] = "pull force: the drive's force on the pulled wire node along the pull, averaged over each "
                          "sample interval (peak_pull_force_n the largest such mean); wire_in_column_m: rest length of the "
                          "whole segments within escape_distance_m of the axis and below the settled height";
        o["pull_out"] = std::move(q);
    }
    o["steps"] = r.steps;
    o["wall_time_s"] = r.wall_time_s;
    o["threads"] = threads;
    return o;
}

} // namespace

StageError analyse(const JobDir& dir, const StageControl& control)
{
    auto job = read_job(dir);
    if (!job.ok()) return job.error();
    auto lock = StageLock::acquire(
        dir.analyse_lock(), "the analysis of " + dir.root.string(), control.lock_wait_s, control.cancel);
    if (!lock.ok()) return lock.error();
    const api::JobSpec& spec = job.value();
    auto specimen_read = read_specimen(dir);
    if (!specimen_read.ok()) return specimen_read.error();
    const Specimen& specimen = specimen_read.value();
    const eng::PreparationReport& prep = specimen.report;
    const std::vector<double>& pressures = spec.triaxial.confining_pressures_pa;
    report(control, progress_stage::analysing, 0.0, "reading the tests");

    std::vector<eng::TriaxialResult> tests;
    std::vector<std::int64_t> test_threads;
    for (std::size_t k = 0; k < pressures.size(); ++k) {
        std::error_code ec;
        if (!std::filesystem::exists(dir.test(k), ec))
            return test_label(k, pressures.size(), pressures[k]) + " has not run: `wiredem test " + dir.root.string()
                 + " --index " + std::to_string(k) + "`";
        try {
            const io::File f = io::File::open_read_only(dir.test(k));
            const io::Group g = f.root().open_group(test_file_group);
            if (g.read_double_attribute("confining_pressure_pa") != pressures[k])
                return dir.test(k).string() + " is a test at another confining pressure than the job's";
            tests.push_back(read_triaxial_result(g));
            test_threads.push_back(g.read_int_attribute("threads"));
        } catch (const std::exception& e) {
            return "cannot read " + dir.test(k).string() + ": " + e.what();
        }
    }

    std::optional<eng::FreeStandingResult> free_standing;
    std::int64_t free_standing_threads = 0;
    if (spec.free_standing.enabled) {
        std::error_code ec;
        if (!std::filesystem::exists(dir.free_standing(), ec))
            return "the free-standing test has not run: `wiredem run` the job again";
        try {
            const io::File f = io::File::open_read_only(dir.free_standing());
            const io::Group g = f.root().open_group(free_standing_group);
            free_standing = read_free_standing_result(g);
            free_standing_threads = g.read_int_attribute("threads");
        } catch (const std::exception& e) {
            return "cannot read " + dir.free_standing().string() + ": " + e.what();
        }
    }

    std::vector<std::string> warnings;
    if (!prep.settled)
        warnings.push_back("the specimen did not settle within max_preparation_time_s; it was tested as it was");
    if (prep.wire_length_m < min_laid_fraction * prep.nozzle_path_m)
        warnings.push_back("the nozzle laid " + engine::format_number(prep.wire_length_m) + " m of wire along "
                           + engine::format_number(prep.nozzle_path_m)
                           + " m of its path: it fell behind the pile and was blocked; lower "
                             "specimen.pouring.fill_rate_m_per_s");
    if (spec.triaxial.cell == api::CellKind::membrane) {
        const double diameter_m = 2.0 * spec.specimen.membrane_radius_m;
        if (prep.pile_height_m < min_height_per_diameter * diameter_m)
            warnings.push_back("the specimen is " + engine::format_number(prep.pile_height_m * 1e3, 3) + " mm tall and "
                               + engine::format_number(diameter_m * 1e3, 3) + " mm wide (H/D = "
                               + engine::format_number(prep.pile_height_m / diameter_m, 2)
                               + "): below H/D = 1.5 the plates hold a column by its ends and its strength reads high "
                                 "(triaxial standards ask for 2 to 2.5); raise specimen.grain_count");
    }
    for (std::size_t k = 0; k < tests.size(); ++k)
        for (const std::string& w : tests[k].warnings)
            warnings.push_back(test_label(k, pressures.size(), pressures[k]) + ": " + w);
    if (free_standing)
        for (const std::string& w : free_standing->warnings) warnings.push_back("free-standing test: " + w);

    // Two envelopes: through the yield states (the maximum of the stress
    // ratio; docs/model.md, "How yield is read") and, beside it, through the
    // states at the maximum of q.
    report(control, progress_stage::analysing, 0.3, "Mohr-Coulomb fit and wire autocorrelation");
    std::vector<eng::analysis::PeakState> yield_states, max_q_states;
    for (const auto& t : tests) {
        max_q_states.push_back({t.peak_sigma1_pa, t.peak_sigma3_effective_pa});
        if (t.strength) yield_states.push_back({t.strength->yield_sigma1_pa, t.strength->yield_sigma3_pa});
    }
    using Fit = eng::Result<eng::analysis::MohrCoulombFit, std::string>;
    const Fit fit = yield_states.size() == tests.size() ? eng::analysis::fit_mohr_coulomb(yield_states)
                                                        : Fit(eng::Err(std::string("a test has no yield state")));
    warn_of_caveats(warnings, fit, "Mohr-Coulomb fit (yield states)");
    const auto fit_max_q = eng::analysis::fit_mohr_coulomb(max_q_states);
    warn_of_caveats(warnings, fit_max_q, "Mohr-Coulomb fit (maximum of q)");
    std::size_t rising = 0;
    for (const auto& t : tests) rising += t.strength && t.strength->stress_ratio.shape == eng::analysis::CurveShape::rising;
    if (rising > 0)
        warnings.push_back(std::to_string(rising) + " of " + std::to_string(tests.size())
                           + " tests: the stress ratio was still rising at the end; their yield states are lower "
                             "bounds (raise triaxial.target_axial_strain)");
    std::optional<double> lag_m, prominent_lag_m;
    const bool with_wire = spec.specimen.wire.pattern != api::WirePattern::none && prep.wire_nodes > 1;
    // At the end of the test at the highest pressure (the first of equals):
    // the wire's strain is largest and most developed there.
    const auto strained = static_cast<std::size_t>(std::max_element(pressures.begin(), pressures.end()) - pressures.begin());
    if (with_wire && strained < tests.size() && !tests[strained].snapshots.empty()) {
        const auto ac = eng::analysis::autocorrelation(
            tests[strained].snapshots.back().wire_segment_strain, spec.specimen.wire.segment_length_m);
        if (!ac.ok())
            warnings.push_back("wire autocorrelation: " + ac.error());
        else if (!ac.value().first_maximum_lag_m)
            warnings.push_back("wire autocorrelation: no local maximum after lag 0");
        else {
            lag_m = ac.value().first_maximum_lag_m;
            prominent_lag_m = ac.value().prominent_maximum_lag_m;
            if (ac.value().prominent_maximum_lag != ac.value().first_maximum_lag)
                warnings.push_back(noise_band_warning(ac.value()));
        }
    }

    // Writing: result.h5, then summary.json (its presence marks success).
    report(control, progress_stage::writing, 0.6, "writing result.h5 and summary.json");
    try {
        io::write_file_atomically(dir.result_h5(), [&](io::Group& root) { write_result(root, spec, specimen, tests, free_standing); });
        eng::io::write_xdmf(dir.result_h5(), dir.result_xdmf()); // ParaView's view of result.h5

        json::object summary;
        json::array jt;
        const std::size_t bodies = body_count(specimen.world);
        double body_steps = static_cast<double>(prep.steps) * static_cast<double>(bodies);
        double stepping_wall_s = prep.wall_time_s;
        std::uint64_t steps = prep.steps;
        for (std::size_t i = 0; i < tests.size(); ++i) {
            const auto& t = tests[i];
            steps += t.steps;
            body_steps += static_cast<double>(t.steps) * static_cast<double>(bodies);
            stepping_wall_s += t.wall_time_s;
            json::object o;
            o["confining_pressure_pa"] = pressures[i];
            o["plate_speed_m_per_s"] = spec.triaxial.plate_speed_m_per_s(i);
            o["peak_deviatoric_stress_pa"] = finite_or_null(t.peak_deviatoric_stress_pa);
            o["peak_axial_strain"] = finite_or_null(t.peak_axial_strain);
            o["sigma1_pa"] = finite_or_null(t.peak_sigma1_pa);
            o["sigma3_effective_pa"] = finite_or_null(t.peak_sigma3_effective_pa);
            if (t.strength) {
                const eng::analysis::StrengthReading& y = *t.strength;
                o["max_q_shape"] = eng::analysis::to_string(y.deviatoric.shape);
                json::object yo;
                yo["shape"] = eng::analysis::to_string(y.stress_ratio.shape);
                yo["stress_ratio"] = finite_or_null(y.stress_ratio.value);
                yo["axial_strain"] = finite_or_null(y.yield_axial_strain);
                yo["sigma1_pa"] = finite_or_null(y.yield_sigma1_pa);
                yo["sigma3_effective_pa"] = finite_or_null(y.yield_sigma3_pa);
                yo["deviatoric_stress_pa"] = finite_or_null(y.yield_sigma1_pa - y.yield_sigma3_pa);
                o["yield"] = std::move(yo);
                o["residual_stress_ratio"] = finite_or_null(y.residual_stress_ratio);
            } else {
                o["max_q_shape"] = nullptr;
                o["yield"] = nullptr;
                o["residual_stress_ratio"] = nullptr;
            }
            // What the test itself recorded; a test file written before it
            // was recorded has the job's setting and no verdict.
            o["consolidation"] = t.consolidation ? eng::to_string(*t.consolidation)
                                                 : api::to_string(spec.triaxial.consolidation);
            o["hold_time_s"] = t.hold_time_s;
            o["consolidated_sigma1_pa"] = finite_or_null(t.consolidated_sigma1_pa);
            o["consolidation_target_pa"] = finite_or_null(t.consolidation_target_pa);
            if (t.consolidation)
                o["consolidated"] = eng::within_consolidation_mismatch(t.consolidated_sigma1_pa, t.consolidation_target_pa);
            else
                o["consolidated"] = nullptr;
            if (const auto start = eng::loading_start(t.series)) {
                json::object so;
                so["sigma1_pa"] = finite_or_null(start->sigma1_pa);
                so["sigma3_effective_pa"] = finite_or_null(start->sigma3_effective_pa);
                so["stress_ratio"] = finite_or_null(start->stress_ratio);
                so["axial_strain"] = finite_or_null(start->axial_strain);
                so["rebound_axial_strain"] = finite_or_null(start->rebound_axial_strain);
                so["radial_strain"] = finite_or_null(start->radial_strain);
                o["loading_start"] = std::move(so);
            } else {
                o["loading_start"] = nullptr;
            }
            o["quasi_static"] = t.verdict.quasi_static;
            o["max_inertial_number"] = finite_or_null(t.verdict.max_inertial_number);
            o["mean_kinetic_to_elastic"] = finite_or_null(t.verdict.mean_kinetic_to_elastic);
            o["max_kinetic_to_elastic"] = finite_or_null(t.verdict.max_kinetic_to_elastic);
            if (spec.specimen.wire.breaking_strain) { // a breakable wire only: other summaries stay as they were
                o["wire_breaks"] = wire_breaks_json(t.wire_breaks);
                o["peak_failure"] = eng::to_string(eng::peak_failure(t.series, t.peak_sample, t.wire_breaks));
            }
            o["steps"] = t.steps;
            o["wall_time_s"] = t.wall_time_s;
            o["threads"] = test_threads[i];
            jt.push_back(std::move(o));
        }
        summary["name"] = spec.name;
        summary["tests"] = std::move(jt);

        summary["mohr_coulomb"] = mohr_coulomb_json(fit,
            "yield states: (sigma1, sigma3_effective) at the maximum of the smoothed stress ratio (tests[].yield)");
        summary["mohr_coulomb_max_q"]
            = mohr_coulomb_json(fit_max_q, "(sigma1, sigma3_effective) at the maximum of q (tests[].peak_*)");
        if (free_standing) {
            summary["free_standing"] = free_standing_json(*free_standing, fit, free_standing_threads);
            if (spec.specimen.wire.breaking_strain) {
                json::object& c = summary["free_standing"].as_object()["compression"].as_object();
                c["wire_breaks"] = wire_breaks_json(free_standing->wire_breaks);
                c["peak_failure"] = free_standing->compression
                                      ? json::value(eng::to_string(eng::peak_failure(free_standing->series,
                                            free_standing->compression->max_sigma1_sample, free_standing->wire_breaks)))
                                      : json::value(nullptr);
            }
            steps += free_standing->steps;
            body_steps += static_cast<double>(free_standing->steps) * static_cast<double>(bodies);
            stepping_wall_s += free_standing->wall_time_s;
        }
        summary["definitions"] = definitions_json();

        json::object sp;
        sp["cell"] = std::string(api::to_string(spec.triaxial.cell)); // which triaxial cell ran
        sp["grain_volume_fraction"] = prep.grain_volume_fraction;
        sp["wire_volume_fraction"] = prep.wire_volume_fraction;
        sp["wire_length_per_volume_m_per_m3"] = finite_or_null(wire_length_per_volume_m_per_m3(prep));
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
        sp["preparation_wall_time_s"] = prep.wall_time_s;
        if (prep.grain_sizes) sp["grain_sizes"] = grain_sizes_json(*prep.grain_sizes);
        if (wire_can_part(spec)) {
            json::array pieces;
            for (const eng::WirePiece& p : eng::wire_pieces(specimen.world))
                pieces.push_back(json::object{{"first_node", p.first_node}, {"nodes", p.nodes},
                    {"rest_length_m", p.rest_length_m}, {"length_m", p.length_m}});
            sp["wire_pieces"] = std::move(pieces);
            std::size_t cuts = 0;
            for (const eng::WireBreak& b : specimen.world.wire_breaks) cuts += b.cause == eng::WireBreakCause::cut;
            sp["wire_cuts"] = cuts;
            sp["wire_breaks_in_preparation"] = specimen.world.wire_breaks.size() - cuts;
        }
        summary["specimen"] = std::move(sp);

        json::object wire;
        wire["pattern"] = api::to_string(spec.specimen.wire.pattern);
        wire["autocorrelation_lag_m"] = lag_m ? json::value(*lag_m) : json::value(nullptr);
        wire["autocorrelation_prominent_lag_m"] = prominent_lag_m ? json::value(*prominent_lag_m) : json::value(nullptr);
        summary["wire"] = std::move(wire);

        json::array jw;
        for (const auto& w : warnings) jw.emplace_back(w);
        summary["warnings"] = std::move(jw);

        json::object e;
        e["time_step_s"] = specimen.world.dt_s;
        e["steps"] = steps;
        // The stages' own times, added: tests that ran at once overlap.
        e["wall_time_s"] = stepping_wall_s;
        e["body_steps_per_second"] = stepping_wall_s > 0.0 ? json::value(body_steps / stepping_wall_s) : json::value(nullptr);
        e["threads"] = specimen.threads; // the preparation's; each test's is in tests[]
        e["density_scale"] = spec.engine.density_scale;
        summary["engine"] = std::move(e);

        io::write_text_file_atomically(dir.summary(), api::json_document_text(summary) + "\n");
    } catch (const std::exception& ex) {
        return io::write_failure_text("writing the results failed: ", ex);
    }
    report(control, progress_stage::writing, 1.0, "done");
    return std::nullopt;
}

StageError run(const api::JobSpec& spec, const JobDir& dir, const StageControl& control)
{
    // Overall progress: the stages' shares of the job's estimated work (api::progress_shares).
    const std::size_t n_tests = spec.triaxial.confining_pressures_pa.size();
    const api::WorkEstimate work = api::estimated_work(spec);
    const api::ProgressShares shares = api::progress_shares(work);
    std::mutex report_mutex; // progress comes from several tests' threads

    // The work for the ETA (eta.hpp), in estimated steps: what is left, and
    // what this process has run — each part's fraction gained between its
    // reports, but not the jump of a test resumed from a checkpoint to the
    // checkpoint's step (run before), nor the rest of a pour that settled
    // before its time limit (never run).
    std::vector<double> done(n_tests, 1.0);  // fraction of each test
    double prep_done = 0.0;                  // fraction of the preparation
    // Fraction of the free-standing test (1 when the job has none or it ran before).
    std::error_code fs_ec;
    double free_standing_done = spec.free_standing.enabled && !std::filesystem::exists(dir.free_standing(), fs_ec) ? 0.0 : 1.0;
    // From a checkpoint: its first step report jumps (as a test's, below).
    bool free_standing_resumed = free_standing_done == 0.0 && std::filesystem::exists(dir.free_standing_checkpoint(), fs_ec);
    double steps_run = 0.0;
    bool testing = false;  // the tests have begun
    const auto report_work = [&] {  // under report_mutex
        if (!control.work) return;
        double left = (1.0 - prep_done) * work.preparation_steps;
        for (std::size_t k = 0; k < n_tests; ++k) left += (1.0 - done[k]) * work.test_steps[k];
        left += (1.0 - free_standing_done) * work.free_standing_steps;
        control.work(WorkSteps{steps_run, left, testing});
    };

    StageControl prep_control = control;
    prep_control.progress = [&](const char* stage, double f, const std::string& m) {
        std::lock_guard lock(report_mutex);
        steps_run += std::max(0.0, f - prep_done) * work.preparation_steps;
        prep_done = f;
        report_work();
        report(control, stage, shares.overall(f, {}, 0.0, 0.0), m);
    };
    if (auto e = prepare(spec, dir, prep_control)) return e;
    prep_done = 1.0;  // prepared now, or by an earlier run (then it reported nothing)

    std::vector<std::size_t> pending;
    std::vector<bool> resumed(n_tests, false);  // from a checkpoint: its first step report jumps
    std::error_code ec;
    for (std::size_t k = 0; k < n_tests; ++k)
        if (!std::filesystem::exists(dir.test(k), ec)) {
            pending.push_back(k);
            done[k] = 0.0;
            resumed[k] = std::filesystem::exists(dir.checkpoint(k), ec);
        }

    // Tests at once: as many as threads (each test is deterministic for any
    // thread count, so the results do not depend on how they are shared).
    // When a worker finds no test left, its threads go to the running test
    // with the most work left: that test stops at its next step, saves its
    // checkpoint and continues from it on the threads of both (the same
    // bits: a restored run continues bit-identically on any thread count),
    // so no core idles while the campaign's last tests run.
    const unsigned threads = control.threads ? control.threads : std::max(1u, std::thread::hardware_concurrency());
    const std::size_t at_once = std::max<std::size_t>(1, std::min<std::size_t>(pending.size(), threads));
    std::vector<StageError> errors(n_tests);
    // Each test's stop flag: the campaign's cancel (copied in by the watcher
    // below) or a request to hand its work to more threads.
    const std::unique_ptr<std::atomic<bool>[]> stop(new std::atomic<bool>[n_tests]);
    for (std::size_t k = 0; k < n_tests; ++k) stop[k].store(false);
    std::mutex schedule_mutex;  // next, running_threads, handed_over, spare_threads
    std::size_t next = 0;
    std::vector<unsigned> running_threads(n_tests, 0);  // a running test's threads; 0: not running
    std::vector<bool> handed_over(n_tests, false);       // asked to stop and take the spare threads
    unsigned spare_threads = 0;
    const auto cancelled = [&] { return control.cancel && control.cancel->load(); };
    const auto worker = [&](unsigned worker_threads) {
        for (;;) {
            std::size_t k = 0;
            {
                std::lock_guard lock(schedule_mutex);
                if (next == pending.size() || cancelled()) break;
                k = pending[next++];
                running_threads[k] = worker_threads;
            }
            for (;;) {
                StageControl tc = control;
                tc.threads = worker_threads;
                tc.cancel = &stop[k];
                tc.progress = [&, k](const char* stage, double f, const std::string& m) {
                    std::lock_guard lock(report_mutex);
                    testing = true;
                    if (resumed[k] && f > 0.0) resumed[k] = false;  // the checkpoint's step
                    else steps_run += std::max(0.0, f - done[k]) * work.test_steps[k];
                    // Never back: a test continued on more threads reports 0 as it restarts.
                    done[k] = std::max(done[k], f);
                    report_work();
                    report(control, stage, shares.overall(1.0, done, 0.0, 0.0), m);
                };
                errors[k] = run_test(dir, k, tc);
                std::lock_guard lock(schedule_mutex);
                if (!errors[k] || !handed_over[k] || cancelled()) {
                    running_threads[k] = 0;
                    break;
                }
                // Stopped to take more threads: continue from its checkpoint.
                worker_threads += std::exchange(spare_threads, 0);
                running_threads[k] = worker_threads;
                handed_over[k] = false;
                stop[k].store(false);
                errors[k].reset();
                std::lock_guard report_lock(report_mutex);
                resumed[k] = true;
            }
        }
        // Nothing left to start: these threads go to the running test with
        // the most estimated work left, unless it is nearly done (a stop
        // and a restore cost a checkpoint's save and read). Not without
        // checkpoints: the test would start again from its first step.
        std::lock_guard lock(schedule_mutex);
        if (cancelled() || !(control.checkpoint_interval_s > 0.0)) return;
        std::size_t best = n_tests;
        double most_left = 0.0;
        for (std::size_t k = 0; k < n_tests; ++k) {
            if (running_threads[k] == 0 || handed_over[k]) continue;
            std::lock_guard report_lock(report_mutex);
            const double left = (1.0 - done[k]) * work.test_steps[k];
            if (done[k] < 0.9 && left > most_left) most_left = left, best = k;
        }
        spare_threads += worker_threads;
        if (best < n_tests) {
            handed_over[best] = true;
            stop[best].store(true);
        }
    };
    // The campaign's cancel reaches every test within 20 ms.
    std::atomic<bool> tests_over{false};
    std::thread watcher;
    if (control.cancel)
        watcher = std::thread([&] {
            while (!tests_over.load()) {
                if (control.cancel->load())
                    for (std::size_t k = 0; k < n_tests; ++k) stop[k].store(true);
                std::this_thread::sleep_for(std::chrono::milliseconds(20));
            }
        });
    std::vector<std::thread> workers;
    for (std::size_t t = 1; t < at_once; ++t)
        workers.emplace_back(worker, static_cast<unsigned>(threads / at_once + (t < threads % at_once ? 1 : 0)));
    worker(static_cast<unsigned>(threads / at_once + (threads % at_once > 0 ? 1 : 0)));
    for (auto& t : workers) t.join();
    tests_over.store(true);
    if (watcher.joinable()) watcher.join();
    for (const StageError& e : errors)
        if (e) return e;
    if (control.cancel && control.cancel->load()) return std::string("cancelled");
    // The free-standing test, after the triaxial tests, on every thread: its
    // share of the progress and of the work left, as a test's.
    {
        StageControl fc = control;
        fc.progress = [&](const char* stage, double f, const std::string& m) {
            std::lock_guard lock(report_mutex);
            testing = true;
            if (free_standing_resumed && f > 0.0) free_standing_resumed = false; // the checkpoint's step
            else steps_run += std::max(0.0, f - free_standing_done) * work.free_standing_steps;
            free_standing_done = std::max(free_standing_done, f);
            report_work();
            report(control, stage, shares.overall(1.0, done, 0.0, free_standing_done), m);
        };
        if (auto e = run_free_standing_test(dir, fc)) return e;
    }

    StageControl analysis_control = control;
    analysis_control.progress = [&](const char* stage, double f, const std::string& m) {
        std::lock_guard lock(report_mutex);
        report_work();  // nothing left to step
        report(control, stage, shares.overall(1.0, std::vector<double>(n_tests, 1.0), f, 1.0), m);
    };
    return analyse(dir, analysis_control);
}

} // namespace wiredem::campaign
