#include "api/study.hpp"

#include "api/json_text.hpp"
#include "api/utf8.hpp"

#include "core/format.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace wiredem::api {

namespace json = boost::json;

namespace {

constexpr std::size_t max_reported_errors = 50;
constexpr std::size_t max_name_chars = 200;

bool is_field_path(std::string_view p)
{
    if (p.empty() || p.front() == '.' || p.back() == '.') return false;
    char previous = '.';
    for (char c : p) {
        const bool name_char = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
        if (!name_char && c != '.') return false;
        if (c == '.' && previous == '.') return false;
        previous = c;
    }
    return true;
}

/// Sets `value` at the dotted `path` of `doc`, creating missing objects; an
/// error message when a component on the way is not an object.
std::optional<std::string> set_at(json::object& doc, std::string_view path, const json::value& value)
{
    json::object* o = &doc;
    std::size_t start = 0;
    for (;;) {
        const std::size_t dot = path.find('.', start);
        const std::string_view key = path.substr(start, dot == std::string_view::npos ? std::string_view::npos : dot - start);
        if (dot == std::string_view::npos) {
            (*o)[key] = value;
            return std::nullopt;
        }
        json::value& next = (*o)[key];
        if (next.is_null()) next = json::object();
        if (!next.is_object())
            return std::string(path.substr(0, dot)) + " is not an object in the base job, so it has no field "
                 + std::string(path.substr(dot + 1));
        o = &next.as_object();
        start = dot + 1;
    }
}

/// A number as its shortest exact decimal text ("30", "0.99", "2.5e-05").
std::string number_text(const json::value& v);

/// A value in a label: numbers shortest, anything else as JSON ("helix" quoted).
std::string value_text(const json::value& v) { return v.is_number() ? number_text(v) : json::serialize(v); }

std::string label_of(const std::vector<std::pair<std::string, json::value>>& values)
{
    std::string label;
    for (const auto& [path, value] : values) {
        if (!label.empty()) label += ' ';
        label.append(path).append("=").append(value_text(value));
    }
    return label;
}

void add(std::vector<FieldError>& errors, std::string path, std::string message)
{
    if (errors.size() < max_reported_errors) errors.push_back({std::move(path), std::move(message)});
}

json::value number_or_null(const json::value* v)
{
    return v && v->is_number() ? json::value(v->to_number<double>()) : json::value(nullptr);
}

const json::value* find(const json::value& v, std::initializer_list<const char*> path)
{
    const json::value* p = &v;
    for (const char* k : path) {
        if (!p->is_object()) return nullptr;
        p = p->as_object().if_contains(k);
        if (!p) return nullptr;
    }
    return p;
}

/// Mean, standard deviation (n − 1) and n of the finite values.
json::object spread(const std::vector<double>& xs)
{
    std::vector<double> v;
    for (double x : xs)
        if (std::isfinite(x)) v.push_back(x);
    json::object o;
    o["n"] = v.size();
    if (v.empty()) {
        o["mean"] = nullptr;
        o["sd"] = nullptr;
        return o;
    }
    double sum = 0.0;
    for (double x : v) sum += x;
    const double mean = sum / static_cast<double>(v.size());
    o["mean"] = mean;
    if (v.size() < 2) {
        o["sd"] = nullptr;
    } else {
        double ss = 0.0;
        for (double x : v) ss += (x - mean) * (x - mean);
        o["sd"] = std::sqrt(ss / static_cast<double>(v.size() - 1));
    }
    return o;
}

/// A number as its shortest exact decimal text ("30", "0.99", "2.5e-05").
std::string number_text(const json::value& v)
{
    if (v.is_int64()) return std::to_string(v.as_int64());
    if (v.is_uint64()) return std::to_string(v.as_uint64());
    return engine::exact_number(v.as_double());
}

/// A cell's text: strings as they are, numbers shortest, lists joined by ';'.
std::string cell_text(const json::value& v)
{
    if (v.is_string()) return std::string(v.as_string());
    if (v.is_null()) return "";
    if (v.is_number()) return number_text(v);
    if (v.is_array()) {
        std::string joined;
        for (const json::value& x : v.as_array()) {
            if (!joined.empty()) joined += ';';
            joined += cell_text(x);
        }
        return joined;
    }
    return json::serialize(v);
}

std::string csv_cell(const json::value& v)
{
    const std::string text = cell_text(v);
    if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

} // namespace

engine::Result<Study, std::vector<FieldError>> parse_study(const json::value& doc, std::size_t max_points)
{
    std::vector<FieldError> errors;
    if (!doc.is_object()) return engine::Err(std::vector<FieldError>{{"", "a study must be a JSON object"}});
    const json::object& d = doc.as_object();
    for (const auto& kv : d)
        if (kv.key() != "name" && kv.key() != "base" && kv.key() != "vary" && kv.key() != "points" && kv.key() != "comment")
            add(errors, std::string(kv.key()), "unknown field (a study has name, comment, base, and vary or points)");

    Study study;
    if (const json::value* n = d.if_contains("name"); !n || !n->is_string() || n->as_string().empty())
        add(errors, "name", "a non-empty string is required");
    else if (n->as_string().size() > max_name_chars)
        add(errors, "name", "longer than " + std::to_string(max_name_chars) + " bytes");
    else if (has_control_character(n->as_string()))
        add(errors, "name", "contains a control character; the name must be a single line of text");
    else
        study.name = std::string(n->as_string());
    if (const json::value* c = d.if_contains("comment"); c && !c->is_string())
        add(errors, "comment", "must be a string");
    else if (c && utf8_length(c->as_string()) > max_comment_chars)  // bounded as a job's (api/job_spec.hpp)
        add(errors, "comment", "is " + std::to_string(utf8_length(c->as_string())) + " characters long; at most "
                                   + std::to_string(max_comment_chars) + " are allowed");
    const json::value* base = d.if_contains("base");
    if (!base || !base->is_object()) add(errors, "base", "the base job, an object, is required");

    const json::value* vary = d.if_contains("vary");
    const json::value* points = d.if_contains("points");
    if ((vary != nullptr) == (points != nullptr))
        add(errors, "", "give either vary (a grid) or points (a list), not " + std::string(vary ? "both" : "neither"));

    // The points' values, before any job is built.
    std::vector<std::vector<std::pair<std::string, json::value>>> grid;
    const auto check_path = [&](std::string_view at, std::string_view path) {
        if (!is_field_path(path)) {
            std::string message = json::serialize(json::value(cut_utf8(std::string(path), 100)));
            message.append(" is not a field path (names of a-z, 0-9 and _, joined by dots)");
            add(errors, std::string(at), std::move(message));
            return false;
        }
        if (path == "name") {
            add(errors, std::string(at), "the study names its jobs: name cannot be varied");
            return false;
        }
        return true;
    };
    if (vary && !points) {
        if (!vary->is_object() || vary->as_object().empty()) {
            add(errors, "vary", "an object of field paths, each with a non-empty list of values, is required");
        } else {
            std::size_t count = 1;
            std::string factors;
            for (const auto& kv : vary->as_object()) {
                const std::string at = "vary." + std::string(kv.key());
                if (!check_path(at, kv.key())) continue;
                if (!kv.value().is_array() || kv.value().as_array().empty()) {
                    add(errors, at, "a non-empty list of values is required");
                    continue;
                }
                study.paths.emplace_back(kv.key());
                const std::size_t k = kv.value().as_array().size();
                count = count > (std::numeric_limits<std::size_t>::max() / k) ? std::numeric_limits<std::size_t>::max() : count * k;
                if (!factors.empty()) factors += " x ";
                factors += std::to_string(k);
            }
            if (errors.empty() && count > max_points)
                add(errors, "vary", "the grid has " + (count == std::numeric_limits<std::size_t>::max() ? std::string("too many")
                                                                                                        : std::to_string(count))
                                        + " points (" + factors + "), more than the limit of " + std::to_string(max_points));
            if (errors.empty()) {
                grid.emplace_back();
                for (const auto& kv : vary->as_object()) {
                    std::vector<std::vector<std::pair<std::string, json::value>>> next;
                    for (const auto& partial : grid)
                        for (const json::value& v : kv.value().as_array()) {
                            auto p = partial;
                            p.emplace_back(std::string(kv.key()), v);
                            next.push_back(std::move(p));
                        }
                    grid = std::move(next);
                }
            }
        }
    } else if (points && !vary) {
        if (!points->is_array() || points->as_array().empty()) {
            add(errors, "points", "a non-empty list of objects (field path: value) is required");
        } else if (points->as_array().size() > max_points) {
            add(errors, "points", std::to_string(points->as_array().size()) + " points, more than the limit of "
                                      + std::to_string(max_points));
        } else {
            const json::array& list = points->as_array();
            for (std::size_t i = 0; i < list.size(); ++i) {
                const std::string at = "points[" + std::to_string(i) + "]";
                if (!list[i].is_object()) {
                    add(errors, at, "must be an object of field paths and values");
                    continue;
                }
                std::vector<std::pair<std::string, json::value>> values;
                for (const auto& kv : list[i].as_object()) {
                    if (!check_path(at + "." + std::string(kv.key()), kv.key())) continue;
                    values.emplace_back(std::string(kv.key()), kv.value());
                    if (std::find(study.paths.begin(), study.paths.end(), kv.key()) == study.paths.end())
                        study.paths.emplace_back(kv.key());
                }
                for (std::size_t j = 0; j < grid.size(); ++j)
                    if (grid[j] == values) add(errors, at, "repeats points[" + std::to_string(j) + "]");
                grid.push_back(std::move(values));
            }
        }
    }
    if (!errors.empty()) return engine::Err(std::move(errors));

    // Each point: the base with its values, validated as a job.
    for (std::size_t i = 0; i < grid.size(); ++i) {
        StudyPoint point;
        point.values = std::move(grid[i]);
        point.label = label_of(point.values);
        const std::string at = "points[" + std::to_string(i) + "] (" + cut_utf8(point.label, 200) + ")";
        json::object job = base->as_object();
        bool placed = true;
        for (const auto& [path, value] : point.values)
            if (auto e = set_at(job, path, value)) {
                add(errors, at + ": " + path, *e);
                placed = false;
            }
        if (!placed) continue;
        job["name"] = cut_utf8(study.name + " [" + std::to_string(i) + "] " + point.label, max_name_chars);
        auto spec = parse_job_spec(json::value(std::move(job)));
        if (!spec.ok()) {
            for (const FieldError& e : spec.error()) add(errors, at + (e.path.empty() ? "" : ": " + e.path), e.message);
            continue;
        }
        point.spec = std::move(spec.value());
        study.points.push_back(std::move(point));
        if (errors.size() >= max_reported_errors) break;
    }
    if (!errors.empty()) return engine::Err(std::move(errors));
    return study;
}

engine::Result<Study, std::vector<FieldError>> parse_study(std::string_view text, std::size_t max_points)
{
    auto doc = parse_json_text(text); // numbers correctly rounded, as a job's
    if (!doc) return engine::Err(std::vector<FieldError>{{"", "not valid JSON: " + doc.error()}});
    return parse_study(doc.value(), max_points);
}

json::object study_summary(const Study& study, const std::vector<PointOutcome>& outcomes)
{
    json::object out;
    out["name"] = study.name;
    json::array paths;
    for (const auto& p : study.paths) paths.emplace_back(p);
    out["paths"] = std::move(paths);

    json::array rows;
    std::map<std::string, std::vector<std::size_t>> groups; // key: values but the seed
    std::vector<std::string> group_order;
    std::map<std::string, json::object> group_values;
    for (std::size_t i = 0; i < study.points.size(); ++i) {
        const StudyPoint& p = study.points[i];
        const PointOutcome outcome = i < outcomes.size() ? outcomes[i] : PointOutcome{"unknown", "", "", std::nullopt};
        json::object row;
        row["index"] = i;
        row["label"] = p.label;
        json::object values, key_values;
        for (const auto& [path, value] : p.values) {
            values[path] = value;
            if (path != "seed") key_values[path] = value;
        }
        row["values"] = values;
        row["job_id"] = outcome.job_id;
        row["state"] = outcome.state;
        row["error"] = outcome.error;
        const json::value none;
        const json::value& s = outcome.summary ? *outcome.summary : none;
        row["friction_angle_deg"] = number_or_null(find(s, {"mohr_coulomb", "friction_angle_deg"}));
        row["cohesion_pa"] = number_or_null(find(s, {"mohr_coulomb", "cohesion_pa"}));
        row["r_squared"] = number_or_null(find(s, {"mohr_coulomb", "r_squared"}));
        // What could make those three misread (summary.json mohr_coulomb.caveats), by code.
        json::array caveats;
        if (const json::value* cs = find(s, {"mohr_coulomb", "caveats"}); cs && cs->is_array())
            for (const json::value& c : cs->as_array())
                if (const json::value* code = find(c, {"code"}); code && code->is_string()) caveats.push_back(*code);
        row["fit_caveats"] = std::move(caveats);
        json::array pressures, yield_q, max_q, shapes;
        if (const json::value* tests = find(s, {"tests"}); tests && tests->is_array())
            for (const json::value& t : tests->as_array()) {
                pressures.push_back(number_or_null(find(t, {"confining_pressure_pa"})));
                yield_q.push_back(number_or_null(find(t, {"yield", "deviatoric_stress_pa"})));
                max_q.push_back(number_or_null(find(t, {"peak_deviatoric_stress_pa"})));
                const json::value* shape = find(t, {"yield", "shape"});
                shapes.push_back(shape && shape->is_string() ? *shape : json::value(nullptr));
            }
        row["confining_pressures_pa"] = std::move(pressures);
        row["yield_deviatoric_stress_pa"] = std::move(yield_q);
        row["yield_shape"] = std::move(shapes);
        row["max_deviatoric_stress_pa"] = std::move(max_q);
        row["grain_volume_fraction"] = number_or_null(find(s, {"specimen", "grain_volume_fraction"}));
        row["wire_volume_fraction"] = number_or_null(find(s, {"specimen", "wire_volume_fraction"}));
        row["core_grain_volume_fraction"] = number_or_null(find(s, {"specimen", "core_grain_volume_fraction"}));
        row["wire_length_m"] = number_or_null(find(s, {"specimen", "wire_length_m"}));
        row["autocorrelation_lag_m"] = number_or_null(find(s, {"wire", "autocorrelation_lag_m"}));
        row["autocorrelation_prominent_lag_m"] = number_or_null(find(s, {"wire", "autocorrelation_prominent_lag_m"}));
        rows.push_back(std::move(row));

        const std::string key = json::serialize(key_values);
        if (!groups.count(key)) {
            group_order.push_back(key);
            group_values[key] = key_values;
        }
        groups[key].push_back(i);
    }

    json::array grouped;
    for (const std::string& key : group_order) {
        std::vector<double> phi, c;
        std::size_t points = 0, succeeded = 0;
        for (std::size_t i : groups[key]) {
            ++points;
            const json::object& row = rows[i].as_object();
            if (row.at("state") != "succeeded") continue;
            ++succeeded;
            const json::value& f = row.at("friction_angle_deg");
            const json::value& co = row.at("cohesion_pa");
            phi.push_back(f.is_number() ? f.to_number<double>() : std::numeric_limits<double>::quiet_NaN());
            c.push_back(co.is_number() ? co.to_number<double>() : std::numeric_limits<double>::quiet_NaN());
        }
        json::object g;
        g["values"] = group_values[key];
        g["points"] = points;
        g["succeeded"] = succeeded;
        g["friction_angle_deg"] = spread(phi);
        g["cohesion_pa"] = spread(c);
        grouped.push_back(std::move(g));
    }
    out["points"] = std::move(rows);
    out["groups"] = std::move(grouped);
    out["definitions"] = json::object{
        {"friction_angle_deg", "Mohr-Coulomb through the yield states (summary.json mohr_coulomb)"},
        {"fit_caveats", "the codes of that fit's caveats (summary.json mohr_coulomb.caveats): its phi, c and R2 are an "
                        "unconstrained line to be read with them"},
        {"groups", "points equal but for seed; sd is the sample standard deviation (n - 1), null below n = 2"}};
    return out;
}

std::string study_summary_csv(const json::object& summary)
{
    std::ostringstream csv;
    std::vector<std::string> paths;
    if (const json::value* p = summary.if_contains("paths"); p && p->is_array())
        for (const json::value& x : p->as_array())
            if (x.is_string()) paths.emplace_back(x.as_string());
    csv << "index";
    for (const auto& p : paths) csv << ',' << csv_cell(json::value(p));
    const char* columns[] = {"state", "job_id", "friction_angle_deg", "cohesion_pa", "r_squared",
        "confining_pressures_pa", "yield_deviatoric_stress_pa", "yield_shape", "max_deviatoric_stress_pa",
        "grain_volume_fraction", "wire_volume_fraction", "core_grain_volume_fraction", "wire_length_m",
        "autocorrelation_lag_m", "autocorrelation_prominent_lag_m", "fit_caveats", "error"};
    for (const char* c : columns) csv << ',' << c;
    csv << '\n';
    if (const json::value* rows = summary.if_contains("points"); rows && rows->is_array())
        for (const json::value& r : rows->as_array()) {
            const json::object& row = r.as_object();
            csv << csv_cell(row.at("index"));
            for (const auto& p : paths) {
                const json::value* v = row.at("values").as_object().if_contains(p);
                csv << ',' << (v ? csv_cell(*v) : std::string());
            }
            for (const char* c : columns) {
                const json::value* v = row.if_contains(c);
                csv << ',' << (v ? csv_cell(*v) : std::string());
            }
            csv << '\n';
        }
    return csv.str();
}

} // namespace wiredem::api
