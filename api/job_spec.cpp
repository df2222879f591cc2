// Reading, validating and writing job specs. The reader walks the schema in
// document order and records every problem instead of stopping at the first;
// a field with a problem keeps its default so that reading can go on. The
// cross-field checks run afterwards, each only when all of its inputs were
// read without a problem (so one bad value gives one error, not a cascade).
//
// The allowed ranges are the Range constants passed to the readers below; the
// same figures are in the header's field comments and docs/job-spec.md.
#include "api/job_spec.hpp"

#include "api/derived.hpp"
#include "api/engine_settings.hpp"
#include "api/json_text.hpp"
#include "api/utf8.hpp"
#include "core/format.hpp"
#include "specimen/box_preparation.hpp"
#include "specimen/grain_sizes.hpp"
#include "specimen/pattern.hpp"
#include "specimen/preparation.hpp"
#include "state/clump_shape.hpp"
#include "triaxial/free_standing.hpp"
#include "triaxial/triaxial.hpp"

#include <boost/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <span>
#include <utility>

namespace wiredem::api {

namespace json = boost::json;

namespace {

// ---------------------------------------------------------------- formatting

using engine::exact_number;
using engine::format_number;

/// What a JSON value is, for "expected a number, got a string".
std::string_view kind_text(const json::value& v)
{
    switch (v.kind()) {
    case json::kind::null: return "null";
    case json::kind::bool_: return "a boolean";
    case json::kind::int64:
    case json::kind::uint64:
    case json::kind::double_: return "a number";
    case json::kind::string: return "a string";
    case json::kind::array: return "an array";
    case json::kind::object: return "an object";
    }
    return "an unknown value";
}

// -------------------------------------------------------------------- ranges

/// An interval of allowed values; NaN is never inside.
struct Range {
    double lo;
    double hi;
    bool lo_open;
    bool hi_open;

    [[nodiscard]] bool contains(double x) const
    {
        return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
    }
    [[nodiscard]] std::string text() const
    {
        return std::string(lo_open ? "(" : "[") + exact_number(lo) + ", " + exact_number(hi) + (hi_open ? ")" : "]");
    }
};

constexpr Range open_closed(double lo, double hi) { return {lo, hi, true, false}; }
constexpr Range closed(double lo, double hi) { return {lo, hi, false, false}; }
constexpr Range closed_open(double lo, double hi) { return {lo, hi, false, true}; }
constexpr Range open_open(double lo, double hi) { return {lo, hi, true, true}; }

// Shared ranges (documented in docs/job-spec.md).
// From the softest grains studied (hydrogel beads, ~10 kPa; a modulus in
// GPa or MPa is refused) up to ~10× diamond. 5e-324 Pa was accepted.
constexpr Range modulus_range = closed(1e4, 1e13);
constexpr Range poisson_range = open_closed(-1.0, 0.5);       // thermodynamic bounds of an isotropic solid
constexpr Range density_range = open_closed(0.0, 1e5);
constexpr double two_pi = 2.0 * std::numbers::pi;

/// Integer ranges are closed.
struct IntRange {
    std::uint64_t lo;
    std::uint64_t hi;
    [[nodiscard]] std::string text() const
    {
        // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "[" + std::string&&.
        std::string s(1, '[');
        s += std::to_string(lo);
        s += ", ";
        s += std::to_string(hi);
        s += ']';
        return s;
    }
};

constexpr std::size_t max_name_chars = 200;
constexpr std::size_t max_pressures = 16;
constexpr std::size_t max_snapshots = 64;
/// The column must be at least this many largest-grain diameters wide. The
/// triaxial standards ask for 6 (ASTM D7181); 4 still lets the small test
/// specimens (R = 8 mm, r_p = 1.23 mm, some spread) through.
constexpr double min_column_grain_diameters = 4.0;
/// Densest random packing of spheres: more grain volume than this fraction of
/// the membrane's cannot be poured into it.

// ----------------------------------------------------------------- validator

/// Collects errors and answers whether a field (or anything under it) holds
/// a bad value. Only blocking errors count for that: a bad value or type
/// read while walking the schema. Unknown keys and the cross-field checks'
/// own findings do not block other checks (the values they read are fine).
class Validator {
public:
    /// A field's value is unusable (wrong type, out of range): checks that read it are skipped.
    void fail(std::string path, std::string message) { add(std::move(path), std::move(message), true); }
    /// A problem that leaves the values usable (unknown key, failed cross-field check).
    void note(std::string path, std::string message) { add(std::move(path), std::move(message), false); }

    /// True when no blocking error was recorded at `path` or below it.
    [[nodiscard]] bool clean(std::string_view path) const
    {
        for (std::size_t i = 0; i < errors_.size(); ++i) {
            if (!blocking_[i]) continue;
            const std::string_view p = errors_[i].path;
            if (p.substr(0, path.size()) != path) continue;
            if (p.size() == path.size() || p[path.size()] == '.' || p[path.size()] == '[') return false;
        }
        return true;
    }
    [[nodiscard]] bool clean(std::initializer_list<std::string_view> paths) const
    {
        for (std::string_view p : paths)
            if (!clean(p)) return false;
        return true;
    }
    [[nodiscard]] std::vector<FieldError>& errors() { return errors_; }

    /// Schema mode (job_spec_json_schema): the readers describe every field
    /// they take, with its type, range and default, instead of only reading it.
    void record_schema() { schema_ = object_schema(); }
    /// Trusted mode (parse_written_job_spec): a document wiredem wrote itself,
    /// judged when it was accepted. A value outside today's range is taken as
    /// written, and the cross-field checks are not run again: tightening a
    /// rule must not make a stored job unreadable.
    void trust() { trusted_ = true; }
    [[nodiscard]] bool trusted() const { return trusted_; }
    [[nodiscard]] bool recording() const { return schema_.has_value(); }
    /// Sets the schema of the field at `path` (dots between keys); the objects above it are made as needed.
    void describe(std::string_view path, json::object field)
    {
        if (!schema_) return;
        json::object* node = &*schema_;
        for (;;) {
            const auto dot = path.find('.');
            json::object& props = (*node)["properties"].as_object();
            const std::string key(path.substr(0, dot));
            if (dot == std::string_view::npos) {
                props[key] = std::move(field);
                return;
            }
            if (!props.contains(key)) props[key] = object_schema();
            node = &props[key].as_object();
            path.remove_prefix(dot + 1);
        }
    }
    [[nodiscard]] json::object schema() const { return schema_ ? *schema_ : json::object(); }

