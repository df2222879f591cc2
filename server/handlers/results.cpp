// Result data routes: result.h5 read through engine/io/hdf5 (read-only), as
// JSON for figures and series (api/result_data), as raw little-endian arrays
// for the 3D view; the offline report (api/report).
#include "results.hpp"

#include "../job_files.hpp"

#include "api/job_spec.hpp"
#include "api/json_text.hpp"
#include "api/report.hpp"
#include "api/result_data.hpp"
#include "files.hpp"
#include "io/hdf5.hpp"
#include "io/snapshot.hpp"
#include "triaxial/result_names.hpp"
#include "triaxial/series_columns.hpp"

#include <boost/json.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <limits>
#include <optional>
#include <string_view>
#include <variant>

namespace wiredem::server {
namespace json = boost::json;
namespace io = engine::io;

namespace {

static_assert(std::endian::native == std::endian::little, "the binary arrays are sent in the host's byte order");

Response not_found(const Request& req, const std::string& what)
{
    return error_response(req, http::status::not_found, "not_found", what);
}

Response bad_parameter(const Request& req, const std::string& message, const std::string& field)
{
    return error_response(req, http::status::bad_request, "bad_parameter", message, field);
}

/// The query parameter `name`, or nullopt; `known` are the route's parameters:
/// any other, or one given twice, is reported through `problem`.
struct Query {
    const QueryParams& params;
    std::optional<std::pair<std::string, std::string>> check(std::initializer_list<std::string_view> known) const
    {
        std::vector<std::string_view> seen;
        for (const auto& [key, value] : params) {
            if (std::find(known.begin(), known.end(), key) == known.end()) {
                std::string list;
                for (auto k : known) list += (list.empty() ? "" : ", ") + std::string(k);
                return std::pair{key, known.size() == 0 ? "this route takes no query parameters"
                                                        : "unknown parameter (known: " + list + ")"};
            }
            if (std::find(seen.begin(), seen.end(), key) != seen.end()) return std::pair{key, std::string("parameter given twice")};
            seen.push_back(key);
        }
        return std::nullopt;
    }
    std::optional<std::string> get(std::string_view name) const
    {
        for (const auto& [key, value] : params)
            if (key == name) return value;
        return std::nullopt;
    }
};

std::string shape_text(const std::vector<std::size_t>& shape)
{
    std::string s;
    for (std::size_t n : shape) {
        if (!s.empty()) s += ',';  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on "," + std::string&&
        s += std::to_string(n);
    }
    return s;
}

/// One dataset of `g` as raw little-endian float32 or int32 rows (the dtype
/// api::arrays_of lists it with).
Response array_response(const Request& req, const io::Group& g, const std::string& name, const std::string& where)
{
    std::string dtype;
    for (const auto& a : api::arrays_of(g, ""))
        if (a.at("name").get_string() == name) dtype = std::string(a.at("dtype").get_string());
    if (dtype.empty()) return not_found(req, where + " has no array '" + name + "'");
    const io::Dataset d = g.open_dataset(name);
    std::string body;
    if (dtype == "int32") {
        const std::vector<std::int64_t> v = d.read_int64s();
        std::vector<std::int32_t> narrow(v.size());
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (v[i] < std::numeric_limits<std::int32_t>::min() || v[i] > std::numeric_limits<std::int32_t>::max())
                throw std::runtime_error(where + "/" + name + ": value " + std::to_string(v[i]) + " does not fit int32");
            narrow[i] = static_cast<std::int32_t>(v[i]);
        }
        body.assign(reinterpret_cast<const char*>(narrow.data()), narrow.size() * sizeof(std::int32_t));
    } else {
        const std::vector<double> v = d.read_doubles();
        std::vector<float> narrow(v.begin(), v.end());
        body.assign(reinterpret_cast<const char*>(narrow.data()), narrow.size() * sizeof(float));
    }
    auto res = text_response(req, http::status::ok, std::move(body), "application/octet-stream");
    res.set("X-Wiredem-Shape", shape_text(d.shape()));
    res.set("X-Wiredem-Dtype", dtype);
    return res;
}

/// What GET …/tests/{test}/series?max_points=N&columns=a,b asks for.
struct SeriesQuery {
    std::vector<std::string> columns;  ///< in the order asked, each once; empty: all
    std::size_t max_points = api::max_series_points;
};

/// The series route's query against the test's `available` columns, or its 400.
std::variant<SeriesQuery, Response> series_query(
    const Request& req, const std::string& name, const std::vector<std::string>& available, const Query& q)
{
    if (auto bad = q.check({"max_points", "columns"})) return bad_parameter(req, bad->second, bad->first);
    SeriesQuery out;
    if (auto c = q.get("columns")) {
        std::string_view rest = *c;
        while (true) {
            const auto comma = rest.find(',');
            const std::string one(rest.substr(0, comma));
            if (std::find(available.begin(), available.end(), one) == available.end())
                return bad_parameter(req, "test " + name + " has no column '" + one + "'", "columns");
            if (std::find(out.columns.begin(), out.columns.end(), one) == out.columns.end()) out.columns.push_back(one);
            if (comma == std::string_view::npos) break;
            rest.remove_prefix(comma + 1);
        }
    }
    if (auto m = q.get("max_points")) {
        std::size_t v = 0;
        auto [p, ec] = std::from_chars(m->data(), m->data() + m->size(), v);
        if (m->empty() || ec != std::errc() || p != m->data() + m->size() || v < 2 || v > api::max_series_points)
            return bad_parameter(req, "max_points must be an integer in [2, " + std::to_string(api::max_series_points) + "]",
                "max_points");
        out.max_points = v;
    }
    return out;
}

/// GET …/tests/{test}/series of a succeeded job, from result.h5, or
/// …/free_standing/series from a file that holds the test; `available`: the
/// group's series columns (all of them when the query names none).
Response series(const Request& req, const io::Group& t, const std::string& name, const std::vector<std::string>& available,
    const Query& q, const json::object& extra = {})
{
    auto parsed = series_query(req, name, available, q);
    if (auto* res = std::get_if<Response>(&parsed)) return std::move(*res);
    const auto& sq = std::get<SeriesQuery>(parsed);
    json::object body = api::series_json(t, name, sq.columns.empty() ? available : sq.columns, sq.max_points);
    body["partial"] = false;
    for (const auto& [key, value] : extra) body[key] = value;
    return json_response(req, http::status::ok, body);
}

/// How far a running test's record reaches: its last row's time and axial strain.
json::value reached(const engine::TriaxialSeries& s)
{
    if (s.size() == 0) return nullptr;
    return json::object{{"rows", s.size()}, {"time_s", s.time_s.back()}, {"axial_strain", s.axial_strain.back()}};
}

/// GET …/tests and …/tests/{test}/series of a job that is preparing or
/// running: read from the attempt's own files, test by test (the runner's
/// test_K.h5 when a test has finished, its last checkpoint while it runs),
/// with the campaign's readers. Marked partial, with how far each test has come.
Response live_data(const Request& req, const std::vector<std::string>& seg, const Query& q, Services& svc, const JobRecord& r)
{
    const api::JobSpec spec = stored_spec(r.spec_json);
    const std::vector<double>& pressures = spec.triaxial.confining_pressures_pa;
    const campaign::JobDir dir{attempt_output_dir(svc.config.data_dir, r.id)};
    const std::string base = "/v1/jobs/" + r.id;
    using State = campaign::TestSoFar::State;

    if (seg.size() == 4) {
        if (auto bad = q.check({})) return bad_parameter(req, bad->second, bad->first);
        json::array tests;
        for (std::size_t k = 0; k < pressures.size(); ++k) {
            const std::string name = campaign::test_group_name(pressures[k]);
            const campaign::TestSoFar so_far = campaign::read_test_so_far(dir, k, campaign::Snapshots::skip);
            json::array columns;
            for (const auto& c : campaign::series_columns(so_far.record.series))
                columns.push_back(json::object{{"name", c.name}, {"units", *c.units}});
            tests.push_back(json::object{{"name", name}, {"state", campaign::to_string(so_far.state)},
                {"partial", so_far.state != State::finished}, {"rows", so_far.record.series.size()},
                {"reached", reached(so_far.record.series)},
                {"attributes", json::object{{"confining_pressure_pa", pressures[k]}}}, {"columns", std::move(columns)},
                {"snapshots", json::array()}, {"series_url", base + "/tests/" + name + "/series"}});
        }
        return json_response(req, http::status::ok, json::object{{"partial", true}, {"tests", std::move(tests)}});
    }
    std::size_t k = 0;
    while (k < pressures.size() && campaign::test_group_name(pressures[k]) != seg[4]) ++k;
    if (k == pressures.size()) return not_found(req, "the job has no test '" + seg[4] + "'");
    const campaign::TestSoFar so_far = campaign::read_test_so_far(dir, k, campaign::Snapshots::skip);
    std::vector<api::SeriesColumn> all = campaign::series_columns(so_far.record.series);
    std::vector<std::string> names;
    for (const auto& c : all) names.push_back(c.name);
    auto parsed = series_query(req, seg[4], names, q);
    if (auto* res = std::get_if<Response>(&parsed)) return std::move(*res);
    const auto& sq = std::get<SeriesQuery>(parsed);
    std::vector<api::SeriesColumn> chosen;
    for (const auto& name : sq.columns)
        for (auto& c : all)
            if (c.name == name) chosen.push_back(std::move(c));
    json::object body = api::series_json(seg[4], sq.columns.empty() ? all : chosen, sq.max_points);
    body["partial"] = so_far.state != State::finished;
    body["state"] = campaign::to_string(so_far.state);
    body["reached"] = reached(so_far.record.series);
    return json_response(req, http::status::ok, body);
}

/// GET …/snapshots/{k}/wire_autocorrelation, with the job's segment length.
Response wire_autocorrelation(const Request& req, const io::Group& snap, const std::string& where, const std::string& spec_json)
{
    constexpr std::string_view strain_name = engine::result_name(engine::ResultPlace::snapshot, "wire_segment_strain");
    if (!snap.exists(strain_name)) return not_found(req, where + " has no wire");
    const std::vector<double> strain = snap.open_dataset(strain_name).read_doubles();
    return json_response(
        req, http::status::ok, api::wire_autocorrelation_json(strain, stored_spec(spec_json).specimen.wire.segment_length_m));
}

/// GET of a snapshot group (`array` null) or of one of its arrays or its wire
/// autocorrelation; `index` null for the free-standing test's peak snapshot.
Response snapshot(const Request& req, const io::Group& snap, const std::string& test, std::optional<std::size_t> index,
    const std::string& where, const std::string& url, const std::string* array, const std::string& spec_json)
{
    if (!array)
        return json_response(req, http::status::ok,
            json::object{{"test", test}, {"index", index ? json::value(*index) : json::value(nullptr)},
                {"attributes", api::attributes_of(snap)}, {"arrays", api::arrays_of(snap, url)},
                {"wire_autocorrelation_url", url + "/wire_autocorrelation"}});
    if (*array == "wire_autocorrelation") return wire_autocorrelation(req, snap, where, spec_json);
    return array_response(req, snap, *array, where);
}

/// The free-standing test's routes on a group that holds it (result.h5's, or
/// the runner's tests/free_standing.h5 of a running job: the same layout):
/// …/free_standing, …/free_standing/series, …/free_standing/snapshots/{k}[/…],
/// …/free_standing/peak_snapshot[/…]; seg[4…] past "free_standing".
/// `extra`: fields added to the test's and its series' replies (a running job's state).
Response free_standing_routes(const Request& req, const std::vector<std::string>& seg, const Query& q, const io::Group& g,
    const std::string& base, const std::string& spec_json, const json::object& extra = {})
{
    const std::string name(api::free_standing_group);
    const bool is_series = seg.size() == 5 && seg[4] == "series";
    if (!is_series)
        if (auto bad = q.check({})) return bad_parameter(req, bad->second, bad->first);
    if (seg.size() == 4) {
        json::object body = api::free_standing_json(g, base, stored_spec(spec_json).specimen.wire.segment_length_m);
        body["partial"] = false;
        for (const auto& [key, value] : extra) body[key] = value;
        return json_response(req, http::status::ok, body);
    }
    if (is_series) return series(req, g, name, api::free_standing_series_columns(g), q, extra);
    const std::string url_base = base + "/" + name;
    if (seg[4] == api::free_standing_peak_snapshot && seg.size() <= 6) {
        const std::string peak(api::free_standing_peak_snapshot);
        if (!g.exists(peak)) return not_found(req, "the free-standing test has no peak snapshot (no compression)");
        return snapshot(req, g.open_group(peak), name, std::nullopt, "the free-standing test's peak snapshot",
            url_base + "/" + peak, seg.size() == 5 ? nullptr : &seg[5], spec_json);
    }
    if (seg[4] != "snapshots" || seg.size() < 6 || seg.size() > 7) return not_found(req, "no such route");
    const std::vector<std::size_t> ks = api::snapshot_indices(g);
    std::size_t k = 0;
    auto [p, ec] = std::from_chars(seg[5].data(), seg[5].data() + seg[5].size(), k);
    if (seg[5].empty() || ec != std::errc() || p != seg[5].data() + seg[5].size() || std::find(ks.begin(), ks.end(), k) == ks.end())
        return not_found(req, "the free-standing test has no snapshot '" + seg[5] + "'");
    const io::Group snap = g.open_group(api::snapshot_path(k));
    return snapshot(req, snap, name, k, "snapshot " + std::to_string(k) + " of the free-standing test",
        url_base + "/snapshots/" + std::to_string(k), seg.size() == 6 ? nullptr : &seg[6], spec_json);
}

/// How far a running record's series in `g` reaches (as `reached`): its last
/// row's time and axial strain; null before its first row.
json::value reached_in(const io::Group& g)
{
    using engine::series_column;
    const std::vector<double> t = g.open_dataset(series_column("time_s").name).read_doubles();
    if (t.empty()) return nullptr;
    return json::object{{"rows", t.size()}, {"time_s", t.back()},
        {"axial_strain", g.open_dataset(series_column("axial_strain").name).read_doubles().back()}};
}

/// …/free_standing and …/free_standing/series of a job that prepares or
/// runs: from the runner's tests/free_standing.h5 once the test has finished
/// (the same reply as after the job, but marked with its state); while it
/// runs, from its last checkpoint (tests/free_standing.checkpoint.h5: the
/// record so far, its readings as far as they are read, marked partial,
/// running, and with how far it reached); before, its state (waiting: not
/// begun; running: its stage holds its lock, no checkpoint yet) and no rows.
/// 409 for its snapshots until the job has succeeded.
Response live_free_standing(const Request& req, const std::vector<std::string>& seg, const Query& q, Services& svc, const JobRecord& r)
{
    const campaign::JobDir dir{attempt_output_dir(svc.config.data_dir, r.id)};
    const std::string base = "/v1/jobs/" + r.id;
    const std::string name(api::free_standing_group);
    std::error_code ec;
    const auto finished = [&]() -> std::optional<Response> {
        if (!std::filesystem::exists(dir.free_standing(), ec)) return std::nullopt;
        // Written whole by a rename: once it is there, it reads.
        const io::File f = io::File::open_read_only(dir.free_standing());
        return free_standing_routes(req, seg, q, f.root().open_group(name), base, r.spec_json, json::object{{"state", "finished"}});
    };
    if (auto done = finished()) return std::move(*done);
    if (std::filesystem::exists(dir.free_standing_checkpoint(), ec)) {
        try {
            // The record so far; the World beside it is not read.
            const io::File f = io::File::open_read_only(dir.free_standing_checkpoint());
            const io::Group g = f.root().open_group(engine::snapshot_host_group).open_group("result");
            return free_standing_routes(req, seg, q, g, base, r.spec_json,
                json::object{{"state", "running"}, {"partial", true}, {"reached", reached_in(g)}});
        } catch (const io::Hdf5Error&) {
            // Replaced by the next checkpoint or removed as the test ended
            // while it was read: the finished file, or a real error.
            if (std::filesystem::exists(dir.free_standing_checkpoint(), ec)) throw;
        }
        if (auto done = finished()) return std::move(*done);
    }
    const bool running = std::filesystem::exists(dir.free_standing_lock(), ec);
    const char* state = running ? "running" : "waiting";
    if (seg.size() == 4) {
        if (auto bad = q.check({})) return bad_parameter(req, bad->second, bad->first);
        return json_response(req, http::status::ok,
            json::object{{"name", name}, {"state", state}, {"partial", true}, {"rows", 0}, {"attributes", json::object()},
                {"columns", json::array()}, {"profiles", nullptr}, {"wire_at_peak", nullptr}, {"snapshots", json::array()},
                {"peak_snapshot", nullptr}, {"series_url", base + "/" + name + "/series"}});
    }
    // No rows yet, but the columns a free-standing series has (a test's, less
    // the volumetric strain it leaves empty), so that a query naming them is
    // answered as it will be once rows come.
    std::vector<api::SeriesColumn> all = campaign::series_columns(engine::TriaxialSeries{});
    std::erase_if(all, [](const api::SeriesColumn& c) { return c.name == "volumetric_strain"; });
    std::vector<std::string> names;
    for (const auto& c : all) names.push_back(c.name);
    auto parsed = series_query(req, name, names, q);
    if (auto* res = std::get_if<Response>(&parsed)) return std::move(*res);
    const SeriesQuery& sq = std::get<SeriesQuery>(parsed);
    std::vector<api::SeriesColumn> chosen;
    for (const auto& n : sq.columns)
        for (auto& c : all)
            if (c.name == n) chosen.push_back(std::move(c));
    json::object body = api::series_json(name, sq.columns.empty() ? all : chosen, sq.max_points);
    body["partial"] = true;
    body["state"] = state;
    body["reached"] = nullptr;
    return json_response(req, http::status::ok, body);
}

/// result.xdmf: small XML, read whole.
Response xdmf(const Request& req, const std::filesystem::path& data_dir, const std::string& id)
{
    const int fd = open_job_file(data_dir, id, "result.xdmf").release();
    if (fd < 0) return not_found(req, "job " + id + " has no result.xdmf (finished before the server kept it)");
    std::string text;
    char buf[65536];
    ssize_t got;
    while ((got = ::read(fd, buf, sizeof buf)) > 0 || (got < 0 && errno == EINTR))
        if (got > 0) text.append(buf, static_cast<std::size_t>(got));
    ::close(fd);
    if (got < 0) throw std::runtime_error("cannot read result.xdmf of job " + id);
    auto res = text_response(req, http::status::ok, std::move(text), "application/xml");
    res.set(http::field::content_disposition, "attachment; filename=\"result.xdmf\"");
    return res;
}

} // namespace

