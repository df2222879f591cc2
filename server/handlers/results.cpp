// Result data routes: result.h5 read through engine/io/hdf5 (read-only), as
// JSON for figures and series, as raw little-endian arrays for the 3D view.
#include "results.hpp"

#include "analysis/autocorrelation.hpp"
#include "api/job_spec.hpp"
#include "api/json_text.hpp"
#include "io/hdf5.hpp"

#include <boost/json.hpp>
#include <hdf5.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace wiredem::server {
namespace json = boost::json;
namespace io = engine::io;

namespace {

static_assert(std::endian::native == std::endian::little, "the binary arrays are sent in the host's byte order");

/// Largest max_points: more than any plot draws, fewer than a server should
/// serialise per request by mistake.
constexpr std::size_t max_points_limit = 1'000'000;

json::value number(double x) { return std::isfinite(x) ? json::value(x) : json::value(nullptr); }

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

/// Every numeric or string attribute of an object, as JSON.
json::object attributes_of(const io::Object& o)
{
    json::object out;
    const hid_t id = static_cast<hid_t>(o.id());
    H5O_info_t info{};
    if (H5Oget_info2(id, &info, H5O_INFO_NUM_ATTRS) < 0) return out;
    for (hsize_t i = 0; i < info.num_attrs; ++i) {
        const ssize_t len = H5Aget_name_by_idx(id, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
        if (len <= 0) continue;
        std::string name(static_cast<std::size_t>(len), '\0');
        H5Aget_name_by_idx(id, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size() + 1, H5P_DEFAULT);
        const hid_t attr = H5Aopen(id, name.c_str(), H5P_DEFAULT);
        if (attr < 0) continue;
        const hid_t type = H5Aget_type(attr);
        const H5T_class_t cls = H5Tget_class(type);
        H5Tclose(type);
        H5Aclose(attr);
        if (cls == H5T_STRING) out[name] = o.read_string_attribute(name);
        else if (cls == H5T_INTEGER) out[name] = o.read_int_attribute(name);
        else if (cls == H5T_FLOAT) out[name] = number(o.read_double_attribute(name));
    }
    return out;
}

/// The tests of a result file by ascending confining pressure (the group
/// names sort as text: sigma3_100000 before sigma3_20000).
std::vector<std::string> test_names(const io::Group& root)
{
    std::vector<std::pair<double, std::string>> found;
    if (!root.exists("tests")) return {};
    const io::Group all = root.open_group("tests");
    for (const std::string& name : all.child_names()) {
        const io::Group t = all.open_group(name);
        found.emplace_back(t.has_attribute("confining_pressure_pa") ? t.read_double_attribute("confining_pressure_pa") : 0.0, name);
    }
    std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> names;
    for (auto& f : found) names.push_back(std::move(f.second));
    return names;
}

constexpr std::string_view snapshot_prefix = "snapshot_";

/// Snapshot indices of a test, ascending.
std::vector<std::size_t> snapshot_indices(const io::Group& test)
{
    std::vector<std::size_t> out;
    if (!test.exists("snapshots")) return out;
    for (const std::string& name : test.open_group("snapshots").child_names()) {
        if (name.size() <= snapshot_prefix.size() || name.compare(0, snapshot_prefix.size(), snapshot_prefix) != 0) continue;
        std::size_t k = 0;
        const char* first = name.data() + snapshot_prefix.size();
        const char* last = name.data() + name.size();
        auto [p, ec] = std::from_chars(first, last, k);
        if (ec == std::errc() && p == last) out.push_back(k);
    }
    std::sort(out.begin(), out.end());
    return out;
}

bool is_numeric_dataset(const io::Dataset& d, H5T_class_t* cls_out = nullptr)
{
    const hid_t type = H5Dget_type(static_cast<hid_t>(d.id()));
    const H5T_class_t cls = H5Tget_class(type);
    H5Tclose(type);
    if (cls_out) *cls_out = cls;
    return cls == H5T_INTEGER || cls == H5T_FLOAT;
}

/// The time-series columns of a test: its 1-D numeric datasets.
std::vector<std::string> series_columns(const io::Group& test)
{
    std::vector<std::string> out;
    for (const std::string& name : test.child_names()) {
        H5O_info_t info{};
        if (H5Oget_info_by_name2(static_cast<hid_t>(test.id()), name.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0
            || info.type != H5O_TYPE_DATASET)
            continue;
        const io::Dataset d = test.open_dataset(name);
        if (d.shape().size() == 1 && is_numeric_dataset(d)) out.push_back(name);
    }
    return out;
}

/// The arrays of a group (specimen or snapshot): its numeric datasets, with shape and type.
json::array arrays_of(const io::Group& g, const std::string& url_base)
{
    json::array out;
    for (const std::string& name : g.child_names()) {
        H5O_info_t info{};
        if (H5Oget_info_by_name2(static_cast<hid_t>(g.id()), name.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0
            || info.type != H5O_TYPE_DATASET)
            continue;
        const io::Dataset d = g.open_dataset(name);
        H5T_class_t cls{};
        if (!is_numeric_dataset(d, &cls)) continue;
        json::array shape;
        for (std::size_t n : d.shape()) shape.push_back(n);
        json::object a{{"name", name}, {"shape", std::move(shape)}, {"dtype", cls == H5T_INTEGER ? "int32" : "float32"},
            {"units", d.has_attribute("units") ? json::value(d.read_string_attribute("units")) : json::value(nullptr)},
            {"url", url_base + "/" + name}};
        out.push_back(std::move(a));
    }
    return out;
}

std::string shape_text(const std::vector<std::size_t>& shape)
{
    std::string s;
    for (std::size_t n : shape) s += (s.empty() ? "" : ",") + std::to_string(n);
    return s;
}

/// One dataset of `g` as raw little-endian float32 or int32 rows.
Response array_response(const Request& req, const io::Group& g, const std::string& name, const std::string& where)
{
    if (name.empty() || !g.exists(name)) return not_found(req, where + " has no array '" + name + "'");
    H5O_info_t info{};
    if (H5Oget_info_by_name2(static_cast<hid_t>(g.id()), name.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0
        || info.type != H5O_TYPE_DATASET)
        return not_found(req, where + " has no array '" + name + "'");
    const io::Dataset d = g.open_dataset(name);
    H5T_class_t cls{};
    if (!is_numeric_dataset(d, &cls)) return not_found(req, where + " has no numeric array '" + name + "'");
    std::string body;
    const char* dtype;
    if (cls == H5T_INTEGER) {
        const std::vector<std::int64_t> v = d.read_int64s();
        std::vector<std::int32_t> narrow(v.size());
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (v[i] < std::numeric_limits<std::int32_t>::min() || v[i] > std::numeric_limits<std::int32_t>::max())
                throw std::runtime_error(where + "/" + name + ": value " + std::to_string(v[i]) + " does not fit int32");
            narrow[i] = static_cast<std::int32_t>(v[i]);
        }
        body.assign(reinterpret_cast<const char*>(narrow.data()), narrow.size() * sizeof(std::int32_t));
        dtype = "int32";
    } else {
        const std::vector<double> v = d.read_doubles();
        std::vector<float> narrow(v.begin(), v.end());
        body.assign(reinterpret_cast<const char*>(narrow.data()), narrow.size() * sizeof(float));
        dtype = "float32";
    }
    auto res = text_response(req, http::status::ok, std::move(body), "application/octet-stream");
    res.set("X-Wiredem-Shape", shape_text(d.shape()));
    res.set("X-Wiredem-Dtype", dtype);
    return res;
}

std::vector<double> column(const io::Group& test, const std::string& name) { return test.open_dataset(name).read_doubles(); }

/// GET …/tests: every test with its attributes, columns and snapshots.
Response list_tests(const Request& req, const io::Group& root, const std::string& base)
{
    json::array tests;
    for (const std::string& name : test_names(root)) {
        const io::Group t = root.open_group("tests/" + name);
        json::array columns;
        std::size_t rows = 0;
        for (const std::string& c : series_columns(t)) {
            const io::Dataset d = t.open_dataset(c);
            rows = std::max(rows, d.shape()[0]);
            columns.push_back(json::object{{"name", c},
                {"units", d.has_attribute("units") ? json::value(d.read_string_attribute("units")) : json::value(nullptr)}});
        }
        json::array snaps;
        for (std::size_t k : snapshot_indices(t)) {
            const io::Group s = t.open_group("snapshots/" + std::string(snapshot_prefix) + std::to_string(k));
            json::object o = attributes_of(s);
            o["index"] = k;
            o["url"] = base + "/tests/" + name + "/snapshots/" + std::to_string(k);
            snaps.push_back(std::move(o));
        }
        tests.push_back(json::object{{"name", name}, {"rows", rows}, {"attributes", attributes_of(t)},
            {"columns", std::move(columns)}, {"snapshots", std::move(snaps)},
            {"series_url", base + "/tests/" + name + "/series"}});
    }
    return json_response(req, http::status::ok, json::object{{"tests", std::move(tests)}});
}

/// GET …/tests/{test}/series?max_points=N&columns=a,b
Response series(const Request& req, const io::Group& t, const std::string& name, const Query& q)
{
    if (auto bad = q.check({"max_points", "columns"})) return bad_parameter(req, bad->second, bad->first);
    const std::vector<std::string> available = series_columns(t);
    std::vector<std::string> wanted = available;
    if (auto c = q.get("columns")) {
        wanted.clear();
        std::string_view rest = *c;
        while (true) {
            const auto comma = rest.find(',');
            const std::string one(rest.substr(0, comma));
            if (std::find(available.begin(), available.end(), one) == available.end())
                return bad_parameter(req, "test " + name + " has no column '" + one + "'", "columns");
            if (std::find(wanted.begin(), wanted.end(), one) == wanted.end()) wanted.push_back(one);
            if (comma == std::string_view::npos) break;
            rest.remove_prefix(comma + 1);
        }
    }
    std::size_t max_points = max_points_limit;
    if (auto m = q.get("max_points")) {
        std::size_t v = 0;
        auto [p, ec] = std::from_chars(m->data(), m->data() + m->size(), v);
        if (m->empty() || ec != std::errc() || p != m->data() + m->size() || v < 2 || v > max_points_limit)
            return bad_parameter(req, "max_points must be an integer in [2, " + std::to_string(max_points_limit) + "]",
                "max_points");
        max_points = v;
    }
    std::vector<std::vector<double>> data;
    std::size_t rows = 0;
    for (const auto& c : wanted) {
        data.push_back(column(t, c));
        rows = std::max(rows, data.back().size());
    }
    for (std::size_t i = 0; i < wanted.size(); ++i)
        if (data[i].size() != rows)
            throw std::runtime_error("test " + name + ": column " + wanted[i] + " has " + std::to_string(data[i].size())
                                     + " rows, others " + std::to_string(rows));
    const std::vector<std::size_t> keep = decimated_rows(rows, max_points);
    json::object cols, units;
    for (std::size_t i = 0; i < wanted.size(); ++i) {
        json::array a;
        a.reserve(keep.size());
        for (std::size_t r : keep) a.push_back(number(data[i][r]));
        cols[wanted[i]] = std::move(a);
        const io::Dataset d = t.open_dataset(wanted[i]);
        units[wanted[i]] = d.has_attribute("units") ? json::value(d.read_string_attribute("units")) : json::value(nullptr);
    }
    json::array row_index;
    for (std::size_t r : keep) row_index.push_back(r);
    return json_response(req, http::status::ok,
        json::object{{"test", name}, {"rows", rows}, {"returned_rows", keep.size()}, {"row_index", std::move(row_index)},
            {"units", std::move(units)}, {"columns", std::move(cols)}});
}

/// GET …/snapshots/{k}/wire_autocorrelation
Response wire_autocorrelation(const Request& req, const io::Group& snap, const std::string& where, const std::string& spec_json)
{
    if (!snap.exists("wire_segment_strain")) return not_found(req, where + " has no wire");
    const std::vector<double> strain = snap.open_dataset("wire_segment_strain").read_doubles();
    const auto doc = api::parse_json_text(spec_json);
    if (!doc) throw std::runtime_error("stored spec is not JSON: " + doc.error());
    const auto spec = api::parse_job_spec(doc.value());
    if (!spec) throw std::runtime_error("stored spec does not parse: " + spec.error().front().message);
    const double l_w = spec.value().specimen.wire.segment_length_m;
    json::object body{{"segment_length_m", l_w}, {"segments", strain.size()}};
    const auto ac = engine::analysis::autocorrelation(strain, l_w);
    if (!ac.ok()) {
        body["error"] = ac.error();
        body["lag_m"] = json::array();
        body["coefficients"] = json::array();
        body["first_maximum_lag_m"] = nullptr;
        return json_response(req, http::status::ok, body);
    }
    json::array lag, r;
    for (std::size_t k = 0; k < ac.value().coefficients.size(); ++k) {
        lag.push_back(static_cast<double>(k) * l_w);
        r.push_back(number(ac.value().coefficients[k]));
    }
    body["error"] = nullptr;
    body["lag_m"] = std::move(lag);
    body["coefficients"] = std::move(r);
    body["mean"] = number(ac.value().mean);
    body["variance"] = number(ac.value().variance);
    body["first_maximum_lag_m"] = ac.value().first_maximum_lag_m ? number(*ac.value().first_maximum_lag_m) : json::value(nullptr);
    return json_response(req, http::status::ok, body);
}

/// result.xdmf: small XML, read whole.
Response xdmf(const Request& req, const std::filesystem::path& dir, const std::string& id)
{
    const auto path = dir / "result.xdmf";
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
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
    return fourth_segment == "tests" || fourth_segment == "specimen" || fourth_segment == "result.xdmf";
}

std::vector<std::size_t> decimated_rows(std::size_t rows, std::size_t max_points)
{
    std::vector<std::size_t> keep;
    if (rows <= max_points) {
        keep.resize(rows);
        for (std::size_t i = 0; i < rows; ++i) keep[i] = i;
        return keep;
    }
    keep.resize(max_points);
    // Row k·(rows−1)/(max_points−1), rounded to nearest, in integers: exact at both ends.
    const std::size_t span = rows - 1, steps = max_points - 1;
    for (std::size_t k = 0; k < max_points; ++k) keep[k] = (k * span + steps / 2) / steps;
    return keep;
}

Response handle_result_data(const Request& req, const std::vector<std::string>& seg, const QueryParams& params, Services& svc)
{
    const std::string& id = seg[2];
    const Query q{params};
    const auto r = svc.store.get(id);
    if (!r) return not_found(req, "no job " + id);
    if (r->state != JobState::succeeded)
        return error_response(req, http::status::conflict, "not_succeeded",
            "job " + id + " is " + std::string(to_string(r->state)) + "; results exist only once it has succeeded", "id");
    const std::filesystem::path dir = svc.config.data_dir / "jobs" / id;
    const std::string base = "/v1/jobs/" + id;

    // Only the series route takes query parameters.
    const bool is_series = seg.size() == 6 && seg[3] == "tests" && seg[5] == "series";
    if (!is_series)
        if (auto bad = q.check({})) return bad_parameter(req, bad->second, bad->first);

    if (seg[3] == "result.xdmf") {
        if (seg.size() != 4) return not_found(req, "no such route");
        return xdmf(req, dir, id);
    }

    // HDF5 opens by name and follows links: refuse anything but a regular file
    // in the job's folder (the folder itself is the server's, named by a valid id).
    const auto h5 = dir / "result.h5";
    struct stat st{};
    if (::lstat(h5.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
        return error_response(req, http::status::internal_server_error, "internal",
            "result of job " + id + " is missing or not a regular file");
    const io::File file = io::File::open_read_only(h5);
    const io::Group root = file.root();

    if (seg[3] == "specimen") {
        if (!root.exists("specimen")) return not_found(req, "the result holds no specimen");
        const io::Group s = root.open_group("specimen");
        if (seg.size() == 4)
            return json_response(req, http::status::ok,
                json::object{{"attributes", attributes_of(s)}, {"arrays", arrays_of(s, base + "/specimen")}});
        if (seg.size() == 5) return array_response(req, s, seg[4], "the specimen");
        return not_found(req, "no such route");
    }

    // tests
    if (seg.size() == 4) return list_tests(req, root, base);
    const std::vector<std::string> names = test_names(root);
    const std::string& test = seg[4];
    if (std::find(names.begin(), names.end(), test) == names.end())
        return not_found(req, "the result has no test '" + test + "'");
    const io::Group t = root.open_group("tests/" + test);
    if (seg.size() == 6 && seg[5] == "series") return series(req, t, test, q);
    if (seg.size() < 7 || seg.size() > 8 || seg[5] != "snapshots") return not_found(req, "no such route");
    const std::vector<std::size_t> ks = snapshot_indices(t);
    std::size_t k = 0;
    auto [p, ec] = std::from_chars(seg[6].data(), seg[6].data() + seg[6].size(), k);
    if (seg[6].empty() || ec != std::errc() || p != seg[6].data() + seg[6].size() || std::find(ks.begin(), ks.end(), k) == ks.end())
        return not_found(req, "test " + test + " has no snapshot '" + seg[6] + "'");
    const io::Group snap = t.open_group("snapshots/" + std::string(snapshot_prefix) + std::to_string(k));
    const std::string where = "snapshot " + std::to_string(k) + " of " + test;
    const std::string url = base + "/tests/" + test + "/snapshots/" + std::to_string(k);
    if (seg.size() == 7)
        return json_response(req, http::status::ok,
            json::object{{"test", test}, {"index", k}, {"attributes", attributes_of(snap)}, {"arrays", arrays_of(snap, url)},
                {"wire_autocorrelation_url", url + "/wire_autocorrelation"}});
    if (seg[7] == "wire_autocorrelation") return wire_autocorrelation(req, snap, where, r->spec_json);
    return array_response(req, snap, seg[7], where);
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
        "summary": "The tests of a succeeded job by ascending confining pressure: attributes (peak, yield, quasi-static figures), time-series columns with units, snapshots",
        "responses": {
          "200": {"description": "The tests", "content": {"application/json": {"schema": {"type": "object", "required": ["tests"],
            "properties": {"tests": {"type": "array", "items": {"type": "object", "required": ["name", "rows", "attributes", "columns", "snapshots"],
              "properties": {"name": {"type": "string", "example": "sigma3_20000"}, "rows": {"type": "integer"},
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
        "summary": "A test's time series as stored in result.h5, optionally thinned",
        "responses": {
          "200": {"description": "Columns of equal length", "content": {"application/json": {"schema": {"type": "object",
            "required": ["test", "rows", "returned_rows", "row_index", "units", "columns"],
            "properties": {"test": {"type": "string"}, "rows": {"type": "integer", "description": "rows stored"},
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
        "summary": "The prepared specimen: its attributes and its arrays (shape, type, url)",
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
        "summary": "A snapshot of a test: its attributes (requested and measured axial strain, time) and arrays (positions, radii, wire strain, membrane triangles, contacts)",
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
        "summary": "Autocorrelation of the snapshot's wire segment strains (the function summary.wire.autocorrelation_lag_m comes from), with its first maximum",
        "responses": {
          "200": {"description": "R(k) against lag k * segment length; error says why there is none", "content": {"application/json": {"schema": {"type": "object",
            "required": ["segment_length_m", "segments", "lag_m", "coefficients", "first_maximum_lag_m", "error"],
            "properties": {"segment_length_m": {"type": "number"}, "segments": {"type": "integer"},
              "lag_m": {"type": "array", "items": {"type": "number"}}, "coefficients": {"type": "array", "items": {"type": "number"}},
              "first_maximum_lag_m": {"type": "number", "nullable": true}, "error": {"type": "string", "nullable": true}}}}}},
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
