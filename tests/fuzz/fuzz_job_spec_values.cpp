// The job spec at the value level: valid documents (examples/*.json and the
// defaults) whose numeric fields take edge values (0, -0, the smallest
// denormal, 1e-300, 1e300, the integer limits, each documented bound and the
// doubles either side of it, any field's bound, the value scaled by powers
// of ten) in combinations, with arrays resized, optionals unset and enums
// switched, so that validation and the estimates derived from a spec see
// hostile values, not just hostile syntax. Each document is validated as
// text (what a client sends) and submitted to the real server (the Router
// with ServerConfig's default limits, server_fixture.hpp): an accepted spec
// has the properties of spec_properties.hpp, validation stays under the
// time bound, and the server answers 201 only for a spec the parser accepts.
//
// The documented ranges are read from docs/job-spec.md's tables (at start),
// so the edges follow the documentation (48 fields have numeric bounds there;
// fewer than 45 means the tables changed form and this reader must follow).
#include "response_check.hpp"
#include "server_fixture.hpp"
#include "spec_properties.hpp"

#include <boost/json.hpp>
#include <fuzzer/FuzzedDataProvider.h>

#include <cfloat>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <regex>
#include <variant>

using namespace wiredem;
namespace json = boost::json;

namespace {

/// Where a value sits in a document: object keys and array indices.
using PathStep = std::variant<std::string, std::size_t>;

/// A field that holds (or may hold) a number.
struct Leaf {
    std::vector<PathStep> path;
    std::string key;       ///< the documented path: dots, no indices
    bool integer = false;  ///< an integer field
};

struct Base {
    json::value doc;          ///< a complete valid document (api::to_json)
    std::vector<Leaf> leaves; ///< its numeric fields, optionals and array elements included
};

/// Fields whose JSON is an integer (api::to_json writes them as such).
bool is_integer_key(const std::string& key)
{
    return key == "seed" || key == "specimen.grain_count" || key == "engine.threads" || key == "engine.max_bodies";
}

/// Optional numbers: the text that unsets them.
const std::map<std::string, json::value>& unset_values()
{
    static const std::map<std::string, json::value> m{{"engine.time_step_s", "auto"},
        {"specimen.wire.bending_yield_strain", "elastic"}, {"specimen.wire.length_m", nullptr},
        {"specimen.membrane.contact_radius_m", nullptr}, {"specimen.pouring.fill_rate_m_per_s", nullptr},
        {"triaxial.max_hold_time_s", nullptr}};
    return m;
}

void collect_leaves(const json::value& v, std::vector<PathStep>& path, const std::string& key, std::vector<Leaf>& out)
{
    if (const auto* o = v.if_object()) {
        for (const auto& kv : *o) {
            path.emplace_back(std::string(kv.key()));
            collect_leaves(kv.value(), path, key.empty() ? std::string(kv.key()) : key + "." + std::string(kv.key()), out);
            path.pop_back();
        }
    } else if (const auto* a = v.if_array()) {
        for (std::size_t i = 0; i < a->size(); ++i) {
            path.emplace_back(i);
            collect_leaves((*a)[i], path, key, out);
            path.pop_back();
        }
    } else if (v.is_number() || unset_values().contains(key)) {
        out.push_back({path, key, is_integer_key(key)});
    }
}

json::value* at(json::value& doc, const std::vector<PathStep>& path)
{
    json::value* cur = &doc;
    for (const auto& step : path) {
        if (const auto* k = std::get_if<std::string>(&step)) {
            auto* o = cur->if_object();
            if (!o || !o->contains(*k)) return nullptr;
            cur = &(*o)[*k];
        } else {
            auto* a = cur->if_array();
            const std::size_t i = std::get<std::size_t>(step);
            if (!a || i >= a->size()) return nullptr;
            cur = &(*a)[i];
        }
    }
    return cur;
}

/// Every number in each range of docs/job-spec.md's "allowed" column, by path.
std::map<std::string, std::vector<double>> documented_bounds()
{
    std::string md = fuzz::read_file(std::filesystem::path(WIREDEM_SOURCE_DIR) / "docs" / "job-spec.md");
    // The docs write some numbers for people: −1, 10⁸, 2π.
    const std::pair<std::string, std::string> plain[] = {{"\u2212", "-"}, {"10\u2078", "1e8"}, {"10\u2079", "1e9"},
        {"2\u03c0", "6.283185307179586"}, {"2\u2076\u2074 - 1", "1.8446744073709552e19"}};
    for (const auto& [from, to] : plain)
        for (std::size_t at = md.find(from); at != std::string::npos; at = md.find(from, at + to.size()))
            md.replace(at, from.size(), to);
    std::map<std::string, std::vector<double>> bounds;
    const std::regex row(R"(\n\| `([a-z_.]+)` \|[^|\n]*\|[^|\n]*\|[^|\n]*\|([^|\n]*)\|)");
    const std::regex range(R"([\[(]\s*([-+0-9.e]+)\s*,\s*([-+0-9.e]+)\s*[\])])");
    for (std::sregex_iterator it(md.begin(), md.end(), row), end; it != end; ++it) {
        const std::string key = (*it)[1];
        const std::string allowed = (*it)[2];
        if (bounds.contains(key)) continue;  // the first table that names a field gives its range
        for (std::sregex_iterator r(allowed.begin(), allowed.end(), range); r != end; ++r)
            for (int i : {1, 2}) bounds[key].push_back(std::strtod((*r)[i].str().c_str(), nullptr));
    }
    std::size_t n = 0;
    for (const auto& [key, b] : bounds) n += b.empty() ? 0 : 1;
    if (n < 45) {
        std::fprintf(stderr, "docs/job-spec.md: found the ranges of only %zu fields\n", n);
        std::abort();
    }
    return bounds;
}

struct Setup {
    std::vector<Base> bases;
    std::map<std::string, std::vector<double>> bounds;
    std::vector<double> all_bounds;
};

const Setup& setup()
{
    static const Setup s = [] {
        Setup s;
        s.bounds = documented_bounds();
        for (const auto& [key, b] : s.bounds) s.all_bounds.insert(s.all_bounds.end(), b.begin(), b.end());
        std::vector<std::string> texts = fuzz::example_documents();
        texts.emplace_back("{}");
        texts.emplace_back(R"({"contact": {"normal_damping_s": 1e-6}, "specimen": {"wire": {"pattern": "spiral_helix"}}})");
        for (const auto& text : texts) {
            const auto spec = api::parse_job_spec(std::string_view(text));
            if (!spec.ok()) {
                std::fprintf(stderr, "a seed document is invalid: %s\n", text.c_str());
                std::abort();
            }
            Base b{api::to_json(spec.value()), {}};
            std::vector<PathStep> path;
            collect_leaves(b.doc, path, "", b.leaves);
            s.bases.push_back(std::move(b));
        }
        return s;
    }();
    return s;
}

/// The double next to x towards `to`.
double next(double x, double to) { return std::nextafter(x, to); }

json::value edge_value(FuzzedDataProvider& in, const Leaf& leaf, const json::value& current)
{
    constexpr double inf = std::numeric_limits<double>::infinity();
    const Setup& s = setup();
    switch (in.ConsumeIntegralInRange<int>(0, 5)) {
    case 0: {  // the usual suspects
        static const json::value edges[] = {0.0, -0.0, std::numeric_limits<double>::denorm_min(),
            -std::numeric_limits<double>::denorm_min(), DBL_MIN, 1e-300, 1e-15, 1e300, -1e300, DBL_MAX, -DBL_MAX, 1.0,
            -1.0, 0.5, 9007199254740993.0, 9223372036854775808.0, 18446744073709551616.0,
            std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min(),
            std::numeric_limits<std::uint64_t>::max(), std::int64_t{0}, std::int64_t{-1},
            std::int64_t{std::numeric_limits<std::uint32_t>::max()},
            std::int64_t{std::numeric_limits<std::uint32_t>::max()} + 1};
        return edges[in.ConsumeIntegralInRange<std::size_t>(0, std::size(edges) - 1)];
    }
    case 1:
    case 2: {  // this field's documented bounds and their neighbours
        const auto it = s.bounds.find(leaf.key);
        const auto& b = it != s.bounds.end() && !it->second.empty() ? it->second : s.all_bounds;
        const double bound = b[in.ConsumeIntegralInRange<std::size_t>(0, b.size() - 1)];
        const int side = in.ConsumeIntegralInRange<int>(-1, 1);
        if (leaf.integer && std::abs(bound) < 9e18) return static_cast<std::int64_t>(bound) + side;
        return side == 0 ? bound : next(bound, side * inf);
    }
    case 3: {  // another field's bound
        const double bound = s.all_bounds[in.ConsumeIntegralInRange<std::size_t>(0, s.all_bounds.size() - 1)];
        const int side = in.ConsumeIntegralInRange<int>(-1, 1);
        return side == 0 ? bound : next(bound, side * inf);
    }
    case 4: {  // the value it had, scaled by a power of ten
        const double x = current.is_number() ? current.to_number<double>() : 1e-3;
        const double scaled = x * std::pow(10.0, in.ConsumeIntegralInRange<int>(-320, 320));
        if (leaf.integer && std::abs(scaled) < 9e18) return static_cast<std::int64_t>(scaled);
        return std::isfinite(scaled) ? scaled : std::copysign(DBL_MAX, scaled);
    }
    default:
        return in.ConsumeFloatingPoint<double>();
    }
}

/// Applies one change to `doc`.
void mutate(FuzzedDataProvider& in, json::value& doc, const Base& base)
{
    switch (in.ConsumeIntegralInRange<int>(0, 9)) {
    default: {  // a number, the commonest change
        const Leaf& leaf = base.leaves[in.ConsumeIntegralInRange<std::size_t>(0, base.leaves.size() - 1)];
        if (json::value* v = at(doc, leaf.path)) *v = edge_value(in, leaf, *v);
        break;
    }
    case 6: {  // an optional unset
        const auto& unset = unset_values();
        auto it = unset.begin();
        std::advance(it, in.ConsumeIntegralInRange<std::size_t>(0, unset.size() - 1));
        std::vector<PathStep> path;
        std::size_t from = 0;
        for (std::size_t dot = it->first.find('.'); ; dot = it->first.find('.', from)) {
            path.emplace_back(it->first.substr(from, dot - from));
            if (dot == std::string::npos) break;
            from = dot + 1;
        }
        if (json::value* v = at(doc, path)) *v = it->second;
        break;
    }
    case 7: {  // an array resized: its elements then take edge values too
        const bool pressures = in.ConsumeBool();
        auto& a = doc.at("triaxial").at(pressures ? "confining_pressures_pa" : "snapshot_strains").as_array();
        const std::size_t n = in.ConsumeIntegralInRange<std::size_t>(0, pressures ? 17 : 65);
        const double step = pressures ? 1e3 * std::pow(10.0, in.ConsumeIntegralInRange<int>(-300, 4))
                                      : std::pow(10.0, in.ConsumeIntegralInRange<int>(-320, 0));
        a.clear();
        for (std::size_t i = 0; i < n; ++i) a.emplace_back(static_cast<double>(i + (pressures ? 1 : 0)) * step);
        break;
    }
    case 8: {  // an enum switched
        static const std::pair<const char*, std::vector<const char*>> enums[] = {
            {"pattern", {"none", "helix", "spiral_helix", "radial_helix"}}, {"integrator", {"gear5", "verlet"}},
            {"edges", {"tension_only", "linear"}}, {"consolidation", {"cell_pressure", "effective"}},
            {"cell", {"membrane", "cuboid"}}, {"grain_preset", {"none", "gravel"}}};
        const auto& [key, names] = enums[in.ConsumeIntegralInRange<std::size_t>(0, std::size(enums) - 1)];
        const char* name = names[in.ConsumeIntegralInRange<std::size_t>(0, names.size() - 1)];
        json::object& parent = std::string(key) == "integrator"      ? doc.at("engine").as_object()
                             : std::string(key) == "edges"           ? doc.at("specimen").at("membrane").as_object()
                             : std::string(key) == "consolidation" || std::string(key) == "cell" ? doc.at("triaxial").as_object()
                             : std::string(key) == "grain_preset"    ? doc.at("specimen").as_object()
                                                                     : doc.at("specimen").at("wire").as_object();
        parent[key] = name;
        // A preset refuses the fields it sets: half the time they go, so the preset is also read.
        if (std::string(key) == "grain_preset" && in.ConsumeBool()) {
            for (const char* k : {"grain_sizes", "grain_shape", "grain_radius_spread"}) parent.erase(k);
            for (const char* k : {"friction_coeff", "rolling_friction_coeff", "rolling_damping_ratio"})
                doc.at("contact").as_object().erase(k);
        }
        break;
    }
    case 9: {  // the other form of the normal damping
        json::object& c = doc.at("contact").as_object();
        if (c.contains("normal_damping_s")) {
            c.erase("normal_damping_s");
            c["restitution"] = in.ConsumeProbability<double>();
            c["restitution_reference_speed_m_per_s"] = 0.1;
        } else {
            c.erase("restitution");
            c.erase("restitution_reference_speed_m_per_s");
            c["normal_damping_s"] = in.ConsumeProbability<double>() * 1e-5;
        }
        break;
    }
    }
}

/// The server, recreated when its queue is full of accepted jobs.
std::unique_ptr<fuzz::ServerFixture> fixture;

/// The slowest validation seen, reported at exit (docs/fuzzing.md).
double slowest_cpu_s = 0.0;
std::string slowest_doc;

void report_slowest()
{
    std::fprintf(stderr, "slowest validation: %.1f ms of CPU (bound %.0f ms)\n", 1e3 * slowest_cpu_s,
        1e3 * fuzz::max_validation_cpu_s);
    if (std::getenv("WIREDEM_FUZZ_SHOW_SLOWEST")) std::fprintf(stderr, "%s\n", slowest_doc.c_str());
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    (void)setup();
    fuzz::warm_clump_templates();
    std::atexit(report_slowest);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    FuzzedDataProvider in(data, size);
    const Setup& s = setup();
    const Base& base = s.bases[in.ConsumeIntegralInRange<std::size_t>(0, s.bases.size() - 1)];
    json::value doc = base.doc;
    const int changes = in.ConsumeIntegralInRange<int>(1, 8);
    for (int i = 0; i < changes && in.remaining_bytes() > 0; ++i) mutate(in, doc, base);
    const std::string text = json::serialize(doc);

    const double t0 = fuzz::thread_cpu_seconds();
    const auto parsed = api::parse_job_spec(std::string_view(text));
    const double took = fuzz::thread_cpu_seconds() - t0;
    if (took > slowest_cpu_s) {
        slowest_cpu_s = took;
        slowest_doc = text;
    }
    FUZZ_CHECK(took <= fuzz::max_validation_cpu_s, "validation took " + std::to_string(took) + " s of CPU: " + text);
    if (parsed.ok()) fuzz::check_parsed_spec(parsed.value());

    if (!fixture) fixture = std::make_unique<fuzz::ServerFixture>();
    server::Request req{server::http::verb::post, "/v1/jobs", 11};
    req.set(server::http::field::host, "127.0.0.1:8080");
    req.set(server::http::field::content_type, "application/json");
    req.body() = text;
    req.prepare_payload();
    const server::Response res = fixture->router().dispatch(req);
    const unsigned status = server::status_of(res);
    fuzz::check_response(res, req.method(), fuzz::result_bytes, text);
    FUZZ_CHECK(status == 201 || status == 400 || status == 429, "status " + std::to_string(status) + " for " + text);
    if (status == 201) {
        FUZZ_CHECK(parsed.ok(), "the server accepted a spec the parser rejects: " + text);
        const auto& cfg = fixture->config();
        fuzz::check_served_spec(parsed.value(), {static_cast<double>(cfg.max_bodies_per_job), cfg.max_steps_per_job,
                                                    cfg.max_samples_per_test});
    } else if (status == 429) {
        fixture.reset();  // the queue is full of accepted jobs: a fresh store
    }
    return 0;
}