bool is_result_data_route(std::string_view fourth_segment) noexcept
{
    return fourth_segment == "tests" || fourth_segment == "specimen" || fourth_segment == "result.xdmf"
        || fourth_segment == "report.html" || fourth_segment == api::free_standing_group;
}

Response handle_result_data(const Request& req, const std::vector<std::string>& seg, const QueryParams& params, Services& svc)
{
    const std::string& id = seg[2];
    const Query q{params};
    const auto r = svc.store.get(id);
    if (!r) return not_found(req, "no job " + id);
    const bool is_tests = seg[3] == "tests" && (seg.size() == 4 || (seg.size() == 6 && seg[5] == "series"));
    const bool is_free_standing = seg[3] == api::free_standing_group;
    if (is_free_standing && !stored_spec(r->spec_json).free_standing.enabled)
        return not_found(req, "job " + id + " has no free-standing test (free_standing.enabled is false)");
    const bool is_free_standing_live = is_free_standing && (seg.size() == 4 || (seg.size() == 5 && seg[4] == "series"));
    if (r->state != JobState::succeeded) {
        if (is_tests && (r->state == JobState::preparing || r->state == JobState::running)) return live_data(req, seg, q, svc, *r);
        if (is_free_standing_live && (r->state == JobState::preparing || r->state == JobState::running))
            return live_free_standing(req, seg, q, svc, *r);
        return error_response(req, http::status::conflict, "not_succeeded",
            "job " + id + " is " + std::string(to_string(r->state))
                + "; results exist only once it has succeeded (the tests and their series also while it runs)", "id");
    }
    const std::filesystem::path dir = svc.config.data_dir / "jobs" / id;
    const std::string base = "/v1/jobs/" + id;

    // Only the series routes take query parameters.
    const bool is_series = (seg.size() == 6 && seg[3] == "tests" && seg[5] == "series")
                        || (seg.size() == 5 && is_free_standing && seg[4] == "series");
    if (!is_series)
        if (auto bad = q.check({})) return bad_parameter(req, bad->second, bad->first);

    if (seg[3] == "result.xdmf") {
        if (seg.size() != 4) return not_found(req, "no such route");
        return xdmf(req, svc.config.data_dir, id);
    }

    // HDF5 opens by name and follows links: refuse anything but a regular file
    // reached without a symlink (job_files.hpp), the job's folder included.
    const auto h5 = dir / "result.h5";
    if (!open_job_file(svc.config.data_dir, id, "result.h5"))
        return error_response(req, http::status::internal_server_error, "internal",
            "result of job " + id + " is missing or not a regular file");
    if (seg[3] == "report.html") {
        if (seg.size() != 4) return not_found(req, "no such route");
        if (svc.config.web_dir.empty()) return not_found(req, "this server has no web page to draw the report with (--web-dir)");
        if (!open_job_file(svc.config.data_dir, id, "summary.json"))
            return error_response(req, http::status::internal_server_error, "internal",
                "summary of job " + id + " is missing or not a regular file");
        auto res = text_response(req, http::status::ok,
            api::report_html(dir / "summary.json", h5, svc.config.web_dir, "job " + id), "text/html; charset=utf-8");
        // A file to save and open offline; shown here anyway, it runs in an opaque origin.
        res.set(http::field::content_disposition, "attachment; filename=\"report.html\"");
        res.set("Content-Security-Policy", "sandbox allow-scripts");
        return res;
    }
    const io::File file = io::File::open_read_only(h5);
    const io::Group root = file.root();

    if (is_free_standing) {
        if (!root.exists(std::string(api::free_standing_group)))
            return error_response(req, http::status::internal_server_error, "internal",
                "result of job " + id + " has no free-standing test though its job asked for one");
        return free_standing_routes(req, seg, q, root.open_group(std::string(api::free_standing_group)), base, r->spec_json);
    }

    if (seg[3] == "specimen") {
        constexpr std::string_view specimen = engine::result_name(engine::ResultPlace::root, "specimen");
        if (!root.exists(specimen)) return not_found(req, "the result holds no specimen");
        const io::Group s = root.open_group(specimen);
        if (seg.size() == 4)
            return json_response(req, http::status::ok,
                json::object{{"attributes", api::attributes_of(s)}, {"arrays", api::arrays_of(s, base + "/specimen")}});
        if (seg.size() == 5) return array_response(req, s, seg[4], "the specimen");
        return not_found(req, "no such route");
    }

    // tests
    if (seg.size() == 4) {
        json::object body = api::tests_json(root, base);
        body["partial"] = false;
        return json_response(req, http::status::ok, body);
    }
    const std::vector<std::string> names = api::test_names(root);
    const std::string& test = seg[4];
    if (std::find(names.begin(), names.end(), test) == names.end())
        return not_found(req, "the result has no test '" + test + "'");
    const io::Group t = root.open_group(api::test_path(test));
    if (seg.size() == 6 && seg[5] == "series") return series(req, t, test, api::series_columns(t), q);
    if (seg.size() < 7 || seg.size() > 8 || seg[5] != "snapshots") return not_found(req, "no such route");
    const std::vector<std::size_t> ks = api::snapshot_indices(t);
    std::size_t k = 0;
    auto [p, ec] = std::from_chars(seg[6].data(), seg[6].data() + seg[6].size(), k);
    if (seg[6].empty() || ec != std::errc() || p != seg[6].data() + seg[6].size() || std::find(ks.begin(), ks.end(), k) == ks.end())
        return not_found(req, "test " + test + " has no snapshot '" + seg[6] + "'");
    const io::Group snap = t.open_group(api::snapshot_path(k));
    const std::string where = "snapshot " + std::to_string(k) + " of " + test;
    const std::string url = base + "/tests/" + test + "/snapshots/" + std::to_string(k);
    return snapshot(req, snap, test, k, where, url, seg.size() == 7 ? nullptr : &seg[7], r->spec_json);
}

} // namespace wiredem::server

