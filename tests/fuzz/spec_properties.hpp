// The properties every job spec the parser accepts must have (issue 18), and
// those of every spec the server accepts (201): checked by the spec fuzz
// targets on each accepted input.
#pragma once

#include "fuzz_check.hpp"

#include "api/derived.hpp"
#include "api/engine_settings.hpp"
#include "api/job_spec.hpp"
#include "specimen/box_preparation.hpp"
#include "specimen/preparation.hpp"
#include "state/clump_shape.hpp"
#include "triaxial/free_standing.hpp"
#include "triaxial/triaxial.hpp"

#include <boost/json.hpp>

#include <cmath>
#include <string>
#include <string_view>

namespace wiredem::fuzz {

/// Bound on the CPU time of validating one spec (parse_job_spec from text),
/// in the fuzz build (ASan + UBSan at -O1, about 3 times slower than Release):
/// docs/fuzzing.md has the measured times behind it.
inline constexpr double max_validation_cpu_s = 1.0;

/// A spec that parse_job_spec accepted, i.e. one `wiredem run` would run:
/// it reads back as itself from its JSON value and text; its time step
/// (given or auto) and stable limit are finite and positive; its work and
/// body estimates are numbers (not NaN); and what the runner computes from it
/// before running (client/run_command.cpp: the steps each test expects,
/// engine::expected_triaxial_steps) has no undefined behaviour (UBSan); and
/// the engine's own set-up rules, the preparation's (the box's too with the
/// cuboid cell) and each test's, pass.
inline void check_parsed_spec(const api::JobSpec& spec)
{
    const boost::json::value doc = api::to_json(spec);
    const std::string text = boost::json::serialize(doc);
    const auto from_value = api::parse_job_spec(doc);
    FUZZ_CHECK(from_value.ok() && from_value.value() == spec, "to_json does not read back: " + text);
    const auto from_text = api::parse_job_spec(std::string_view(text));
    FUZZ_CHECK(from_text.ok() && from_text.value() == spec, "the serialized spec does not read back: " + text);

    const api::StableStep stable = api::stable_time_step(spec);
    FUZZ_CHECK(std::isfinite(stable.critical_s) && stable.critical_s > 0.0, text);
    FUZZ_CHECK(std::isfinite(stable.auto_s) && stable.auto_s > 0.0, text);
    const api::WorkEstimate work = api::estimated_work(spec);
    FUZZ_CHECK(std::isfinite(work.time_step_s) && work.time_step_s > 0.0, text);
    FUZZ_CHECK(!std::isnan(work.preparation_steps) && !std::isnan(work.tests_total_steps())
            && !std::isnan(work.samples_per_test), text);
    FUZZ_CHECK(work.test_steps.size() == spec.triaxial.confining_pressures_pa.size(), text);
    const api::BodyCounts bodies = api::estimated_body_counts(spec);
    // In doubles: a sum of saturated counts must not wrap round to a small one.
    const double total = static_cast<double>(bodies.grains) + static_cast<double>(bodies.wire_nodes)
                       + static_cast<double>(bodies.membrane_nodes);
    FUZZ_CHECK(total <= static_cast<double>(spec.engine.max_bodies), "bodies beyond engine.max_bodies: " + text);
    FUZZ_CHECK(static_cast<double>(bodies.total()) == total || total > 9e15, "the body total wraps: " + text);

    const double height_m = engine::estimated_fill_height_m(api::preparation_geometry(spec));
    FUZZ_CHECK(std::isfinite(height_m) && height_m > 0.0, text);
    for (std::size_t k = 0; k < spec.triaxial.confining_pressures_pa.size(); ++k)
        (void)engine::expected_triaxial_steps(api::triaxial_settings(spec, k), height_m, work.time_step_s);

    // Accepted means it runs: the engine's own set-up rules pass, the
    // preparation's (engine::preparation_error) and each test's
    // (engine::settings_error), asked of the spec the runner would build.
    const auto preparation = engine::preparation_error(api::preparation_geometry(spec));
    FUZZ_CHECK(!preparation, "accepted, but the preparation refuses it (" + preparation.value_or("") + "): " + text);
    for (std::size_t k = 0; k < spec.triaxial.confining_pressures_pa.size(); ++k) {
        const auto test = engine::settings_error(api::triaxial_settings(spec, k));
        FUZZ_CHECK(!test, "accepted, but test " + std::to_string(k) + " refuses its settings ("
                              + (test ? test->field + ": " + test->message : "") + "): " + text);
    }
    if (spec.triaxial.cell == api::CellKind::cuboid) { // the box preparation's rules too
        const auto box = api::box_preparation_spec(spec);
        FUZZ_CHECK(box.ok(), "accepted, but the box preparation refuses it (" + (box.ok() ? "" : box.error()) + "): " + text);
        const auto e = engine::box_preparation_error(box.value());
        FUZZ_CHECK(!e, "accepted, but the box preparation refuses it (" + e.value_or("") + "): " + text);
    }
    if (spec.free_standing.enabled) {
        const auto test = engine::free_standing_settings_error(api::free_standing_settings(spec));
        FUZZ_CHECK(!test, "accepted, but the free-standing test refuses its settings ("
                              + (test ? test->field + ": " + test->message : "") + "): " + text);
    }
}

/// Computes the built-in clump templates' bodies once (api::grain_shape_body
/// keeps them for the process): a one-off ~50 ms each in Release, a second
/// under ASan, that a server pays once, not per validation. The spec fuzz
/// targets call it from LLVMFuzzerInitialize so that the validation time
/// bound measures validation.
inline void warm_clump_templates()
{
    for (std::string_view name : engine::builtin_clump_names) {
        api::GrainShapeSpec g;
        g.template_name = std::string(name);
        (void)api::grain_shape_body(g);
    }
}

/// Limits a server enforces at submit (ServerConfig's defaults unless given).
struct ServerLimits {
    double max_bodies;
    double max_steps;
    double max_samples_per_test;
};

/// A spec the server accepted: finite estimates within its limits.
inline void check_served_spec(const api::JobSpec& spec, const ServerLimits& limits)
{
    const std::string text = boost::json::serialize(api::to_json(spec));
    const api::WorkEstimate work = api::estimated_work(spec);
    FUZZ_CHECK(std::isfinite(work.total_steps()) && work.total_steps() <= limits.max_steps, text);
    FUZZ_CHECK(std::isfinite(work.samples_per_test) && work.samples_per_test <= limits.max_samples_per_test, text);
    const api::BodyCounts bodies = api::estimated_body_counts(spec);
    const double total = static_cast<double>(bodies.grains) + static_cast<double>(bodies.wire_nodes)
                       + static_cast<double>(bodies.membrane_nodes);
    FUZZ_CHECK(total <= limits.max_bodies, "bodies beyond the server's limit: " + text);
}

} // namespace wiredem::fuzz