    /// An object with no field described yet; unknown keys are errors.
    static json::object object_schema()
    {
        return json::object{{"type", "object"}, {"properties", json::object()}, {"additionalProperties", false}};
    }

private:
    bool trusted_ = false;
    std::optional<json::object> schema_;
    void add(std::string path, std::string message, bool blocking)
    {
        errors_.push_back({std::move(path), std::move(message)});
        blocking_.push_back(blocking);
    }
    std::vector<FieldError> errors_;
    std::vector<bool> blocking_;
};

std::string join_path(std::string_view parent, std::string_view key)
{
    return parent.empty() ? std::string(key) : std::string(parent) + "." + std::string(key);
}

std::string index_path(std::string_view parent, std::size_t i)
{
    return std::string(parent) + "[" + std::to_string(i) + "]";
}

// ------------------------------------------------------------ schema pieces

/// A number's bounds as JSON Schema (2020-12: exclusive bounds are numbers).
json::object number_schema(const Range& range)
{
    json::object o{{"type", "number"}};
    o[range.lo_open ? "exclusiveMinimum" : "minimum"] = range.lo;
    o[range.hi_open ? "exclusiveMaximum" : "maximum"] = range.hi;
    return o;
}

json::object with_default(json::object o, json::value d)
{
    o["default"] = std::move(d);
    return o;
}

/// What a field means and its unit: every reader takes one, and the schema
/// carries them ("description", and "x-unit" for a number: "1" when it has
/// none; a JSON Schema keyword of its own, as OpenAPI wants extensions named).
/// docs/job-spec.md's table gives the same (tests/api/test_job_spec_schema.cpp).
struct Meaning {
    const char* unit;  ///< nullptr: not a quantity (a string, a choice)
    const char* text;
};

json::object with_meaning(json::object o, const Meaning& m)
{
    o["description"] = m.text;
    if (m.unit) o["x-unit"] = m.unit;
    return o;
}

// --------------------------------------------------------- value-level reads

/// A JSON number as a double, or nullopt for any other kind.
std::optional<double> number_of(const json::value& v)
{
    if (v.is_double()) return v.get_double();
    if (v.is_int64()) return static_cast<double>(v.get_int64());
    if (v.is_uint64()) return static_cast<double>(v.get_uint64());
    return std::nullopt;
}

/// Reads a number in `range` into `out`; on a problem records it and leaves `out`.
bool read_number(Validator& v, const json::value& j, const std::string& path, Range range, double& out)
{
    const std::optional<double> x = number_of(j);
    if (!x) {
        v.fail(path, "expected a number, got " + std::string(kind_text(j)));
        return false;
    }
    if (!range.contains(*x) && !v.trusted()) {
        v.fail(path, exact_number(*x) + " is out of range " + range.text());
        return false;
    }
    out = *x;
    return true;
}

/// Reads a non-negative integer in `range`. A number with a zero fraction
/// (3.0) counts as an integer; 3.5 does not.
bool read_integer(Validator& v, const json::value& j, const std::string& path, IntRange range, std::uint64_t& out)
{
    std::uint64_t n = 0;
    if (j.is_int64()) {
        if (j.get_int64() < 0) {
            v.fail(path, std::to_string(j.get_int64()) + " is out of range " + range.text());
            return false;
        }
        n = static_cast<std::uint64_t>(j.get_int64());
    } else if (j.is_uint64()) {
        n = j.get_uint64();
    } else if (j.is_double()) {
        const double d = j.get_double();
        if (!std::isfinite(d) || std::trunc(d) != d) {
            v.fail(path, "expected an integer, got " + exact_number(d));
            return false;
        }
        if (d < 0.0 || d >= 0x1p64) {
            v.fail(path, exact_number(d) + " is out of range " + range.text());
            return false;
        }
        n = static_cast<std::uint64_t>(d);
    } else {
        v.fail(path, "expected an integer, got " + std::string(kind_text(j)));
        return false;
    }
    if ((n < range.lo || n > range.hi) && !v.trusted()) {
        v.fail(path, std::to_string(n) + " is out of range " + range.text());
        return false;
    }
    out = n;
    return true;
}

/// Reads an enum from one of its JSON names.
template <class E, std::size_t N>
bool read_choice(Validator& v, const json::value& j, const std::string& path,
    const std::array<std::pair<std::string_view, E>, N>& choices, E& out)
{
    if (!j.is_string()) {
        v.fail(path, "expected a string, got " + std::string(kind_text(j)));
        return false;
    }
    const std::string_view s(j.get_string().data(), j.get_string().size());
    std::string allowed;
    for (const auto& [name, value] : choices) {
        if (name == s) {
            out = value;
            return true;
        }
        allowed += (allowed.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    }
    v.fail(path, "\"" + std::string(s) + "\" is not one of " + allowed);
    return false;
}


// --------------------------------------------------------- object-level reads

/// Reads the fields of one JSON object. Every key the schema knows is taken
/// with take(); finish() then reports the keys nobody took. An absent object
/// (nullptr) reads as all defaults.
class ObjectReader {
public:
    ObjectReader(Validator& v, const json::value* j, std::string path) : v_(v), path_(std::move(path))
    {
        if (j == nullptr) return;
        if (j->is_object())
            obj_ = &j->get_object();
        else
            v_.fail(path_, "expected an object, got " + std::string(kind_text(*j)));
    }
    ObjectReader(const ObjectReader&) = delete;
    ObjectReader& operator=(const ObjectReader&) = delete;

    [[nodiscard]] Validator& validator() { return v_; }
    [[nodiscard]] std::string path_of(std::string_view key) const { return join_path(path_, key); }

    /// The value under `key`, or nullptr when absent; marks the key as known.
    [[nodiscard]] const json::value* take(std::string_view key)
    {
        known_.push_back(key);
        if (obj_ == nullptr) return nullptr;
        return obj_->if_contains(key);
    }

    /// Describes the field `key` in schema mode (Validator::record_schema).
    void describe(std::string_view key, json::object field, const Meaning& m)
    {
        v_.describe(path_of(key), with_meaning(std::move(field), m));
    }

    void number(std::string_view key, Range range, double& out, const Meaning& m)
    {
        if (v_.recording()) describe(key, with_default(number_schema(range), out), m);
        if (const json::value* j = take(key)) read_number(v_, *j, path_of(key), range, out);
    }
    template <class T>
    void integer(std::string_view key, IntRange range, T& out, const Meaning& m)
    {
        if (v_.recording())
            describe(key, json::object{{"type", "integer"}, {"minimum", range.lo}, {"maximum", range.hi},
                              {"default", static_cast<std::uint64_t>(out)}}, m);
        std::uint64_t n = 0;
        if (const json::value* j = take(key))
            if (read_integer(v_, *j, path_of(key), range, n)) out = static_cast<T>(n);
    }
    template <class E, std::size_t N>
    void choice(std::string_view key, const std::array<std::pair<std::string_view, E>, N>& choices, E& out, const Meaning& m)
    {
        if (v_.recording()) {
            json::array names;
            json::value current;
            for (const auto& [name, value] : choices) {
                names.push_back(json::string(name));
                if (value == out) current = json::string(name);
            }
            describe(key, json::object{{"type", "string"}, {"enum", std::move(names)}, {"default", std::move(current)}}, m);
        }
        if (const json::value* j = take(key)) read_choice(v_, *j, path_of(key), choices, out);
    }
    void text(std::string_view key, std::string& out, const Meaning& m)
    {
        if (v_.recording()) describe(key, json::object{{"type", "string"}, {"default", out}}, m);
        const json::value* j = take(key);
        if (j == nullptr) return;
        if (!j->is_string()) {
            v_.fail(path_of(key), "expected a string, got " + std::string(kind_text(*j)));
            return;
        }
        out.assign(j->get_string().data(), j->get_string().size());
    }

    /// Reports every key of the object that no take() asked for, in document order.
    void finish()
    {
        if (obj_ == nullptr) return;
        for (const auto& kv : *obj_) {
            const std::string_view key(kv.key().data(), kv.key().size());
            bool is_known = false;
            for (std::string_view k : known_) is_known = is_known || k == key;
            if (is_known) continue;
            std::string allowed;
            for (std::string_view k : known_) allowed += (allowed.empty() ? "" : ", ") + std::string(k);
            v_.note(path_of(key), "unknown key \"" + std::string(key) + "\" (allowed here: " + allowed + ")");
        }
    }

private:
    Validator& v_;
    std::string path_;
    const json::object* obj_ = nullptr;
    std::vector<std::string_view> known_;
};

/// Reads an array of numbers, each in `range`, with `min_n`–`max_n` entries;
/// strictly increasing unless `what` (the array's name in the message) is
/// empty. Returns false (leaving `out`) on any problem.
bool read_numbers(ObjectReader& r, std::string_view key, Range range, std::size_t min_n, std::size_t max_n,
    std::string_view what, std::vector<double>& out, const Meaning& m)
{
    if (r.validator().recording()) {
        json::array d;
        for (double x : out) d.push_back(x);
        json::object schema{{"type", "array"}, {"items", number_schema(range)}, {"minItems", min_n}, {"maxItems", max_n},
            {"default", std::move(d)}};
        // The order the reader checks, for the web form's "allowed" column.
        if (!what.empty()) schema["x-order"] = "increasing";
        r.describe(key, std::move(schema), m);
    }
    const json::value* j = r.take(key);
    if (j == nullptr) return false;
    Validator& v = r.validator();
    const std::string path = r.path_of(key);
    if (!j->is_array()) {
        v.fail(path, "expected an array, got " + std::string(kind_text(*j)));
        return false;
    }
    const json::array& a = j->get_array();
    bool ok = true;
    if (a.size() < min_n || a.size() > max_n) {
        v.fail(path, "has " + std::to_string(a.size()) + " entries; allowed " + std::to_string(min_n) + " to "
                         + std::to_string(max_n));
        ok = false;
    }
    std::vector<double> values(a.size(), 0.0);
    std::vector<bool> valid(a.size(), false);
    for (std::size_t i = 0; i < a.size(); ++i) {
        valid[i] = read_number(v, a[i], index_path(path, i), range, values[i]);
        ok = ok && valid[i];
        if (!what.empty() && i > 0 && valid[i] && valid[i - 1] && !(values[i] > values[i - 1])) {
            v.fail(index_path(path, i), exact_number(values[i]) + " is not greater than the previous entry "
                                            + exact_number(values[i - 1]) + "; " + std::string(what)
                                            + " must be strictly increasing");
            ok = false;
        }
    }
    if (ok) out = std::move(values);
    return ok;
}

/// Reads an array of numbers, each in `range`, strictly increasing (`what`
/// names it in the message), with `min_n`–`max_n` entries. Returns false
/// (leaving `out`) on any problem.
bool read_increasing_numbers(ObjectReader& r, std::string_view key, Range range, std::size_t min_n,
    std::size_t max_n, std::string_view what, std::vector<double>& out, const Meaning& m)
{
    return read_numbers(r, key, range, min_n, max_n, what, out, m);
}

/// The same in any order.
bool read_numbers(ObjectReader& r, std::string_view key, Range range, std::size_t min_n, std::size_t max_n,
    std::vector<double>& out, const Meaning& m)
{
    return read_numbers(r, key, range, min_n, max_n, {}, out, m);
}

// ----------------------------------------------------------- schema readers

// The engine's own name tables: the spec's names are the engine's.
constexpr const auto& wire_patterns = engine::pattern_kind_names;
constexpr const auto& integrators = engine::integrator_names;
constexpr const auto& membrane_edges = engine::membrane_edge_law_names;
constexpr const auto& grain_size_bases = engine::sieve_basis_names;
constexpr const auto& wire_ends = engine::wire_end_names;
constexpr const auto& consolidations = engine::consolidation_names;

constexpr std::array<std::pair<std::string_view, GrainPreset>, 2> grain_presets{{
    {"none", GrainPreset::none},
    {gravel_preset.name, GrainPreset::gravel},
}};

constexpr std::array<std::pair<std::string_view, CellKind>, 2> cell_kinds{{
    {"membrane", CellKind::membrane},
    {"cuboid", CellKind::cuboid},
}};

/// An optional number: absent or null leaves `out` empty.
void optional_number(ObjectReader& r, std::string_view key, const Range& range, std::optional<double>& out, const Meaning& m)
{
    if (r.validator().recording()) {
        json::object o = number_schema(range);
        o["type"] = json::array{"number", "null"};
        r.describe(key, with_default(std::move(o), out ? json::value(*out) : json::value(nullptr)), m);
    }
    if (const json::value* j = r.take(key); j != nullptr && !j->is_null()) {
        double x = 0.0;
        if (read_number(r.validator(), *j, r.path_of(key), range, x)) out = x;
    }
}

void read_grain(ObjectReader& r, GrainMaterialSpec& g)
{
    r.number("youngs_modulus_pa", modulus_range, g.youngs_modulus_pa,
        {"Pa", "E_p, Young's modulus of the grains"});
    r.number("poisson_ratio", poisson_range, g.poisson_ratio,
        {"1", "ν_p, Poisson's ratio of the grains"});
    r.number("density_kg_per_m3", density_range, g.density_kg_per_m3,
        {"kg/m³", "ρ_p, density of the grains"});
}

void read_plate(ObjectReader& r, PlateMaterialSpec& p)
{
    r.number("youngs_modulus_pa", modulus_range, p.youngs_modulus_pa,
        {"Pa", "E_b, Young's modulus of both plates"});
    r.number("poisson_ratio", poisson_range, p.poisson_ratio,
        {"1", "ν_b, Poisson's ratio of the plates"});
}

/// The most points a toolpath's layer may have.
constexpr std::size_t max_toolpath_points = 10'000;


void read_toolpath(ObjectReader& r, WireSpec& w)
{
    read_numbers(r, "toolpath_x_m", closed(-1.0, 1.0), 0, max_toolpath_points, w.toolpath_x_m,
        {"m", "the pattern \"toolpath\": x of the points of one layer of the nozzle's path, in the column's frame (the axis at x = y = 0); with toolpath_y_m, 2 or more points. The nozzle walks the polyline at the path speed ω R_a, then straight on to the next layer's first point, and lays the next layer on the fill as it rises, the polyline turned by toolpath_rotation_per_layer_rad; the farthest point must stay below membrane_radius_m less the membrane nodes' contact radius, radius_m and clearance_m, as the built-in patterns' reach must (docs/model.md, \"The robot's own toolpath\"). Only with the pattern \"toolpath\""});
    read_numbers(r, "toolpath_y_m", closed(-1.0, 1.0), 0, max_toolpath_points, w.toolpath_y_m,
        {"m", "the pattern \"toolpath\": y of the points, as many as toolpath_x_m"});
    r.number("toolpath_rotation_per_layer_rad", closed(-two_pi, two_pi), w.toolpath_rotation_per_layer_rad,
        {"rad", "the pattern \"toolpath\": the turn of the polyline about the axis from one layer to the next (layer k is turned by k times it)"});
}

/// specimen.wire.breaking_strain: a number (ε_b) or "unbreakable".
void read_breaking_strain(ObjectReader& r, std::optional<double>& out)
{
    const Range range = open_closed(0.0, 10.0);
    if (r.validator().recording())
        r.describe("breaking_strain",
            json::object{{"oneOf", json::array{number_schema(range), json::object{{"const", "unbreakable"}}}},
                {"default", out ? json::value(*out) : json::value("unbreakable")}},
            {"1", "ε_b, the wire's breaking strain: a segment stretched beyond it breaks, the chain has two free ends there, and the event (time, the test's axial strain, position along the wire) is recorded; its tensile strength is E_w ε_b, its breaking force E_w π r_w² ε_b. \"unbreakable\": the model spec's wire (docs/model.md, \"A wire that breaks\")"});
    const json::value* j = r.take("breaking_strain");
    if (j == nullptr) return;
    const std::string path = r.path_of("breaking_strain");
    if (j->is_string()) {
        const json::string& s = j->get_string();
        if (s == "unbreakable")
            out.reset();
        else
            r.validator().fail(path, "\"" + std::string(s.data(), s.size()) + "\" is neither \"unbreakable\" nor a number in "
                                         + range.text());
    } else if (number_of(*j)) {
        double strain = 0.0;
        if (read_number(r.validator(), *j, path, range, strain)) out = strain;
    } else {
        r.validator().fail(path, "expected a breaking strain in " + range.text() + " or \"unbreakable\", got "
                                     + std::string(kind_text(*j)));
    }
}

/// The most cut positions a job may give.
constexpr std::size_t max_wire_cuts = 10'000;

void read_wire_cuts(ObjectReader& r, WireSpec& w)
{
    read_increasing_numbers(r, "cuts_at_m", open_closed(0.0, 1e4), 0, max_wire_cuts, "the cut positions", w.cuts_at_m,
        {"m", "where the prepared wire is cut before any test: positions along the wire, as the rest length from its first node (l_w per segment); the segment that holds a position is removed. A position past the laid wire's end fails the preparation. The pieces and their lengths are in the summary (specimen.wire_pieces). To cut where a reference test's wire strain was lowest (the seed paper's claim that the spiral helix can be cut between its loops without losing much strength), run the reference job, then wiredem cuts RESULT --count N (docs/client.md) prints these positions"});
    r.integer("cut_every_loops", IntRange{0, 1'000'000}, w.cut_every_loops,
        {"1", "cut the prepared wire after every this many loops around the column's axis (the winding angle of its nodes about the axis, unwrapped along the wire): the segment where the angle passes each multiple of 2π k is removed; 0: no such cuts"});
}

void read_wire(ObjectReader& r, WireSpec& w)
{
    r.choice("pattern", wire_patterns, w.pattern,
        {nullptr, "deployment pattern (model spec §5); toolpath: the robot's own path, given by toolpath_x_m and toolpath_y_m"});
    r.number("radius_m", open_closed(0.0, 0.01), w.radius_m,
        {"m", "r_w, contact radius of a wire node"});
    r.number("segment_length_m", open_closed(0.0, 0.1), w.segment_length_m,
        {"m", "l_w, rest length of a segment"});
    r.number("youngs_modulus_pa", modulus_range, w.youngs_modulus_pa,
        {"Pa", "E_w, Young's modulus of the wire"});
    r.number("poisson_ratio", poisson_range, w.poisson_ratio,
        {"1", "ν_w, Poisson's ratio of the wire"});
    r.number("density_kg_per_m3", density_range, w.density_kg_per_m3,
        {"kg/m³", "ρ_w, density of the wire; node mass ρ_w π r_w² l_w"});
    r.number("nozzle_rise_speed_m_per_s", open_closed(0.0, 100.0), w.nozzle_rise_speed_m_per_s,
        {"m/s", "v_z^w, rise speed of the nozzle that lays the wire"});
    r.number("angular_speed_rad_per_s", open_closed(0.0, 1e5), w.angular_speed_rad_per_s,
        {"rad/s", "ω; the wire is laid at ω·R_a for every pattern"});
    r.number("helix_radius_m", open_closed(0.0, 1.0), w.helix_radius_m,
        {"m", "R_a, radius of the (outer) circle: 0.6 R for the 20 mm column"});
    r.number("inner_radius_m", open_closed(0.0, 1.0), w.inner_radius_m,
        {"m", "R_i, small circle of spiral_helix (ignored otherwise); must be < R_a"});
    r.number("period_angle_rad", open_closed(0.0, two_pi), w.period_angle_rad,
        {"rad", "φ_rs: one small circle (spiral_helix) or one radial excursion (radial_helix) per φ_rs around the axis; four per turn by default"});
    r.number("clearance_m", closed(0.0, 0.1), w.clearance_m,
        {"m", "gap kept between the wire surface and the membrane"});
    optional_number(r, "length_m", open_closed(0.0, 1e4), w.length_m,
        {"m", "the length of wire to lay; the fill rate then follows: v_fill = ω R_a (H_fill − 2 r_max) / L (the wire is laid at ω R_a while the fill rises through all but its last grain diameter). The paper's column has about 10 m (0.030 m/s for 8000 grains in R = 20 mm). null: specimen.pouring.fill_rate_m_per_s sets the length. Ignored without a pattern"});
    // A number (the yield strain ε_y) or "elastic" (the model spec's wire).
    const Range yield_range = open_closed(0.0, 1.0);
    if (r.validator().recording())
        r.describe("bending_yield_strain",
            json::object{{"oneOf", json::array{number_schema(yield_range), json::object{{"const", "elastic"}}}},
                {"default", w.bending_yield_strain ? json::value(*w.bending_yield_strain) : json::value("elastic")}},
            {"1", "ε_y = σ_y/E_w, the wire's yield strain in bending. Every joint is an elastic–perfectly-plastic hinge that yields at ζ_y = ε_y l_w/r_w (0.125 rad at the defaults), so the nozzle forms the wire plastically and a laid coil or hairpin keeps its shape; 0.05 is a polyamide-like wire (σ_y = 50 MPa at E_w = 1 GPa). \"elastic\": the model spec's wire, straight at rest, which springs back from any curve (docs/model.md, \"Wire\")"});
    if (const json::value* j = r.take("bending_yield_strain")) {
        const std::string path = r.path_of("bending_yield_strain");
        const Range range = yield_range;
        if (j->is_string()) {
            const json::string& s = j->get_string();
            if (s == "elastic")
                w.bending_yield_strain.reset();
            else
                r.validator().fail(path, "\"" + std::string(s.data(), s.size()) + "\" is neither \"elastic\" nor a number in "
                                             + range.text());
        } else if (number_of(*j)) {
            double strain = 0.0;
            if (read_number(r.validator(), *j, path, range, strain)) w.bending_yield_strain = strain;
        } else {
            r.validator().fail(path, "expected a yield strain in " + range.text() + " or \"elastic\", got "
                                         + std::string(kind_text(*j)));
        }
    }
    read_breaking_strain(r, w.breaking_strain);
    read_wire_cuts(r, w);
    read_toolpath(r, w);
}

void read_membrane(ObjectReader& r, MembraneSpec& m)
{
    r.number("thickness_m", open_closed(0.0, 0.01), m.thickness_m,
        {"m", "d, thickness of the membrane"});
    r.number("mesh_size_m", open_closed(0.0, 0.1), m.mesh_size_m,
        {"m", "l_m, edge of the triangular mesh"});
    r.number("youngs_modulus_pa", modulus_range, m.youngs_modulus_pa,
        {"Pa", "E_m, Young's modulus of the membrane; edge stiffness k_m = (√3/2) E_m d"});
    r.number("poisson_ratio", poisson_range, m.poisson_ratio,
        {"1", "ν_m (enters the Hertz E* of grain–membrane contacts)"});
    r.number("density_kg_per_m3", density_range, m.density_kg_per_m3,
        {"kg/m³", "ρ_m; node mass (√3/2) l_m² ρ_m d"});
    r.choice("edges", membrane_edges, m.edges,
        {nullptr, "edge law: slack when shorter than its rest length (the sheet wrinkles), or the model spec's linear spring both ways (docs/model.md, \"The membrane carries no compression\")"});
    // null (or absent) means "follow the thickness": d/2.
    optional_number(r, "contact_radius_m", open_closed(0.0, 0.01), m.contact_radius_m,
        {"m", "r_m, contact radius of a membrane node; null (or absent) = d/2, following the thickness"});
}

void read_pouring(ObjectReader& r, PouringSpec& p)
{
    optional_number(r, "fill_rate_m_per_s", open_closed(0.0, 100.0), p.fill_rate_m_per_s,
        {"m/s", "how fast the pile's fill height rises while pouring. The nozzle lays wire at ω R_a for the whole pour, so this sets the wire per height of column: a helix's pitch is 2π v_fill / ω (5.2 mm at the defaults; 0.1 m/s gives 2.1 mm)"});
    r.number("settle_kinetic_energy_per_grain_j", open_closed(0.0, 1.0), p.settle_kinetic_energy_per_grain_j,
        {"J", "the packing has settled when the mean kinetic energy per grain is below this"});
    r.number("max_preparation_time_s", open_closed(0.0, 1e4), p.max_preparation_time_s,
        {"s", "simulated time after which an unsettled preparation fails"});
}

/// The diameters of a grain-size curve: the radii grain_radius_m allows, doubled.
constexpr Range grain_diameter_range = closed(2e-5, 0.2);
constexpr std::size_t max_grain_size_points = 64;
constexpr double min_grain_size_ratio = 1.001;

/// specimen.grain_sizes: null (or absent), or a curve. Its fields are
/// described inside the one schema entry (a curve is all or nothing).
void read_grain_sizes(ObjectReader& r, std::optional<GrainSizesSpec>& out)
{
    Validator& v = r.validator();
    const std::string_view key = "grain_sizes";
    if (v.recording()) {
        json::array bases;
        for (const auto& [name, value] : grain_size_bases) bases.push_back(json::string(name));
        json::object diameters{{"type", "array"}, {"items", number_schema(grain_diameter_range)}, {"minItems", 2},
            {"maxItems", max_grain_size_points}, {"description", "D_k, grain diameters (sieve apertures), strictly increasing"},
            {"x-unit", "m"}, {"x-order", "increasing"}};
        json::object fractions{{"type", "array"}, {"items", number_schema(closed(0.0, 1.0))}, {"minItems", 2},
            {"maxItems", max_grain_size_points},
            {"description", "P_k, the fraction passing D_k: one per diameter, nondecreasing, the first 0 and the last 1"},
            {"x-unit", "1"}, {"x-order", "nondecreasing"}};
        // One schema entry, an object or null (as the optional numbers are
        // a number or null); its own fields are described inside it.
        json::object curve{{"type", json::array{"object", "null"}}, {"default", nullptr},
            {"properties", json::object{{"basis", json::object{{"type", "string"}, {"enum", std::move(bases)}, {"default", "mass"},
                                                     {"description", "what the fractions count: mass (a sieve analysis) or number"}}},
                               {"diameters_m", std::move(diameters)}, {"fraction_passing", std::move(fractions)}}},
            {"required", json::array{"diameters_m", "fraction_passing"}}, {"additionalProperties", false}};
        r.describe(key, std::move(curve),
            {nullptr, "a grain-size curve to draw the grains from instead of grain_radius_m and grain_radius_spread (leave those out): {\"basis\": \"mass\" or \"number\", \"diameters_m\": [D_k], \"fraction_passing\": [P_k]}, linear in log D between sizes (docs/model.md, \"Size distribution\"); null: the spread"});
    }
    const json::value* j = r.take(key);
    if (j == nullptr || j->is_null()) return;
    const std::string path = r.path_of(key);
    if (!j->is_object()) {
        v.fail(path, "expected an object or null, got " + std::string(kind_text(*j)));
        return;
    }
    ObjectReader c(v, j, path);
    GrainSizesSpec g;
    c.choice("basis", grain_size_bases, g.basis, {nullptr, ""});
    bool ok = read_increasing_numbers(c, "diameters_m", grain_diameter_range, 2, max_grain_size_points,
        "grain-size diameters", g.diameters_m, {"m", ""});
    if (!c.take("diameters_m")) {
        v.fail(c.path_of("diameters_m"), "is missing: a curve needs its diameters");
        ok = false;
    }
    // Sizes that cannot be told apart make an interval whose grains have no
    // width to be drawn in (its number integral can round to zero).
    for (std::size_t k = 1; ok && k < g.diameters_m.size(); ++k)
        if (g.diameters_m[k] < min_grain_size_ratio * g.diameters_m[k - 1]) {
            v.fail(index_path(c.path_of("diameters_m"), k),
                exact_number(g.diameters_m[k]) + " is within 0.1 % of the previous size " + exact_number(g.diameters_m[k - 1])
                    + "; sizes of a curve must differ by more than that");
            ok = false;
        }
    // The fractions: numbers in [0, 1], nondecreasing, one per diameter,
    // from 0 (nothing passes the smallest size: it bounds the grains) to 1.
    const std::string fpath = c.path_of("fraction_passing");
    const json::value* f = c.take("fraction_passing");
    if (f == nullptr) {
        v.fail(fpath, "is missing: a curve needs the fraction passing each diameter");
        ok = false;
    } else if (!f->is_array()) {
        v.fail(fpath, "expected an array, got " + std::string(kind_text(*f)));
        ok = false;
    } else {
        const json::array& a = f->get_array();
        const Range unit = closed(0.0, 1.0);
        bool values_ok = true;
        for (std::size_t i = 0; i < a.size(); ++i) {
            double x = 0.0;
            if (!read_number(v, a[i], index_path(fpath, i), unit, x)) {
                values_ok = false;
                continue;
            }
            if (values_ok && i > 0 && x < g.fraction_passing.back()) {
                v.fail(index_path(fpath, i), exact_number(x) + " is less than the previous entry "
                                                 + exact_number(g.fraction_passing.back())
                                                 + "; the fraction passing must not decrease with size");
                values_ok = false;
            }
            g.fraction_passing.push_back(x);
        }
        if (values_ok && !a.empty() && g.fraction_passing.front() != 0.0) {
            v.fail(index_path(fpath, 0), exact_number(g.fraction_passing.front())
                                             + " is not 0: the smallest diameter bounds the grains, so nothing passes it "
                                               "(add the size below which there are no grains, with 0)");
            values_ok = false;
        }
        if (values_ok && !a.empty() && g.fraction_passing.back() != 1.0) {
            v.fail(index_path(fpath, a.size() - 1), exact_number(g.fraction_passing.back())
                                                        + " is not 1: every grain passes the largest diameter");
            values_ok = false;
        }
        if (ok && a.size() != g.diameters_m.size()) {
            v.fail(fpath, "has " + std::to_string(a.size()) + " entries for " + std::to_string(g.diameters_m.size())
                              + " diameters; give one fraction per diameter");
            values_ok = false;
        }
        ok = ok && values_ok;
    }
    c.finish();
    if (ok) out = std::move(g);
}

constexpr std::size_t max_clump_spheres = 32;
/// The smallest sphere of a clump against its largest: a smaller one would
/// set the time step without shaping the grain.
constexpr double min_clump_radius_ratio = 0.1;

/// specimen.grain_shape: null (or absent: spheres), or {"template": name}
/// or {"spheres": [[x, y, z, r], …]}. Described in one schema entry.
void read_grain_shape(ObjectReader& r, std::optional<GrainShapeSpec>& out)
{
    Validator& v = r.validator();
    const std::string_view key = "grain_shape";
    if (v.recording()) {
        json::array names;
        for (const std::string_view name : engine::builtin_clump_names) names.push_back(json::string(name));
        json::object sphere{{"type", "array"}, {"items", json::object{{"type", "number"}}}, {"minItems", 4},
            {"maxItems", 4}, {"description", "x, y, z of the centre and the radius, in any one length unit"}};
        json::object shape{{"type", json::array{"object", "null"}}, {"default", nullptr},
            {"properties",
                json::object{{"template", json::object{{"type", "string"}, {"enum", std::move(names)},
                                              {"description", "a built-in clump (docs/model.md, \"Clumps\")"}}},
                    {"spheres", json::object{{"type", "array"}, {"items", std::move(sphere)}, {"minItems", 2},
                                    {"maxItems", max_clump_spheres},
                                    {"description", "the clump's spheres; their union is one connected body, every "
                                                    "radius at least a tenth of the largest"}}}}},
            // One of the two, never both (the reader refuses both and neither);
            // the web form clears the other when one is given.
            {"minProperties", 1}, {"maxProperties", 1}, {"additionalProperties", false}};
        r.describe(key, std::move(shape),
            {nullptr, "every grain a rigid clump of overlapping spheres: {\"template\": \"elongated\", \"flat\", \"tetrahedral\" or \"crushed\"} or {\"spheres\": [[x, y, z, r], …]}, scaled to the grain's size as its volume-equivalent radius and poured turned at random (docs/model.md, \"Clumps\"); null: spheres"});
    }
    const json::value* j = r.take(key);
    if (j == nullptr || j->is_null()) return;
    const std::string path = r.path_of(key);
    if (!j->is_object()) {
        v.fail(path, "expected an object or null, got " + std::string(kind_text(*j)));
        return;
    }
    ObjectReader c(v, j, path);
    GrainShapeSpec g;
    bool ok = true;
    const json::value* name = c.take("template");
    const json::value* spheres = c.take("spheres");
    c.finish();
    if ((name == nullptr) == (spheres == nullptr)) {
        v.fail(path, name == nullptr ? "needs \"template\" or \"spheres\"" : "has both \"template\" and \"spheres\"; give one");
        return;
    }
    if (name != nullptr) {
        std::string allowed;
        for (const std::string_view n : engine::builtin_clump_names) allowed += (allowed.empty() ? "\"" : ", \"") + std::string(n) + "\"";
        if (!name->is_string()) {
            v.fail(c.path_of("template"), "expected a string, got " + std::string(kind_text(*name)));
            return;
        }
        g.template_name.assign(name->get_string().data(), name->get_string().size());
        if (!engine::builtin_clump_template(g.template_name)) {
            v.fail(c.path_of("template"), "\"" + g.template_name + "\" is not one of " + allowed);
            return;
        }
        out = std::move(g);
        return;
    }
    const std::string spath = c.path_of("spheres");
    if (!spheres->is_array()) {
        v.fail(spath, "expected an array, got " + std::string(kind_text(*spheres)));
        return;
    }
    const json::array& a = spheres->get_array();
    if (a.size() < 2 || a.size() > max_clump_spheres) {
        v.fail(spath, "has " + std::to_string(a.size()) + " spheres; a clump has 2 to " + std::to_string(max_clump_spheres)
                          + " (one sphere is the default grain: leave grain_shape out)");
        return;
    }
    const Range coordinate = closed(-1e6, 1e6), radius = open_closed(0.0, 1e6);
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string at = index_path(spath, i);
        if (!a[i].is_array() || a[i].get_array().size() != 4) {
            v.fail(at, "expected [x, y, z, radius], got " + std::string(a[i].is_array() ? "an array of another length" : kind_text(a[i])));
            ok = false;
            continue;
        }
        std::array<double, 4> s{};
        for (std::size_t k = 0; k < 4; ++k)
            ok = read_number(v, a[i].get_array()[k], index_path(at, k), k < 3 ? coordinate : radius, s[k]) && ok;
        g.spheres.push_back(s);
    }
    if (!ok) return;
    double largest = 0.0;
    for (const auto& s : g.spheres) largest = std::max(largest, s[3]);
    for (std::size_t i = 0; i < g.spheres.size(); ++i)
        if (g.spheres[i][3] < min_clump_radius_ratio * largest) {
            v.fail(index_path(index_path(spath, i), 3), exact_number(g.spheres[i][3]) + " is below "
                + exact_number(min_clump_radius_ratio) + " × the largest radius " + exact_number(largest)
                + "; so small a sphere would set the time step without shaping the grain");
            ok = false;
        }
    // One rigid body: every sphere reached from the first through spheres that overlap or touch.
    std::vector<char> reached(g.spheres.size(), 0);
    reached[0] = 1;
    for (bool grew = true; grew;) {
        grew = false;
        for (std::size_t i = 0; i < g.spheres.size(); ++i)
            for (std::size_t j = 0; j < g.spheres.size(); ++j) {
                if (!reached[i] || reached[j]) continue;
                const auto& p = g.spheres[i];
                const auto& q = g.spheres[j];
                const double d = std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
                if (d <= p[3] + q[3]) reached[j] = 1, grew = true;
            }
    }
    for (std::size_t i = 0; i < g.spheres.size() && ok; ++i)
        if (!reached[i]) {
            v.fail(index_path(spath, i), "touches no sphere connected to the first: a clump's spheres must form one body");
            ok = false;
        }
    if (ok) out = std::move(g);
}

void read_specimen(ObjectReader& r, SpecimenSpec& s)
{
    r.number("membrane_radius_m", open_closed(0.0, 1.0), s.membrane_radius_m,
        {"m", "R, radius of the membrane cylinder"});
    r.number("membrane_height_m", open_closed(0.0, 10.0), s.membrane_height_m,
        {"m", "H_m, height of the membrane"});
    r.integer("grain_count", IntRange{1, 100'000'000}, s.grain_count,
        {"1", "N_p. Not the paper's 1000, which fills only a few percent of the column (model spec §8)"});
    // From 10 µm down, adhesion, which the contact law leaves out, grows
    // comparable to the contact forces a confining pressure of 10 kPa makes
    // (pull-off 1.5 π γ r against 4 p r², γ ≈ 0.05 J/m²); far below, r³
    // (a grain's volume, the column's fill) underflows to zero.
    r.number("grain_radius_m", closed(1e-5, 0.1), s.grain_radius_m,
        {"m", "r_p, mean grain radius; not below 10 µm, where adhesion (not modelled) matters"});
    r.number("grain_radius_spread", closed_open(0.0, 0.5), s.grain_radius_spread,
        {"1", "s: radii uniform in r_p·(1 ± s); 0 = monodisperse"});
    read_grain_sizes(r, s.grain_sizes);
    read_grain_shape(r, s.grain_shape);
    r.choice("grain_preset", grain_presets, s.grain_preset,
        {nullptr, "a named grain: gravel, a crushed gravel 8/32 (the crushed clump, its sieve curve scaled so that D50 = 2 grain_radius_m, μ = 0.6 and rolling resistance calibrated against its angle of repose: docs/model.md, \"A calibrated gravel\"); it sets specimen.grain_sizes, specimen.grain_shape, contact.friction_coeff, contact.rolling_friction_coeff and contact.rolling_damping_ratio, which must then be left out, as must grain_radius_spread; none: the fields as given. Written to the job file only when set"});
    // A curve gives every size: a radius or spread beside it would be ignored.
    if (s.grain_sizes)
        for (const std::string_view key : {"grain_radius_m", "grain_radius_spread"})
            if (r.take(key) != nullptr)
                r.validator().fail(r.path_of(key), "is given with " + r.path_of("grain_sizes")
                                                       + ", which sets every grain's size; leave one of the two out");
    {
        ObjectReader g(r.validator(), r.take("grain"), r.path_of("grain"));
        read_grain(g, s.grain);
        g.finish();
    }
    {
        ObjectReader p(r.validator(), r.take("plate"), r.path_of("plate"));
        read_plate(p, s.plate);
        p.finish();
    }
    {
        ObjectReader w(r.validator(), r.take("wire"), r.path_of("wire"));
        read_wire(w, s.wire);
        w.finish();
    }
    {
        ObjectReader m(r.validator(), r.take("membrane"), r.path_of("membrane"));
        read_membrane(m, s.membrane);
        m.finish();
    }
    {
        ObjectReader p(r.validator(), r.take("pouring"), r.path_of("pouring"));
        read_pouring(p, s.pouring);
        p.finish();
    }
}

void read_contact(ObjectReader& r, ContactSpec& c)
{
    Validator& v = r.validator();
    const Range damping_range = closed(0.0, 1.0), restitution_range = open_closed(0.0, 1.0),
                reference_speed_range = open_closed(0.0, 100.0);
    if (v.recording()) {
        const NormalRestitution e;
        r.describe("normal_damping_s", json::object{{"type", "number"}, {"minimum", damping_range.lo}, {"maximum", damping_range.hi}},
            {"s", "γ_n in F_n = (4/3) E* √R* (ξ^{3/2} + γ_n √ξ dξ/dt)"});
        r.describe("restitution", with_default(number_schema(restitution_range), e.restitution),
            {"1", "e_n, coefficient of normal restitution"});
        r.describe("restitution_reference_speed_m_per_s",
            with_default(number_schema(reference_speed_range), e.restitution_reference_speed_m_per_s),
            {"m/s", "impact speed at which e_n holds (for this law e_n varies weakly with speed)"});
    }
    const json::value* damping = r.take("normal_damping_s");
    const json::value* restitution = r.take("restitution");
    const json::value* reference_speed = r.take("restitution_reference_speed_m_per_s");
    // γ_n in seconds, or e_n from which γ_n is derived (the model spec §3): one form only.
    if (damping != nullptr && restitution != nullptr)
        v.fail(r.path_of("normal_damping_s"), "both " + r.path_of("normal_damping_s") + " and "
                                                  + r.path_of("restitution")
                                                  + " are given; give one (γ_n directly, or e_n to derive γ_n from)");
    else if (damping != nullptr && reference_speed != nullptr)
        v.fail(r.path_of("restitution_reference_speed_m_per_s"),
            "applies to " + r.path_of("restitution") + " only, but the damping is given as "
                + r.path_of("normal_damping_s"));

    NormalDampingTime time;
    if (damping != nullptr) read_number(v, *damping, r.path_of("normal_damping_s"), damping_range, time.normal_damping_s);
    NormalRestitution e;
    if (restitution != nullptr) read_number(v, *restitution, r.path_of("restitution"), restitution_range, e.restitution);
    if (reference_speed != nullptr)
        read_number(v, *reference_speed, r.path_of("restitution_reference_speed_m_per_s"), reference_speed_range,
            e.restitution_reference_speed_m_per_s);
    if (damping != nullptr)
        c.normal_damping = time;
    else
        c.normal_damping = e;

    r.number("tangential_stiffness_per_m", open_closed(0.0, 1e9), c.tangential.stiffness_per_m,
        {"1/m", "k_t in F_t = −k_t F_n δ_t (the paper's reading, model spec §8)"});
    r.number("friction_coeff", closed(0.0, 10.0), c.tangential.friction_coeff,
        {"1", "μ, Coulomb friction coefficient of the contacts"});
    r.number("critical_slip_m", open_closed(0.0, 1.0), c.tangential.critical_slip_m,
        {"m", "d_cr, the spring breaks beyond this slip"});
    r.number("tangential_damping_s_per_m", closed(0.0, 1e9), c.tangential.damping_s_per_m,
        {"s/m", "γ_t: sliding force F_n·min(μ, γ_t·|v_t|) (engine/laws/tangential.hpp)"});
    // Rolling resistance, type C of Ai et al. (2011): engine/laws/rolling.hpp.
    // f_r ≤ 1 keeps the rolling spring's frequency below the tangential
    // spring's, and η_r ≤ 0.3 the damping within what Gear-5 was measured to
    // follow at the auto step (docs/model.md, "Rolling resistance").
    r.number("rolling_friction_coeff", closed(0.0, 1.0), c.rolling.friction_coeff,
        {"1", "μ_r: the rolling torque is at most μ_r R* F_n (a ball holds on an incline up to tan β = μ_r); 0 = no rolling resistance"});
    r.number("rolling_stiffness_factor", open_closed(0.0, 1.0), c.rolling.stiffness_factor,
        {"1", "f_r: rolling stiffness k_r = f_r k_t F_n R*² (Ai et al.'s k_r = k_t R*² at 1)"});
    r.number("rolling_damping_ratio", closed(0.0, 0.3), c.rolling.damping_ratio,
        {"1", "η_r: viscous rolling torque 2 η_r √(I_r k_r) ω_r below the limit torque"});
}

/// triaxial.plate_speed_m_per_s: a number (every test), or an array with
/// one speed per confining pressure (read before it).
void read_plate_speeds(ObjectReader& r, TriaxialSpec& t)
{
    const std::string_view key = "plate_speed_m_per_s";
    const Range range = open_closed(0.0, 10.0);
    if (r.validator().recording()) {
        json::object per_test{{"type", "array"}, {"items", number_schema(range)}, {"minItems", 1},
            {"maxItems", max_pressures}};
        r.describe(key,
            json::object{{"oneOf", json::array{number_schema(range), std::move(per_test)}},
                {"default", t.plate_speeds_m_per_s.front()}},
            {"m/s", "v_z of the top plate: one speed for every test, or one per test in the order of "
                    "confining_pressures_pa (slower at the low pressures keeps them quasi-static at the same cost "
                    "elsewhere: docs/model.md, \"Quasi-static scaling\"); each test's summary states its speed"});
    }
    const json::value* j = r.take(key);
    if (j == nullptr) return;
    Validator& v = r.validator();
    const std::string path = r.path_of(key);
    if (!j->is_array()) {
        double speed = 0.0;
        if (read_number(v, *j, path, range, speed)) t.plate_speeds_m_per_s = {speed};
        return;
    }
    const json::array& a = j->get_array();
    const std::size_t tests = t.confining_pressures_pa.size();
    bool ok = true;
    // Without valid pressures the count cannot be checked: the speeds are
    // still read for their own errors, but not kept (the spec is refused).
    const bool pressures_valid = v.clean(r.path_of("confining_pressures_pa"));
    if (pressures_valid && a.size() != tests) {
        v.fail(path, "has " + std::to_string(a.size()) + (a.size() == 1 ? " entry" : " entries")
                         + "; give one speed per confining pressure (" + std::to_string(tests)
                         + "), or a number for every test");
        ok = false;
    }
    ok = ok && pressures_valid;
    std::vector<double> speeds(a.size(), 0.0);
    for (std::size_t i = 0; i < a.size(); ++i) ok = read_number(v, a[i], index_path(path, i), range, speeds[i]) && ok;
    if (ok) t.plate_speeds_m_per_s = std::move(speeds);
}

void read_triaxial(ObjectReader& r, TriaxialSpec& t)
{
    read_increasing_numbers(r, "confining_pressures_pa", open_closed(0.0, 1e7), 1, max_pressures, "the pressures",
        t.confining_pressures_pa,
        {"Pa", "σ_3 of each test"});
    r.number("target_axial_strain", open_closed(0.0, 0.5), t.target_axial_strain,
        {"1", "a test ends at this ε_a"});
    read_plate_speeds(r, t);
    r.number("pressure_ramp_time_s", closed(0.0, 1e3), t.pressure_ramp_time_s,
        {"s", "σ_3 rises linearly from 0 over this time"});
    r.number("hold_time_s", closed(0.0, 1e3), t.hold_time_s,
        {"s", "σ_3 is then held at least this long before loading, while the top plate consolidates the column (triaxial.consolidation; docs/model.md)"});
    optional_number(r, "max_hold_time_s", closed(0.0, 1e3), t.max_hold_time_s,
        {"s", "the hold goes on past hold_time_s until the column has consolidated (σ_1 averaged over 5 ms within 5 % of its target, the top plate slower than the loading speed), at most this long; a warning says when that was not enough"});
    r.choice("consolidation", consolidations, t.consolidation,
        {nullptr, "what the top plate brings σ_1 to while σ_3 ramps and holds: cell_pressure, σ_1 = σ_3 (the cell pressure on the cap); effective, σ_1 = σ_3,eff, the lateral stress the column feels (membrane included), so loading starts from η ≈ 0 and the column is not driven into extension; a column the membrane does not touch (σ_3,eff = 0) is brought to σ_3 instead, with a warning (docs/model.md, \"Consolidation\"; the study of docs/study.md ran with cell_pressure)"});
    r.number("sample_interval_s", open_closed(0.0, 1e3), t.sample_interval_s,
        {"s", "time between samples of the test record"});
    // The default snapshots follow the target; a given list is checked
    // against the target by the cross-field checks.
    if (r.validator().clean(r.path_of("target_axial_strain")))
        t.snapshot_strains = {0.0, 0.5 * t.target_axial_strain, t.target_axial_strain};
    read_increasing_numbers(r, "snapshot_strains", closed(0.0, 0.5), 0, max_snapshots, "the snapshot strains",
        t.snapshot_strains,
        {"1", "axial strains at which the wire elongation profile and the force network are saved; the default follows the target"});
    r.choice("cell", cell_kinds, t.cell,
        {nullptr, "the triaxial cell: membrane, the poured column in the pressurised membrane (the model spec §6); cuboid, a box of six rigid walls, the grains placed at random in a loose box and compacted by its servo walls to the lowest confining pressure, then tested with four servo walls holding σ_3 and the top at the plate speed (docs/model.md, \"The rigid-wall cell\"). The cuboid cell takes no wire (specimen.wire.pattern \"none\") and no free-standing test; clumps (specimen.grain_shape, the gravel preset) are placed in the loose box where their bounding spheres are free, turned at random; specimen.membrane_* and specimen.pouring are checked as for the membrane cell but not used. Its tests keep checkpoints as the membrane cell's do; its preparation keeps none (a stopped preparation runs again, the same bits). Written to the job file only for the cuboid cell"});
    ObjectReader c(r.validator(), r.take("cuboid"), r.path_of("cuboid"));
    c.number("aspect_ratio", closed(0.25, 4.0), t.cuboid.aspect_ratio,
        {"1", "the cuboid cell's box: height over its square width when the grains are placed (the compaction is isotropic)"});
    c.number("wall_friction_coeff", closed(0.0, 10.0), t.cuboid.wall_friction_coeff,
        {"1", "μ_w of the cuboid cell's six walls (0: frictionless)"});
    optional_number(c, "compaction_friction_coeff", closed(0.0, 10.0), t.cuboid.compaction_friction_coeff,
        {"1", "μ between the grains while the box is compacted, which sets the packing's density (0: dense, near random close packing); contact.friction_coeff again for the tests; null (or absent) = contact.friction_coeff"});
    c.finish();
}

void read_free_standing(ObjectReader& r, FreeStandingSpec& f)
{
    if (r.validator().recording())
        r.describe("enabled", json::object{{"type", "boolean"}, {"default", f.enabled}},
            {nullptr, "run the free-standing test after the triaxial tests: the formwork removed, the column settled on the bottom plate, an optional dead load, unconfined compression (docs/model.md, \"The free-standing test\")"});
    if (const json::value* j = r.take("enabled")) {
        if (j->is_bool())
            f.enabled = j->get_bool();
        else
            r.validator().fail(r.path_of("enabled"), "expected true or false, got " + std::string(kind_text(*j)));
    }
    r.number("removal_time_s", open_closed(0.0, 1e3), f.removal_time_s,
        {"s", "the formwork (the membrane's radius) opens over this time: slowly enough that the column gets no kick (its kinetic energy stays below 2 M v², v = removal_distance_m / removal_time_s); a release like the collapse experiments' is of order √(h/g) or less"});
    r.number("removal_distance_m", open_closed(0.0, 1.0), f.removal_distance_m,
        {"m", "how far the membrane's radius opens, and the top plate rises, before the formwork is gone; more than the column's elastic expansion"});
    optional_number(r, "escape_distance_m", open_closed(0.0, 100.0), f.escape_distance_m,
        {"m", "a grain whose centre is farther than this from the axis has left the column; more than specimen.membrane_radius_m; null (or absent) = 1.5 × it"});
    r.number("settle_kinetic_energy_per_grain_j", open_closed(0.0, 1.0), f.settle_kinetic_energy_per_grain_j,
        {"J", "the free column is at rest when the mean kinetic energy per grain of the standing column (its grains within "
              "escape_distance_m of the axis, and the wire) is below this (the preparation's criterion; a grain that left the "
              "column is counted as lost, not waited for: docs/model.md, \"The free-standing test\")"});
    r.number("max_settling_time_s", open_closed(0.0, 1e4), f.max_settling_time_s,
        {"s", "settling ends here at the latest (a warning says the column was not at rest). Under mass scaling the settling "
              "is √engine.density_scale slower than a real column's (s = 100: 5 s here is 0.5 s of a real slump)"});
    r.number("max_height_loss", open_open(0.0, 1.0), f.max_height_loss,
        {"1", "the column stands when it came to rest having lost at most this fraction of its grains' bulk height (bulk_fraction; not the top of its highest grain or wire node, which a wire left standing keeps), and at most max_lost_fraction of its grains"});
    r.number("bulk_fraction", closed(0.5, 1.0), f.bulk_fraction,
        {"1", "q of the grains' bulk height z_q / q, z_q the height below which this share of the standing grains' volume lies: a uniform column reads its height, the grains above the bulk that hold less than 1 - q of the volume (caught in a wire left standing) do not raise it (docs/model.md, \"What stands\"); 1: the top of the highest grain"});
    r.number("max_lost_fraction", closed_open(0.0, 1.0), f.max_lost_fraction,
        {"1", "the column stands only if at most this share of its grains' volume ended farther than escape_distance_m from the axis"});
    optional_number(r, "dead_load_n", open_closed(0.0, 1e9), f.dead_load_n,
        {"N", "a constant force on the top plate after settling, held for dead_load_hold_time_s: does the column hold, how much does it creep; null (or absent) = none"});
    r.number("dead_load_ramp_time_s", closed(0.0, 1e3), f.dead_load_ramp_time_s,
        {"s", "the dead load rises over this time as ½(1 − cos πt/T)"});
    r.number("dead_load_hold_time_s", open_closed(0.0, 1e3), f.dead_load_hold_time_s,
        {"s", "the dead load is then held this long"});
    optional_number(r, "pull_out_speed_m_per_s", open_closed(0.0, 10.0), f.pull_out_speed_m_per_s,
        {"m/s", "pull the wire out after settling, instead of the dead load and the compression: one end node driven at this speed along pull_out_direction (the force it takes, the wire and grains left in the column; docs/model.md, \"Pulling the wire out\"); needs a wire; not with dead_load_n; null (or absent) = no pull-out"});
    r.choice("pull_out_end", wire_ends, f.pull_out_end,
        {nullptr, "the end pulled: last, the last node laid (the top of a printed column), or first (the bottom)"});
    read_numbers(r, "pull_out_direction", closed(-1.0, 1.0), 3, 3, f.pull_out_direction,
        {"1", "the direction of the pull [x, y, z] in the column's frame, normalised; not all zero; [0, 0, 1]: upward along the axis"});
    r.number("pull_out_ramp_time_s", closed(0.0, 1e3), f.pull_out_ramp_time_s,
        {"s", "the pull's speed rises over this time as ½(1 − cos πt/T): a wire set moving in one step takes the impulse of its axial wave"});
    optional_number(r, "pull_out_length_m", open_closed(0.0, 1e3), f.pull_out_length_m,
        {"m", "the pull ends after pulling the end this far; null (or absent) = when the pulled piece of wire has left the settled column (no segment of it within escape_distance_m of the axis and below the settled height)"});
    r.number("pull_out_max_time_s", open_closed(0.0, 1e4), f.pull_out_max_time_s,
        {"s", "the pull ends here at the latest (a warning says when the length or the wire's exit was not reached)"});
    r.number("plate_speed_m_per_s", open_closed(0.0, 10.0), f.plate_speed_m_per_s,
        {"m/s", "the top plate's speed in the unconfined compression"});
    r.number("target_axial_strain", open_closed(0.0, 0.5), f.target_axial_strain,
        {"1", "the compression ends at this ε_a at the latest"});
    r.number("failure_drop", open_closed(0.0, 1.0), f.failure_drop,
        {"1", "the column has failed, and the compression ends, when σ_1 (averaged over 0.5 % of strain) has stayed below (1 − this) of its largest such average for 2 % of strain; 1: compress to the target"});
    r.number("sample_interval_s", open_closed(0.0, 1e3), f.sample_interval_s,
        {"s", "time between samples of the test record"});
}

void read_engine(ObjectReader& r, EngineSpec& e)
{
    const Range time_step_range = open_closed(0.0, 1e-3);
    if (r.validator().recording())
        r.describe("time_step_s",
            json::object{{"oneOf", json::array{number_schema(time_step_range), json::object{{"const", "auto"}}}},
                {"default", e.time_step_s ? json::value(*e.time_step_s) : json::value("auto")}},
            {"s", "δt; \"auto\" uses engine::auto_time_step_fraction (0.5) × the undamped critical step, and at most the critical step with the contacts' and the wire's damping (auto_s of engine::stable_time_step)"});
    if (const json::value* j = r.take("time_step_s")) {
        const std::string path = r.path_of("time_step_s");
        if (j->is_string()) {
            const json::string& s = j->get_string();
            if (s != "auto") r.validator().fail(path, "\"" + std::string(s.data(), s.size()) + "\" is neither \"auto\" nor a number");
        } else if (number_of(*j)) {
            double dt = 0.0;
            if (read_number(r.validator(), *j, path, time_step_range, dt)) e.time_step_s = dt;
        } else {
            r.validator().fail(path, "expected a number or \"auto\", got " + std::string(kind_text(*j)));
        }
    }
    r.choice("integrator", integrators, e.integrator,
        {nullptr, "Gear-5 predictor–corrector (reference) or velocity Verlet"});
    r.integer("threads", IntRange{0, 256}, e.threads,
        {"1", "worker threads; 0 = all cores. Results do not depend on it"});
    r.number("density_scale", closed(1.0, 1e6), e.density_scale,
        {"1", "s, mass scaling: every mass (grains, wire and membrane nodes) is multiplied by it; inertia only, weights stay real (gravity g/s on the scaled masses in the test; docs/model.md, \"Quasi-static scaling\"); δt grows as its square root"});
    r.number("wire_mass_scale", closed(1.0, 1e6), e.wire_mass_scale,
        {"1", "M, extra inertia of the wire nodes (masses s·M times the model's), weights unchanged: lifts the δt set by the wire's axial springs. The membrane's nodes take s only"});
    // 1e9 < 2^30: every body index fits a BodyRef (engine/core/types.hpp).
    r.integer("max_bodies", IntRange{1, 1'000'000'000}, e.max_bodies,
        {"1", "refuse jobs whose estimated body count exceeds this"});
}

/// specimen.grain_preset: the fields it names filled from the preset
/// (api/grain_presets.hpp), each of them refused when the document gives it
/// too (a value beside the preset's would leave the job two answers), and
/// its sieve curve scaled so that its D50 is 2 specimen.grain_radius_m.
void apply_grain_preset(Validator& v, const json::value& doc, JobSpec& spec)
{
    const GrainPresetValues* p = grain_preset_values(spec.specimen.grain_preset);
    if (p == nullptr || !v.clean("specimen.grain_preset")) return;
    const auto given = [&](std::string_view object, std::string_view key) {
        if (!doc.is_object()) return false;
        const json::value* o = doc.get_object().if_contains(object);
        return o != nullptr && o->is_object() && o->get_object().contains(key);
    };
    bool ok = true;
    for (const auto& [object, key] : std::initializer_list<std::pair<std::string_view, std::string_view>>{
             {"specimen", "grain_sizes"}, {"specimen", "grain_shape"}, {"specimen", "grain_radius_spread"},
             {"contact", "friction_coeff"}, {"contact", "rolling_friction_coeff"}, {"contact", "rolling_damping_ratio"}})
        if (given(object, key)) {
            v.fail(join_path(object, key), "is given with specimen.grain_preset \"" + std::string(p->name)
                                               + "\", which sets it; leave one of the two out");
            ok = false;
        }
    if (!ok || !v.clean("specimen.grain_radius_m")) return;
    // The lab's curve scaled to the column: its D50 (linear in log D, as the
    // engine reads a curve) becomes 2 r_p.
    engine::SieveCurve lab;
    lab.diameters_m.assign(p->sieve_mm.begin(), p->sieve_mm.end());
    lab.fraction_passing.assign(p->fraction_passing.begin(), p->fraction_passing.end());
    const double scale = 2.0 * spec.specimen.grain_radius_m / engine::GrainSizeDistribution(lab).diameter_at_mass_fraction(0.5);
    GrainSizesSpec sizes;
    for (const double d : p->sieve_mm) sizes.diameters_m.push_back(d * scale);
    sizes.fraction_passing = lab.fraction_passing;
    if (!grain_diameter_range.contains(sizes.diameters_m.front()) || !grain_diameter_range.contains(sizes.diameters_m.back())) {
        v.fail("specimen.grain_radius_m", "with specimen.grain_preset \"" + std::string(p->name) + "\" the grains span "
            + exact_number(sizes.diameters_m.front()) + " to " + exact_number(sizes.diameters_m.back())
            + " m in diameter (the preset's curve scaled to D50 = 2 grain_radius_m), beyond a curve's "
            + grain_diameter_range.text());
        return;
    }
    spec.specimen.grain_sizes = std::move(sizes);
    spec.specimen.grain_shape = GrainShapeSpec{std::string(p->clump_template), {}};
    spec.contact.tangential.friction_coeff = p->friction_coeff;
    spec.contact.rolling.friction_coeff = p->rolling_friction_coeff;
    spec.contact.rolling.damping_ratio = p->rolling_damping_ratio;
}

void read_job(Validator& v, const json::value& doc, JobSpec& spec)
{
    ObjectReader r(v, &doc, "");
    // The document's format (job_spec_schema_version): read, checked, and not
    // kept (to_json writes today's). A user writes today's format; a stored
    // document without it was written before the field (version 1). A trusted
    // reader takes any range but cannot read a future format either.
    std::uint64_t version = v.trusted() ? 1 : job_spec_schema_version;
    r.integer("schema_version", IntRange{1, job_spec_schema_version}, version,
        {"1", "the version of the document's format (api::job_spec_schema_version); wiredem writes it first in every "
              "job it stores and reads a stored job without it as version 1; a version above the reader's is refused"});
    if (v.clean("schema_version") && version > job_spec_schema_version)
        v.fail("schema_version", std::to_string(version) + " is newer than this wiredem reads (1 to "
                                     + std::to_string(job_spec_schema_version) + "): a newer wiredem wrote this job");
    r.text("name", spec.name,
        {nullptr, "label of the job"});
    if (v.recording())
        r.describe("name", json::object{{"type", "string"}, {"maxLength", max_name_chars}, {"default", spec.name}},
            {nullptr, "label of the job"});
    if (v.clean("name")) {
        const std::size_t n = utf8_length(spec.name);
        if (n > max_name_chars)
            v.fail("name", "is " + std::to_string(n) + " characters long; at most " + std::to_string(max_name_chars)
                               + " are allowed");
        if (has_control_character(spec.name))
            v.fail("name", "contains a control character; the name must be a single line of text");
    }
    r.text("comment", spec.comment, {nullptr, "free text"});
    if (v.recording())
        r.describe("comment", json::object{{"type", "string"}, {"maxLength", max_comment_chars}, {"default", spec.comment}},
            {nullptr, "free text"});
    if (v.clean("comment"))
        if (const std::size_t n = utf8_length(spec.comment); n > max_comment_chars)
            v.fail("comment", "is " + std::to_string(n) + " characters long; at most " + std::to_string(max_comment_chars)
                                  + " are allowed");
    r.integer("seed", IntRange{0, UINT64_MAX}, spec.seed,
        {"1", "seed of the pouring (reproducible preparation)"});
    {
        ObjectReader s(v, r.take("specimen"), "specimen");
        read_specimen(s, spec.specimen);
        s.finish();
    }
    {
        ObjectReader c(v, r.take("contact"), "contact");
        read_contact(c, spec.contact);
        c.finish();
    }
    apply_grain_preset(v, doc, spec);
    {
        ObjectReader t(v, r.take("triaxial"), "triaxial");
        read_triaxial(t, spec.triaxial);
        t.finish();
    }
    {
        ObjectReader f(v, r.take("free_standing"), "free_standing");
        read_free_standing(f, spec.free_standing);
        f.finish();
    }
    {
        ObjectReader e(v, r.take("engine"), "engine");
        read_engine(e, spec.engine);
        e.finish();
    }
    r.finish();
}

// ------------------------------------------------------- cross-field checks

/// The fields that set the grains' sizes (a curve, or a radius and spread).
const std::initializer_list<std::string_view> grain_size_fields{
    "specimen.grain_radius_m", "specimen.grain_radius_spread", "specimen.grain_sizes"};

void check_grain_size(Validator& v, const JobSpec& spec)
{
    if (!v.clean(grain_size_fields) || !v.clean("specimen.membrane_radius_m")) return;
    const SpecimenSpec& s = spec.specimen;
    const double largest_m = engine::largest_grain_radius_m(preparation_geometry(spec));
    const double limit_m = s.membrane_radius_m / min_column_grain_diameters;
    if (largest_m <= limit_m) return;
    // A clump reaches beyond its volume-equivalent radius: say by how much,
    // or a size below the limit would read as refused for nothing.
    const double plain_m = s.grain_sizes ? 0.5 * s.grain_sizes->diameters_m.back() : s.grain_radius_m * (1.0 + s.grain_radius_spread);
    const std::string clump = s.grain_shape ? "; the clump of specimen.grain_shape reaches " + format_number(largest_m / plain_m)
            + " × the grain's radius from its centre, so the largest grain spans " + format_number(2.0 * largest_m)
                                            : std::string();
    // A preset's curve is scaled from grain_radius_m: that is the field to change.
    const bool preset = s.grain_preset != GrainPreset::none;
    if (s.grain_sizes)
        v.note(preset ? "specimen.grain_radius_m" : "specimen.grain_sizes.diameters_m",
            std::string(preset ? "with specimen.grain_preset \"" + std::string(to_string(s.grain_preset)) + "\", " : "")
                + "the largest diameter " + exact_number(s.grain_sizes->diameters_m.back())
                + " is too big for the membrane: the column must be at least " + exact_number(min_column_grain_diameters)
                + " grain diameters wide, so it must not exceed 2 membrane_radius_m / "
                + exact_number(min_column_grain_diameters) + " = " + format_number(2.0 * limit_m) + clump);
    else
        v.note("specimen.grain_radius_m",
            exact_number(s.grain_radius_m) + " is too big for the membrane: the column must be at least "
                + exact_number(min_column_grain_diameters)
                + " grain diameters wide, so grain_radius_m × (1 + grain_radius_spread) must not exceed "
                  "membrane_radius_m / "
                + exact_number(min_column_grain_diameters) + " = " + format_number(limit_m) + clump);
}

void check_grain_volume(Validator& v, const JobSpec& spec)
{
    if (!v.clean({"specimen.grain_count", "specimen.grain_radius_m", "specimen.grain_radius_spread", "specimen.grain_sizes",
            "specimen.membrane_radius_m", "specimen.membrane_height_m"}))
        return;
    // The preparation's own requirement: the fill at the packing it paces
    // the pour by, and room above it to pour from.
    const SpecimenSpec& s = spec.specimen;
    const engine::PreparationSpec p = preparation_geometry(spec);
    const double needed_m = engine::required_membrane_height_m(p);
    if (needed_m > s.membrane_height_m)
        v.note("specimen.grain_count",
            std::to_string(s.grain_count) + " grains do not fit in the membrane: they fill about "
                + format_number(engine::estimated_fill_height_m(p)) + " m, and pouring needs 8 largest grain radii above "
                + "that: membrane_height_m must be at least " + format_number(needed_m) + ", not "
                + exact_number(s.membrane_height_m));
}

void check_wire_fits(Validator& v, const JobSpec& spec)
{
    const SpecimenSpec& s = spec.specimen;
    const WireSpec& w = s.wire;
    const std::string pattern(to_string(w.pattern));
    // Points with another pattern (none included) would be dropped on writing.
    if (v.clean("specimen.wire") && w.pattern != WirePattern::toolpath
        && (!w.toolpath_x_m.empty() || !w.toolpath_y_m.empty()))
        v.note("specimen.wire.toolpath_x_m", "toolpath points are for the pattern \"toolpath\", not \"" + pattern + "\"");
    if (w.pattern == WirePattern::none
        || !v.clean({"specimen.membrane_radius_m", "specimen.membrane", "specimen.wire"}))
        return;
    if (w.pattern == WirePattern::toolpath) {
        if (w.toolpath_x_m.size() != w.toolpath_y_m.size() || w.toolpath_x_m.size() < 2) {
            v.note("specimen.wire.toolpath_x_m",
                "the pattern \"toolpath\" needs at least 2 points, as many x (toolpath_x_m: "
                    + std::to_string(w.toolpath_x_m.size()) + ") as y (toolpath_y_m: " + std::to_string(w.toolpath_y_m.size()) + ")");
            return;
        }
        if (!(engine::NozzlePath(pattern_spec(w), 0.0).layer_length_m() > 0.0)) {
            v.note("specimen.wire.toolpath_x_m", "the toolpath's points are all in one place: a layer must have a length");
            return;
        }
    }
    if (w.pattern == WirePattern::spiral_helix && w.inner_radius_m >= w.helix_radius_m) {
        v.note("specimen.wire.inner_radius_m",
            exact_number(w.inner_radius_m) + " is not smaller than helix_radius_m " + exact_number(w.helix_radius_m)
                + ": the small circle of a spiral_helix must be smaller than the circle its centre travels on");
        return;
    }
    // The preparation's own rule for every pattern (engine::wire_reach_limit_m):
    // the pattern's reach (engine::pattern_reach_m: R_a, R_a + R_i, a
    // toolpath's farthest point) stays below R − r_m − r_w − clearance.
    const engine::PreparationSpec p = preparation_geometry(spec);
    const double limit_m = engine::wire_reach_limit_m(p);
    const double reach_m = engine::pattern_reach_m(p.pattern);
    if (reach_m < limit_m) return;
    const std::string limit_text = "membrane_radius_m " + exact_number(s.membrane_radius_m)
        + " − the membrane nodes' contact radius " + format_number(p.membrane.contact_radius_m) + " − wire.radius_m "
        + exact_number(w.radius_m) + " − wire.clearance_m " + exact_number(w.clearance_m) + " = " + format_number(limit_m);
    if (w.pattern == WirePattern::toolpath) {
        v.note("specimen.wire.toolpath_x_m", "the toolpath reaches " + format_number(reach_m)
                                                 + " m from the axis: its farthest point must stay below " + limit_text
                                                 + ", so every point within " + format_number(limit_m) + " m of the axis");
        return;
    }
    const bool spiral = w.pattern == WirePattern::spiral_helix;
    v.note("specimen.wire.helix_radius_m",
        exact_number(w.helix_radius_m) + " is too large for the membrane: a " + pattern + " needs helix_radius_m"
            + (spiral ? " + inner_radius_m" : "") + " < " + limit_text + ", so helix_radius_m < "
            + format_number(spiral ? limit_m - w.inner_radius_m : limit_m)
            + (spiral ? " with inner_radius_m " + exact_number(w.inner_radius_m) : std::string()));
}

void check_fill_rate(Validator& v, const JobSpec& spec)
{
    const SpecimenSpec& s = spec.specimen;
    if (!v.clean({"specimen.pouring", "specimen.wire", "specimen.grain_count", "specimen.grain_radius_m",
            "specimen.grain_radius_spread", "specimen.grain_sizes", "specimen.membrane_radius_m"}))
        return;
    const bool with_wire = s.wire.pattern != WirePattern::none;
    if (with_wire && s.wire.length_m && s.pouring.fill_rate_m_per_s) {
        v.note("specimen.wire.length_m", "set either specimen.wire.length_m or specimen.pouring.fill_rate_m_per_s: "
                                         "the fill rate sets the length of wire laid, and the length the fill rate");
        return;
    }
    const engine::PreparationSpec p = preparation_geometry(spec);
    if (with_wire && !(engine::wire_laying_height_m(p) > 0.0)) {
        // The fill height grows as the grain count: N C/H grains reach the cover.
        const double fill_m = engine::estimated_fill_height_m(p), cover_m = engine::wire_cover_height_m(p);
        v.note("specimen.grain_count",
            std::to_string(s.grain_count) + " grains fill about " + format_number(fill_m)
                + " m, not above the grains poured over the wire's end (one diameter of the largest grain, "
                + format_number(cover_m) + " m): the nozzle would lay no wire; with this membrane and these grains "
                + "grain_count must be at least "
                + format_number(std::floor(static_cast<double>(s.grain_count) * cover_m / fill_m) + 1.0));
        return;
    }
    const double fill_rate = p.fill_rate_m_per_s;
    // The nozzle follows the top of the pile at most v_z^w (the model spec §5).
    const double limit = engine::max_fill_rate_per_rise_speed * s.wire.nozzle_rise_speed_m_per_s;
    if (with_wire && fill_rate > limit) {
        if (s.wire.length_m) {
            // L = ω R_a t_lay: the shortest wire is laid at the fastest fill.
            const double shortest_m = *s.wire.length_m * fill_rate / limit;
            v.note("specimen.wire.length_m",
                exact_number(*s.wire.length_m) + " needs a fill rate of " + format_number(fill_rate)
                    + " m/s, faster than the nozzle can follow (at most " + exact_number(engine::max_fill_rate_per_rise_speed)
                    + " × specimen.wire.nozzle_rise_speed_m_per_s = " + format_number(limit)
                    + "): length_m must be at least " + format_number(shortest_m));
        } else {
            v.note("specimen.pouring.fill_rate_m_per_s",
                exact_number(fill_rate) + " is too fast for the nozzle, which rises at most "
                    + "specimen.wire.nozzle_rise_speed_m_per_s " + exact_number(s.wire.nozzle_rise_speed_m_per_s)
                    + " and must follow the pile's uneven top: fill_rate_m_per_s must not exceed "
                    + exact_number(engine::max_fill_rate_per_rise_speed) + " × that = " + format_number(limit));
        }
        return;
    }
    // The pour alone takes H_fill / v_fill; the preparation fails when it
    // runs past max_preparation_time_s, so say so now.
    const double pour_s = engine::estimated_fill_height_m(p) / fill_rate;
    if (!(pour_s < s.pouring.max_preparation_time_s))
        v.note("specimen.pouring.max_preparation_time_s",
            exact_number(s.pouring.max_preparation_time_s) + " is too short: pouring "
                + format_number(engine::estimated_fill_height_m(p)) + " m of fill at " + format_number(fill_rate)
                + " m/s" + (with_wire && s.wire.length_m ? " (the rate that lays specimen.wire.length_m)" : "")
                + " takes " + format_number(pour_s) + " s; max_preparation_time_s must exceed that, with time to settle");
}

void check_membrane_mesh(Validator& v, const JobSpec& spec)
{
    if (!v.clean(grain_size_fields) || !v.clean("specimen.membrane")) return;
    const SpecimenSpec& s = spec.specimen;
    // A sphere passes through a mesh triangle of edge l_m whose corners carry
    // spheres of radius r_m unless r_p + r_m > l_m/√3 (centroid to corner).
    const double smallest_m = engine::smallest_grain_radius_m(preparation_geometry(spec));
    const double contact_m = membrane_contact_radius_m(s.membrane);
    const double limit_m = std::numbers::sqrt3 * (smallest_m + contact_m);
    if (s.membrane.mesh_size_m >= limit_m)
        v.note("specimen.membrane.mesh_size_m",
            exact_number(s.membrane.mesh_size_m) + " is too coarse: the smallest grain (radius " + format_number(smallest_m)
                + ") would slip between membrane nodes of contact radius " + format_number(contact_m)
                + "; mesh_size_m must be below √3 (smallest grain radius + membrane contact radius) = "
                + format_number(limit_m));
}

void check_body_count(Validator& v, const JobSpec& spec)
{
    if (!v.clean({"specimen.grain_count", "specimen.grain_radius_m", "specimen.grain_radius_spread", "specimen.grain_sizes",
            "specimen.membrane_radius_m", "specimen.membrane_height_m", "specimen.membrane.mesh_size_m",
            "specimen.wire", "specimen.pouring", "engine.max_bodies"}))
        return;
    const BodyCounts n = estimated_body_counts(spec);
    if (n.total() > spec.engine.max_bodies)
        v.note("engine.max_bodies",
            "the job needs about " + std::to_string(n.total()) + " bodies (" + std::to_string(n.grains) + " grains, "
                + std::to_string(n.wire_nodes) + " wire nodes, " + std::to_string(n.membrane_nodes)
                + " membrane nodes), more than max_bodies " + std::to_string(spec.engine.max_bodies));
}

/// The engine's own rules for each test's settings (engine::settings_error,
/// engine::free_standing_settings_error), asked at the door so that an
/// accepted job's tests start.
void check_test_settings(Validator& v, const JobSpec& spec)
{
    if (!v.clean("triaxial")) return;
    for (std::size_t k = 0; k < spec.triaxial.confining_pressures_pa.size(); ++k) {
        const auto e = engine::settings_error(triaxial_settings(spec, k));
        if (!e) continue;
        const std::string field = e->field == "confining_pressure_pa"
            ? index_path("triaxial.confining_pressures_pa", k)
            : "triaxial." + e->field;
        v.note(field, e->message);
        return;
    }
    if (!spec.free_standing.enabled || !v.clean({"free_standing", "specimen.membrane_radius_m"})) return;
    if (spec.free_standing.pull_out_speed_m_per_s && spec.specimen.wire.pattern == WirePattern::none) {
        v.note("free_standing.pull_out_speed_m_per_s", "a pull-out needs a wire: specimen.wire.pattern is \"none\"");
        return;
    }
    if (const auto e = engine::free_standing_settings_error(free_standing_settings(spec))) {
        // The engine's dead_load.* are the job's dead_load_*, its pull_out.*
        // the job's pull_out_* (pull_out itself: the field that asks for it).
        std::string field = e->field;
        if (field.starts_with("dead_load.")) field = field == "dead_load.force_n" ? "dead_load_n" : "dead_load_" + field.substr(10);
        if (field == "pull_out") field = "pull_out_speed_m_per_s";
        if (field.starts_with("pull_out.")) field = "pull_out_" + field.substr(9);
        v.note(field == "snapshot_strains" ? "free_standing" : "free_standing." + field, e->message);
    }
}

/// estimated_work reads every test's pressure and plate speed, the
/// free-standing phases, the grains, the contact law (the auto step) and the
/// engine's scales: it runs only on a spec whose inputs to it are all valid.
bool work_inputs_clean(const Validator& v)
{
    return v.clean({"specimen", "contact", "triaxial", "free_standing", "engine"});
}

/// A record has at most a row a step: a sample interval shorter than the
/// step the job will run at would silently become "every step" (the run's
/// own step can still differ from this estimate; the test then says so in
/// a warning, engine::sample_interval_warning).
void check_sample_intervals(Validator& v, const JobSpec& spec)
{
    if (!work_inputs_clean(v)) return;
    const double dt = estimated_work(spec).time_step_s;
    const auto check = [&](const char* field, double interval_s) {
        if (interval_s >= dt) return;
        v.note(field, exact_number(interval_s) + " is shorter than the time step " + format_number(dt) + " s"
                          + (spec.engine.time_step_s ? " (engine.time_step_s)"
                                                     : " (the auto step, set by the " + stable_time_step(spec).limited_by + ")")
                          + ": a record has at most one row a step, so it must be at least that");
    };
    check("triaxial.sample_interval_s", spec.triaxial.sample_interval_s);
    if (spec.free_standing.enabled) check("free_standing.sample_interval_s", spec.free_standing.sample_interval_s);
}

void check_snapshots(Validator& v, const TriaxialSpec& t)
{
    if (!v.clean({"triaxial.target_axial_strain", "triaxial.snapshot_strains"})) return;
    for (std::size_t i = 0; i < t.snapshot_strains.size(); ++i)
        if (t.snapshot_strains[i] > t.target_axial_strain)
            v.note(index_path("triaxial.snapshot_strains", i),
                exact_number(t.snapshot_strains[i]) + " is beyond triaxial.target_axial_strain "
                    + exact_number(t.target_axial_strain));
}

void check_time_step(Validator& v, const JobSpec& spec)
{
    if (!spec.engine.time_step_s) return;
    if (!v.clean({"engine.time_step_s", "engine.density_scale", "engine.wire_mass_scale", "specimen.grain_radius_m",
            "specimen.grain_radius_spread", "specimen.grain_sizes", "specimen.grain", "specimen.plate", "specimen.wire", "specimen.membrane"}))
        return;
    const StableStep stable = stable_time_step(spec);
    const double dt = *spec.engine.time_step_s;
    if (dt > stable.critical_s)
        v.note("engine.time_step_s", exact_number(dt) + " exceeds the stable limit " + format_number(stable.critical_s)
                                         + " set by the " + stable.limited_by + " (\"auto\" would use "
                                         + format_number(stable.auto_s) + ")");
}

/// A damping given as γ_n that no explicit step can follow (engine::
/// min_damped_step_fraction); a restitution's is checked when the run starts
/// (its γ_n is a 50–250 ms fit, api/derived.hpp).
void check_damping(Validator& v, const JobSpec& spec)
{
    const auto* given = std::get_if<NormalDampingTime>(&spec.contact.normal_damping);
    if (given == nullptr || !v.clean({"contact", "specimen", "engine"})) return;
    const StableStep stable = stable_time_step(spec);
    if (stable.overdamped()) v.note("contact.normal_damping_s", engine::overdamped_error(stable, given->normal_damping_s));
}

void check_work(Validator& v, const JobSpec& spec)
{
    if (!work_inputs_clean(v)) return;
    const WorkEstimate work = estimated_work(spec);
    if (work.total_steps() <= max_steps_of_any_job) return;
    v.note(work_field(spec, work),
        "the job needs about " + format_number(work.total_steps()) + " time steps of " + format_number(work.time_step_s)
            + " s" + (spec.engine.time_step_s ? "" : " (the auto step, set by the " + stable_time_step(spec).limited_by + ")")
            + "; no job may take more than " + format_number(max_steps_of_any_job));
}

/// The escape distance must lie beyond the column's own radius.
void check_escape_distance(Validator& v, const JobSpec& spec)
{
    const auto& given = spec.free_standing.escape_distance_m;
    if (!given || !v.clean({"free_standing.escape_distance_m", "specimen.membrane_radius_m"})) return;
    if (*given <= spec.specimen.membrane_radius_m)
        v.note("free_standing.escape_distance_m",
            exact_number(*given) + " is not beyond specimen.membrane_radius_m " + exact_number(spec.specimen.membrane_radius_m)
                + ": grains at the column's edge would count as having left it");
}

/// The preparation's own refusal (engine::preparation_error), asked last:
/// the checks above say the same in the job's terms, so this speaks only
/// when one of them was missed, and an accepted job still starts.
void check_preparation(Validator& v, const JobSpec& spec)
{
    if (!v.clean({"specimen", "engine", "contact", "seed"}) || !v.errors().empty()) return;
    if (auto e = engine::preparation_error(preparation_geometry(spec)))
        v.note("specimen", "the preparation would refuse it: " + *e);
}

/// Cuts and a breaking strain need a wire; a cut must lie on the wire to be laid.
void check_wire_cuts(Validator& v, const WireSpec& w)
{
    if (!v.clean({"specimen.wire.pattern", "specimen.wire.breaking_strain", "specimen.wire.cuts_at_m",
            "specimen.wire.cut_every_loops", "specimen.wire.length_m"}))
        return;
    if (w.pattern == WirePattern::none) {
        for (const char* field : {"breaking_strain", "cuts_at_m", "cut_every_loops"}) {
            const bool given = std::string_view(field) == "breaking_strain" ? w.breaking_strain.has_value()
                             : std::string_view(field) == "cuts_at_m"       ? !w.cuts_at_m.empty()
                                                                            : w.cut_every_loops != 0;
            if (given)
                v.note(std::string("specimen.wire.") + field, "the pattern \"none\" lays no wire to break or cut");
        }
        return;
    }
    if (w.length_m && !w.cuts_at_m.empty() && w.cuts_at_m.back() >= *w.length_m)
        v.note(index_path("specimen.wire.cuts_at_m", w.cuts_at_m.size() - 1),
            exact_number(w.cuts_at_m.back()) + " is not within the wire: specimen.wire.length_m is " + exact_number(*w.length_m));
}

/// The cuboid cell holds a box of grains and nothing else (issue 43): no
/// wire, no clumps, no free-standing column; and its box preparation's own
/// rules (engine::box_preparation_error), so that an accepted job runs.
void check_cuboid_cell(Validator& v, const JobSpec& spec)
{
    if (spec.triaxial.cell != CellKind::cuboid || !v.clean({"triaxial", "specimen", "free_standing", "contact", "engine"}))
        return;
    bool ok = true;
    if (spec.specimen.wire.pattern != WirePattern::none) {
        v.note("specimen.wire.pattern", "is \"" + std::string(to_string(spec.specimen.wire.pattern))
                                            + "\"; the cuboid cell (triaxial.cell) has no wire: lay none (\"none\")");
        ok = false;
    }
    if (spec.free_standing.enabled) {
        v.note("free_standing.enabled", "the free-standing test stands the poured column up when its membrane goes; the "
                                        "cuboid cell (triaxial.cell) has neither: leave it off or use the membrane cell");
        ok = false;
    }
    if (!ok) return;
    const auto box = box_preparation_geometry(spec); // no collision fit at the door
    if (!box.ok()) {
        v.note(spec.specimen.grain_shape ? "specimen.grain_shape" : "triaxial.cell", box.error());
        return;
    }
    if (const auto e = engine::box_preparation_error(box.value())) v.note("triaxial.cuboid", *e);
}

void cross_check(Validator& v, const JobSpec& spec)
{
    check_cuboid_cell(v, spec);
    check_wire_cuts(v, spec.specimen.wire);
    check_escape_distance(v, spec);
    check_grain_size(v, spec);
    check_grain_volume(v, spec);
    check_wire_fits(v, spec);
    check_fill_rate(v, spec);
    check_membrane_mesh(v, spec);
    check_body_count(v, spec);
    check_test_settings(v, spec);
    check_sample_intervals(v, spec);
    check_snapshots(v, spec.triaxial);
    check_time_step(v, spec);
    check_damping(v, spec);
    check_work(v, spec);
    check_preparation(v, spec);
}

// ------------------------------------------------------------------- writing

/// A number, or null when unset.
json::value optional_json(const std::optional<double>& x) { return x ? json::value(*x) : json::value(nullptr); }

json::array numbers_json(const std::vector<double>& xs)
{
    json::array a;
    a.reserve(xs.size());
    for (const double x : xs) a.emplace_back(x);
    return a;
}

json::object specimen_json(const SpecimenSpec& s)
{
    const WireSpec& w = s.wire;
    const MembraneSpec& m = s.membrane;
    json::object membrane{
        {"thickness_m", m.thickness_m},
        {"mesh_size_m", m.mesh_size_m},
        {"youngs_modulus_pa", m.youngs_modulus_pa},
        {"poisson_ratio", m.poisson_ratio},
        {"density_kg_per_m3", m.density_kg_per_m3},
        {"edges", to_string(m.edges)},
    };
    membrane["contact_radius_m"] = optional_json(m.contact_radius_m);
    json::value grain_sizes = nullptr;
    if (s.grain_sizes) {
        json::array d, f;
        for (double x : s.grain_sizes->diameters_m) d.push_back(x);
        for (double x : s.grain_sizes->fraction_passing) f.push_back(x);
        grain_sizes = json::object{{"basis", to_string(s.grain_sizes->basis)}, {"diameters_m", std::move(d)},
            {"fraction_passing", std::move(f)}};
    }
    json::object o{
        {"membrane_radius_m", s.membrane_radius_m},
        {"membrane_height_m", s.membrane_height_m},
        {"grain_count", s.grain_count},
        {"grain_radius_m", s.grain_radius_m},
        {"grain_radius_spread", s.grain_radius_spread},
        {"grain_sizes", std::move(grain_sizes)},
        {"grain",
            {
                {"youngs_modulus_pa", s.grain.youngs_modulus_pa},
                {"poisson_ratio", s.grain.poisson_ratio},
                {"density_kg_per_m3", s.grain.density_kg_per_m3},
            }},
        {"plate",
            {
                {"youngs_modulus_pa", s.plate.youngs_modulus_pa},
                {"poisson_ratio", s.plate.poisson_ratio},
            }},
        {"wire",
            {
                {"pattern", to_string(w.pattern)},
                {"radius_m", w.radius_m},
                {"segment_length_m", w.segment_length_m},
                {"youngs_modulus_pa", w.youngs_modulus_pa},
                {"poisson_ratio", w.poisson_ratio},
                {"density_kg_per_m3", w.density_kg_per_m3},
                {"nozzle_rise_speed_m_per_s", w.nozzle_rise_speed_m_per_s},
                {"angular_speed_rad_per_s", w.angular_speed_rad_per_s},
                {"helix_radius_m", w.helix_radius_m},
                {"inner_radius_m", w.inner_radius_m},
                {"period_angle_rad", w.period_angle_rad},
                {"clearance_m", w.clearance_m},
                {"bending_yield_strain",
                    w.bending_yield_strain ? json::value(*w.bending_yield_strain) : json::value("elastic")},
                {"length_m", optional_json(w.length_m)},
            }},
        {"membrane", std::move(membrane)},
        {"pouring",
            {
                {"fill_rate_m_per_s", optional_json(s.pouring.fill_rate_m_per_s)},
                {"settle_kinetic_energy_per_grain_j", s.pouring.settle_kinetic_energy_per_grain_j},
                {"max_preparation_time_s", s.pouring.max_preparation_time_s},
            }},
    };
    // A breakable or cut wire only (job_spec.hpp): other jobs' files stay as they were.
    json::object& wire = o["wire"].as_object();
    if (w.breaking_strain) wire["breaking_strain"] = *w.breaking_strain;
    if (!w.cuts_at_m.empty()) {
        json::array cuts;
        for (double x : w.cuts_at_m) cuts.push_back(x);
        wire["cuts_at_m"] = std::move(cuts);
    }
    if (w.cut_every_loops != 0) wire["cut_every_loops"] = w.cut_every_loops;
    if (w.pattern == WirePattern::toolpath) {
        json::array x, y;
        for (double v : w.toolpath_x_m) x.push_back(v);
        for (double v : w.toolpath_y_m) y.push_back(v);
        wire["toolpath_x_m"] = std::move(x);
        wire["toolpath_y_m"] = std::move(y);
        wire["toolpath_rotation_per_layer_rad"] = w.toolpath_rotation_per_layer_rad;
    }
    // Written only when set: every job without it writes what it wrote before.
    if (s.grain_shape) {
        if (!s.grain_shape->template_name.empty()) {
            o["grain_shape"] = json::object{{"template", s.grain_shape->template_name}};
        } else {
            json::array spheres;
            for (const auto& sphere : s.grain_shape->spheres) spheres.push_back(json::array{sphere[0], sphere[1], sphere[2], sphere[3]});
            o["grain_shape"] = json::object{{"spheres", std::move(spheres)}};
        }
    }
    // A curve sets every size: the reader refuses a radius or spread beside it.
    if (s.grain_sizes) {
        o.erase("grain_radius_m");
        o.erase("grain_radius_spread");
    }
    // A preset's name stands for the fields it sets (the reader refuses them
    // beside it); the grain radius is its scale. Jobs without one write what
    // they wrote before.
    if (s.grain_preset != GrainPreset::none) {
        o.erase("grain_sizes");
        o.erase("grain_shape");
        o.erase("grain_radius_spread");
        o["grain_radius_m"] = s.grain_radius_m;
        o["grain_preset"] = to_string(s.grain_preset);
    }
    return o;
}

json::object contact_json(const ContactSpec& c)
{
    json::object o;
    if (const auto* time = std::get_if<NormalDampingTime>(&c.normal_damping)) {
        o["normal_damping_s"] = time->normal_damping_s;
    } else {
        const auto& e = std::get<NormalRestitution>(c.normal_damping);
        o["restitution"] = e.restitution;
        o["restitution_reference_speed_m_per_s"] = e.restitution_reference_speed_m_per_s;
    }
    o["tangential_stiffness_per_m"] = c.tangential.stiffness_per_m;
    o["friction_coeff"] = c.tangential.friction_coeff;
    o["critical_slip_m"] = c.tangential.critical_slip_m;
    o["tangential_damping_s_per_m"] = c.tangential.damping_s_per_m;
    o["rolling_friction_coeff"] = c.rolling.friction_coeff;
    o["rolling_stiffness_factor"] = c.rolling.stiffness_factor;
    o["rolling_damping_ratio"] = c.rolling.damping_ratio;
    return o;
}

json::object triaxial_json(const TriaxialSpec& t)
{
    return {
        {"confining_pressures_pa", numbers_json(t.confining_pressures_pa)},
        {"target_axial_strain", t.target_axial_strain},
        {"plate_speed_m_per_s", t.plate_speeds_m_per_s.size() == 1 ? json::value(t.plate_speeds_m_per_s.front())
                                                                    : json::value(numbers_json(t.plate_speeds_m_per_s))},
        {"pressure_ramp_time_s", t.pressure_ramp_time_s},
        {"hold_time_s", t.hold_time_s},
        {"max_hold_time_s", optional_json(t.max_hold_time_s)},
        {"consolidation", to_string(t.consolidation)},
        {"sample_interval_s", t.sample_interval_s},
        {"snapshot_strains", numbers_json(t.snapshot_strains)},
    };
}

/// The triaxial object: the cell and its box only for the cuboid cell (a
/// membrane job's file is as it was before the field).
json::object triaxial_with_cell_json(const TriaxialSpec& t)
{
    json::object o = triaxial_json(t);
    if (t.cell != CellKind::membrane || !(t.cuboid == TriaxialSpec::Cuboid{})) {
        o["cell"] = to_string(t.cell);
        o["cuboid"] = json::object{{"aspect_ratio", t.cuboid.aspect_ratio},
            {"wall_friction_coeff", t.cuboid.wall_friction_coeff},
            {"compaction_friction_coeff", optional_json(t.cuboid.compaction_friction_coeff)}};
    }
    return o;
}

json::object free_standing_json(const FreeStandingSpec& f)
{
    return {
        {"enabled", f.enabled},
        {"removal_time_s", f.removal_time_s},
        {"removal_distance_m", f.removal_distance_m},
        {"escape_distance_m", optional_json(f.escape_distance_m)},
        {"settle_kinetic_energy_per_grain_j", f.settle_kinetic_energy_per_grain_j},
        {"max_settling_time_s", f.max_settling_time_s},
        {"max_height_loss", f.max_height_loss},
        {"bulk_fraction", f.bulk_fraction},
        {"max_lost_fraction", f.max_lost_fraction},
        {"dead_load_n", optional_json(f.dead_load_n)},
        {"dead_load_ramp_time_s", f.dead_load_ramp_time_s},
        {"dead_load_hold_time_s", f.dead_load_hold_time_s},
        {"pull_out_speed_m_per_s", optional_json(f.pull_out_speed_m_per_s)},
        {"pull_out_end", to_string(f.pull_out_end)},
        {"pull_out_direction", numbers_json(f.pull_out_direction)},
        {"pull_out_ramp_time_s", f.pull_out_ramp_time_s},
        {"pull_out_length_m", optional_json(f.pull_out_length_m)},
        {"pull_out_max_time_s", f.pull_out_max_time_s},
        {"plate_speed_m_per_s", f.plate_speed_m_per_s},
        {"target_axial_strain", f.target_axial_strain},
        {"failure_drop", f.failure_drop},
        {"sample_interval_s", f.sample_interval_s},
    };
}

json::object engine_json(const EngineSpec& e)
{
    json::object o;
    if (e.time_step_s)
        o["time_step_s"] = *e.time_step_s;
    else
        o["time_step_s"] = "auto";
    o["integrator"] = to_string(e.integrator);
    o["threads"] = e.threads;
    o["density_scale"] = e.density_scale;
    o["wire_mass_scale"] = e.wire_mass_scale;
    o["max_bodies"] = e.max_bodies;
    return o;
}

} // namespace

std::string_view to_string(GrainPreset p)
{
    for (const auto& [name, value] : grain_presets)
        if (value == p) return name;
    return "?";
}

std::string_view to_string(CellKind c)
{
    for (const auto& [name, value] : cell_kinds)
        if (value == c) return name;
    return "?";
}

engine::Result<JobSpec, std::vector<FieldError>> parse_job_spec(const json::value& doc)
{
    Validator v;
    JobSpec spec;
    read_job(v, doc, spec);
    cross_check(v, spec);
    if (!v.errors().empty()) return engine::Err{std::move(v.errors())};
    return spec;
}

json::object job_spec_json_schema()
{
    Validator v;
    v.record_schema();
    JobSpec spec;
    read_job(v, json::object(), spec);
    json::object schema{{"$schema", "https://json-schema.org/draft/2020-12/schema"}, {"$id", "/v1/job-spec/schema"},
        {"title", "wiredem job spec"},
        {"description", "Every field the reader takes (api/job_spec.cpp), its type, allowed range or values and default; "
                        "fields left out take their defaults. The checks across fields (the grains fit the membrane, "
                        "the wire fits inside it, ...) are not in it: docs/job-spec.md lists them."}};
    for (auto& [k, val] : v.schema()) schema[k] = val;
    return schema;
}

engine::Result<JobSpec, std::vector<FieldError>> parse_job_spec(std::string_view text)
{
    auto doc = parse_json_text(text);
    if (!doc) return engine::Err{std::vector<FieldError>{{"", doc.error()}}};
    return parse_job_spec(doc.value());
}

engine::Result<JobSpec, std::vector<FieldError>> parse_written_job_spec(std::string_view text)
{
    auto doc = parse_json_text(text);
    if (!doc) return engine::Err{std::vector<FieldError>{{"", doc.error()}}};
    Validator v;
    v.trust();
    engine::Result<JobSpec, std::vector<FieldError>> spec{JobSpec{}};
    read_job(v, doc.value(), spec.value());
    if (!v.errors().empty()) return engine::Err{std::move(v.errors())};
    const json::object* triaxial = nullptr;
    if (const json::object* root = doc.value().if_object())
        if (const json::value* t = root->if_contains("triaxial")) triaxial = t->if_object();
    if (triaxial && !triaxial->contains("consolidation")) spec.value().triaxial.consolidation = Consolidation::cell_pressure;
    return spec;
}

engine::Result<JobSpec, std::vector<FieldError>> parse_job_spec(const char* text)
{
    return parse_job_spec(std::string_view(text));
}

json::value to_json(const JobSpec& spec)
{
    json::object o{
        {"schema_version", job_spec_schema_version},
        {"name", spec.name},
        {"comment", spec.comment},
        {"seed", spec.seed},
        {"specimen", specimen_json(spec.specimen)},
        {"contact", contact_json(spec.contact)},
        {"triaxial", triaxial_with_cell_json(spec.triaxial)},
    };
    if (spec.specimen.grain_preset != GrainPreset::none) {  // the preset sets them (apply_grain_preset)
        json::object& contact = o["contact"].as_object();
        for (const std::string_view key : {"friction_coeff", "rolling_friction_coeff", "rolling_damping_ratio"}) contact.erase(key);
    }
    // Only a job that asks for it (job_spec.hpp): the files of every other job stay as they were.
    if (!(spec.free_standing == FreeStandingSpec{})) o["free_standing"] = free_standing_json(spec.free_standing);
    o["engine"] = engine_json(spec.engine);
    return o;
}

} // namespace wiredem::api