namespace wiredem::server {

const boost::json::object& result_data_openapi_paths()
{
    // Merged into the OpenAPI document by handlers/meta.cpp.
    static const json::object paths = json::parse(R"json({
    "/v1/jobs/{id}/tests": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "The tests of a job by ascending confining pressure: attributes (peak, yield, quasi-static figures), time-series columns with units, snapshots; while the job prepares or runs, how far each test has come (partial)",
        "responses": {
          "200": {"description": "The tests", "content": {"application/json": {"schema": {"type": "object", "required": ["partial", "tests"],
            "properties": {"partial": {"type": "boolean", "description": "true while the job prepares or runs: read from the runner's per-test files"},
              "tests": {"type": "array", "items": {"type": "object", "required": ["name", "rows", "attributes", "columns", "snapshots"],
              "properties": {"name": {"type": "string", "example": "sigma3_20000"}, "rows": {"type": "integer"},
                "state": {"type": "string", "enum": ["waiting", "running", "finished"], "description": "while the job runs only"},
                "partial": {"type": "boolean"}, "reached": {"$ref": "#/components/schemas/Reached"},
                "attributes": {"type": "object"}, "series_url": {"type": "string"},
                "columns": {"type": "array", "items": {"type": "object", "properties": {"name": {"type": "string"}, "units": {"type": "string", "nullable": true}}}},
                "snapshots": {"type": "array", "items": {"type": "object", "properties": {"index": {"type": "integer"}, "url": {"type": "string"},
                  "requested_axial_strain": {"type": "number"}, "axial_strain": {"type": "number"}, "time_s": {"type": "number"}}}}}}}}}}}},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/tests/{test}/series": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}, {"$ref": "#/components/parameters/Test"},
        {"name": "max_points", "in": "query", "description": "at most this many rows, evenly spaced, the first and last among them (default: every row)",
         "schema": {"type": "integer", "minimum": 2, "maximum": 1000000}},
        {"name": "columns", "in": "query", "description": "comma-separated column names (default: every column)", "schema": {"type": "string", "example": "axial_strain,deviatoric_stress_pa"}}],
      "get": {
        "summary": "A test's time series as stored in result.h5, optionally thinned; while the job prepares or runs, as far as the test has recorded it (its last checkpoint, partial)",
        "responses": {
          "200": {"description": "Columns of equal length", "content": {"application/json": {"schema": {"type": "object",
            "required": ["test", "rows", "returned_rows", "row_index", "units", "columns", "partial"],
            "properties": {"test": {"type": "string"}, "rows": {"type": "integer", "description": "rows stored"},
              "partial": {"type": "boolean", "description": "true: the test has not finished, more rows will come"},
              "state": {"type": "string", "enum": ["waiting", "running", "finished"], "description": "while the job runs only"},
              "reached": {"$ref": "#/components/schemas/Reached"},
              "returned_rows": {"type": "integer"}, "row_index": {"type": "array", "items": {"type": "integer"}},
              "units": {"type": "object", "additionalProperties": {"type": "string"}},
              "columns": {"type": "object", "additionalProperties": {"type": "array", "items": {"type": "number", "nullable": true}}}}}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/specimen": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "The prepared specimen: its attributes and its arrays (shape, type, url); with clumps (specimen.grain_shape) every sphere of a clump is a grain of grain_position_m and grain_radius_m, and grain_clump (int32, -1 for a free grain) names its clump, for every snapshot too (the same spheres in the same order)",
        "responses": {
          "200": {"description": "Figures and arrays", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/ArrayGroup"}}}},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/specimen/{array}": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}, {"$ref": "#/components/parameters/Array"}],
      "get": {
        "summary": "One array of the specimen, binary",
        "responses": {
          "200": {"$ref": "#/components/responses/BinaryArray"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/tests/{test}/snapshots/{k}": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}, {"$ref": "#/components/parameters/Test"}, {"$ref": "#/components/parameters/Snapshot"}],
      "get": {
        "summary": "A snapshot of a test: its attributes (requested and measured axial strain, time) and arrays (positions, radii, wire strain, membrane triangles, contacts; with clumps a position and radius per sphere, their clumps in /specimen/grain_clump)",
        "responses": {
          "200": {"description": "Figures and arrays", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/ArrayGroup"}}}},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/tests/{test}/snapshots/{k}/{array}": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}, {"$ref": "#/components/parameters/Test"}, {"$ref": "#/components/parameters/Snapshot"},
        {"$ref": "#/components/parameters/Array"}],
      "get": {
        "summary": "One array of a snapshot, binary",
        "responses": {
          "200": {"$ref": "#/components/responses/BinaryArray"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/tests/{test}/snapshots/{k}/wire_autocorrelation": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}, {"$ref": "#/components/parameters/Test"}, {"$ref": "#/components/parameters/Snapshot"}],
      "get": {
        "summary": "Autocorrelation of the snapshot's wire segment strains (the function summary.wire.autocorrelation_lag_m and autocorrelation_prominent_lag_m come from), with its first maximum and its first prominent maximum",
        "responses": {
          "200": {"description": "R(k) against lag k * segment length; first_maximum_lag_m: the first local maximum after lag 0; prominent_maximum_lag_m: the first one whose prominence exceeds the white-noise 95 % band 1.96/sqrt(segments - k); error says why there is none", "content": {"application/json": {"schema": {"type": "object",
            "required": ["segment_length_m", "segments", "lag_m", "coefficients", "first_maximum_lag_m", "prominent_maximum_lag_m", "error"],
            "properties": {"segment_length_m": {"type": "number"}, "segments": {"type": "integer"},
              "lag_m": {"type": "array", "items": {"type": "number"}}, "coefficients": {"type": "array", "items": {"type": "number"}},
              "first_maximum_lag_m": {"type": "number", "nullable": true}, "prominent_maximum_lag_m": {"type": "number", "nullable": true},
              "error": {"type": "string", "nullable": true}}}}}},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/free_standing": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "The free-standing test (a job with free_standing.enabled; docs/model.md, \"The free-standing test\"): its readings as stored (settling, dead load, compression: attributes), its time-series columns, the radius profiles (radius against height before the removal, settled, at the largest sigma1, at the end), the wire's segment strain and tension along its length at the largest sigma1, its snapshots; while the job prepares or runs, its state and its rows so far (from the runner's last checkpoint: partial, with how far it reached)",
        "responses": {
          "200": {"description": "The test", "content": {"application/json": {"schema": {"type": "object",
            "required": ["name", "partial", "rows", "attributes", "columns", "profiles", "wire_at_peak", "snapshots", "peak_snapshot", "series_url"],
            "properties": {"name": {"type": "string", "enum": ["free_standing"]}, "rows": {"type": "integer"},
              "partial": {"type": "boolean", "description": "true while the job prepares or runs and the test has not finished"},
              "state": {"type": "string", "enum": ["waiting", "running", "finished"], "description": "while the job runs only"},
              "attributes": {"type": "object", "description": "result.h5 /free_standing's attributes (docs/results.md)"},
              "columns": {"type": "array", "items": {"type": "object", "properties": {"name": {"type": "string"}, "units": {"type": "string", "nullable": true}}}},
              "profiles": {"type": "object", "nullable": true, "description": "profile_before, profile_settled, profile_at_peak, profile_at_end (null: not reached)",
                "additionalProperties": {"$ref": "#/components/schemas/RadiusProfile"}},
              "wire_at_peak": {"type": "object", "nullable": true, "description": "per segment at the largest sigma1 (null without a compression)",
                "required": ["segment_length_m", "distance_m", "strain", "tension_n"],
                "properties": {"segment_length_m": {"type": "number"}, "distance_m": {"type": "array", "items": {"type": "number"}, "description": "(k + 1/2) l_w of segment k"},
                  "strain": {"type": "array", "items": {"type": "number", "nullable": true}}, "tension_n": {"type": "array", "items": {"type": "number", "nullable": true}}}},
              "snapshots": {"type": "array", "items": {"type": "object", "properties": {"index": {"type": "integer"}, "url": {"type": "string"},
                "requested_axial_strain": {"type": "number"}, "axial_strain": {"type": "number"}, "time_s": {"type": "number"}}}},
              "peak_snapshot": {"type": "object", "nullable": true, "description": "the snapshot at the largest sigma1 (force network there): attributes and url"},
              "series_url": {"type": "string"}}}}}},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/free_standing/series": {
      "parameters": [{"$ref": "#/components/parameters/JobId"},
        {"name": "max_points", "in": "query", "description": "at most this many rows, evenly spaced, the first and last among them (default: every row)",
         "schema": {"type": "integer", "minimum": 2, "maximum": 1000000}},
        {"name": "columns", "in": "query", "description": "comma-separated column names (default: every column)", "schema": {"type": "string", "example": "axial_strain,sigma1_pa,phase"}}],
      "get": {
        "summary": "The free-standing test's time series (phase 0 removal, 1 settling, 2 dead_load, 3 loading; sigma1_pa = F_top / (pi r0^2)), as a test's series route gives it; empty (partial) until the test has finished",
        "responses": {
          "200": {"description": "Columns of equal length, as /tests/{test}/series", "content": {"application/json": {"schema": {"type": "object",
            "required": ["test", "rows", "returned_rows", "row_index", "units", "columns", "partial"],
            "properties": {"test": {"type": "string"}, "rows": {"type": "integer"}, "partial": {"type": "boolean"},
              "state": {"type": "string", "enum": ["waiting", "running", "finished"]}, "reached": {"$ref": "#/components/schemas/Reached"},
              "returned_rows": {"type": "integer"}, "row_index": {"type": "array", "items": {"type": "integer"}},
              "units": {"type": "object", "additionalProperties": {"type": "string"}},
              "columns": {"type": "object", "additionalProperties": {"type": "array", "items": {"type": "number", "nullable": true}}}}}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/free_standing/snapshots/{k}": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}, {"$ref": "#/components/parameters/Snapshot"}],
      "get": {
        "summary": "A snapshot of the free-standing test's compression, laid out as a test's",
        "responses": {
          "200": {"description": "Figures and arrays", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/ArrayGroup"}}}},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/free_standing/snapshots/{k}/{array}": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}, {"$ref": "#/components/parameters/Snapshot"}, {"$ref": "#/components/parameters/Array"}],
      "get": {
        "summary": "One array of a free-standing snapshot, binary (wire_autocorrelation: JSON, as a test's)",
        "responses": {
          "200": {"$ref": "#/components/responses/BinaryArray"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/free_standing/peak_snapshot": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "The free-standing test's snapshot at the largest sigma1 (the force network at the peak)",
        "responses": {
          "200": {"description": "Figures and arrays", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/ArrayGroup"}}}},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/free_standing/peak_snapshot/{array}": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}, {"$ref": "#/components/parameters/Array"}],
      "get": {
        "summary": "One array of the peak snapshot, binary",
        "responses": {
          "200": {"$ref": "#/components/responses/BinaryArray"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/report.html": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "The offline report: one HTML file with the job page's results (summary, curves, Mohr circles, wire) that opens without a server (what wiredem report OUT/ writes)",
        "responses": {
          "200": {"description": "HTML, as an attachment", "content": {"text/html": {"schema": {"type": "string"}}}},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/result.xdmf": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "The XDMF sidecar that describes result.h5 to ParaView (save both in one folder)",
        "responses": {
          "200": {"description": "XDMF 3 XML", "content": {"application/xml": {"schema": {"type": "string"}}}},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    }
    })json").as_object();
    return paths;
}

const boost::json::object& result_data_openapi_components()
{
    static const json::object components = json::parse(R"json({
    "parameters": {
      "Test": {"name": "test", "in": "path", "required": true, "description": "a test's name from /tests", "schema": {"type": "string", "example": "sigma3_20000"}},
      "Snapshot": {"name": "k", "in": "path", "required": true, "description": "a snapshot's index from /tests", "schema": {"type": "integer", "minimum": 0}},
      "Array": {"name": "array", "in": "path", "required": true, "description": "an array's name from the group's arrays", "schema": {"type": "string", "example": "grain_position_m"}}
    },
    "responses": {
      "BinaryArray": {"description": "Row-major little-endian values; X-Wiredem-Shape gives the dimensions (e.g. 150,3), X-Wiredem-Dtype float32 or int32 (indices)",
        "headers": {"X-Wiredem-Shape": {"schema": {"type": "string"}}, "X-Wiredem-Dtype": {"schema": {"type": "string", "enum": ["float32", "int32"]}}},
        "content": {"application/octet-stream": {"schema": {"type": "string", "format": "binary"}}}}
    },
    "schemas": {
      "RadiusProfile": {"type": "object", "nullable": true, "description": "the standing grains' equivalent radius in horizontal slices of a mean grain diameter (engine::radius_profile)",
        "required": ["height_m", "radius_m", "grains"], "properties": {"height_m": {"type": "array", "items": {"type": "number"}},
          "radius_m": {"type": "array", "items": {"type": "number"}}, "grains": {"type": "array", "items": {"type": "integer"}}}},
      "Reached": {"type": "object", "nullable": true, "description": "how far a test of a running job has come: its last recorded row (null before the first; while the job runs only)",
        "properties": {"rows": {"type": "integer"}, "time_s": {"type": "number"}, "axial_strain": {"type": "number"}}},
      "ArrayGroup": {"type": "object", "required": ["attributes", "arrays"], "properties": {
        "attributes": {"type": "object"},
        "arrays": {"type": "array", "items": {"type": "object", "required": ["name", "shape", "dtype", "url"], "properties": {
          "name": {"type": "string"}, "shape": {"type": "array", "items": {"type": "integer"}},
          "dtype": {"type": "string", "enum": ["float32", "int32"]}, "units": {"type": "string", "nullable": true}, "url": {"type": "string"}}}}}}
    }
    })json").as_object();
    return components;
}

} // namespace wiredem::server
