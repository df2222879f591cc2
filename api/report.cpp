// The offline report (api/report.hpp).
#include "api/report.hpp"

#include "api/job_spec.hpp"
#include "api/json_text.hpp"
#include "api/result_data.hpp"
#include "core/format.hpp"
#include "io/hdf5.hpp"
#include "triaxial/result_names.hpp"
#include "triaxial/series_columns.hpp"

#include <boost/json.hpp>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace wiredem::api {
namespace json = boost::json;
namespace fs = std::filesystem;
namespace io = engine::io;
using P = engine::ResultPlace;

namespace {

std::string read_text(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read " + p.string());
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// A module of the page as a plain part of one inline module: its imports
/// dropped (the modules it imports come before it in the same script; uPlot
/// is the global of its browser build) and `export` dropped from its
/// declarations. The page's modules import and export on single lines.
std::string inlined_module(const fs::path& file)
{
    std::istringstream in(read_text(file));
    std::string out, line;
    while (std::getline(in, line)) {
        if (line.rfind("import ", 0) == 0) continue;
        if (line.rfind("export ", 0) == 0) line.erase(0, 7);
        out += line;
        out += '\n';
    }
    return out;
}

/// Text placed inside <script> or <style> must not close it early.
std::string checked_inline(std::string text, const std::string& what)
{
    for (const char* bad : {"</script", "</style", "<!--"})
        if (text.find(bad) != std::string::npos)
            throw std::runtime_error(what + " holds '" + bad + "' and cannot be inlined");
    return text;
}

/// JSON inside <script type="application/json">: '<' only occurs in strings
/// there, where \u003c reads back the same.
std::string script_json(const json::value& v)
{
    std::string text = json::serialize(v), out;
    out.reserve(text.size());
    for (char c : text) {
        if (c == '<') out += "\\u003c";
        else out += c;
    }
    return out;
}

/// The report's data: the summary, the tests and their curves, and the wire
/// at the end of the test at the highest pressure (what summary.wire's lag is read from).
json::object report_data(const fs::path& summary_json, const fs::path& result_h5, const std::string& source)
{
    const auto summary = parse_json_text(read_text(summary_json));
    if (!summary) throw std::runtime_error(summary_json.string() + ": " + summary.error());
    const io::File file = io::File::open_read_only(result_h5);
    const io::Group root = file.root();
    const auto spec_doc = parse_json_text(root.open_dataset(engine::result_name(P::root, "job_spec")).read_string());
    if (!spec_doc) throw std::runtime_error("result.h5: /job_spec is not JSON");
    const auto spec = parse_job_spec(spec_doc.value());
    if (!spec) throw std::runtime_error("result.h5: /job_spec is not a valid job: " + spec.error().front().message);

    json::object data;
    data["name"] = spec.value().name;
    data["source"] = source;
    data["written_by"] = "wiredem report";
    data["summary"] = summary.value();
    json::object tests = tests_json(root, "");
    // The columns the curves draw (curveColumns of web/src/js/results_view.js),
    // each checked by the compiler against the one list of columns.
    using engine::series_column;
    const std::vector<std::string> columns{std::string(series_column("axial_strain").name),
        std::string(series_column("deviatoric_stress_pa").name), std::string(series_column("stress_ratio").name),
        std::string(series_column("volumetric_strain").name), std::string(series_column("phase").name)};
    constexpr std::size_t points = 1000;  // as the job page asks for
    json::array series;
    const std::vector<std::string> names = test_names(root);
    for (const std::string& name : names) {
        const io::Group t = root.open_group(test_path(name));
        const std::vector<std::string> stored = series_columns(t);
        std::vector<std::string> present;  // a result written before a column existed has no such column
        for (const auto& c : columns)
            if (std::find(stored.begin(), stored.end(), c) != stored.end()) present.push_back(c);
        series.push_back(series_json(t, name, present, points));
    }
    data["tests"] = std::move(tests.at("tests"));
    data["series"] = std::move(series);
    // The free-standing test, as the job page asks for it (renderFreeStanding:
    // its test reply and the series of freeStandingColumns).
    data["free_standing"] = nullptr;
    if (const std::string fs_name(free_standing_group); root.exists(fs_name)) {
        const io::Group g = root.open_group(fs_name);
        data["free_standing"] = json::object{
            {"test", free_standing_json(g, "", spec.value().specimen.wire.segment_length_m)},
            {"series", series_json(g, fs_name, {std::string(series_column("axial_strain").name),
                std::string(series_column("sigma1_pa").name), std::string(series_column("phase").name)}, 2000)}};
    }
    data["wire"] = nullptr;
    if (!names.empty()) {
        const io::Group last = root.open_group(test_path(names.back()));
        const auto ks = snapshot_indices(last);
        if (!ks.empty()) {
            const io::Group snap = last.open_group(snapshot_path(ks.back()));
            constexpr std::string_view strain_name = engine::result_name(P::snapshot, "wire_segment_strain"),
                                       nodes_name = engine::result_name(P::snapshot, "wire_node_position_m");
            if (snap.exists(strain_name) && snap.exists(nodes_name)) {
                const std::vector<double> strain = snap.open_dataset(strain_name).read_doubles();
                const std::vector<double> nodes = snap.open_dataset(nodes_name).read_doubles();
                if (strain.size() > 1) {
                    // 6 significant digits, as std::ostream's default wrote them.
                    const std::string label = "sigma3 = "
                        + engine::format_number(last.read_double_attribute(engine::result_name(P::test, "confining_pressure_pa")) / 1000, 6)
                        + " kPa, eps1 = " + engine::format_number(snap.read_double_attribute(engine::result_name(P::snapshot, "axial_strain")), 6);
                    data["wire"] = json::object{{"label", label},
                        {"node_position_m", json::value_from(nodes)}, {"segment_strain", json::value_from(strain)},
                        {"autocorrelation", wire_autocorrelation_json(strain, spec.value().specimen.wire.segment_length_m)}};
                }
            }
        }
    }
    return data;
}

} // namespace

std::string report_html(const fs::path& summary_json, const fs::path& result_h5, const fs::path& web_dir, const std::string& source)
{
    if (!fs::is_regular_file(web_dir / "js" / "results_view.js"))
        throw std::runtime_error("no web page in " + web_dir.string());
    const json::object data = report_data(summary_json, result_h5, source);
    std::string script;
    for (const char* m : {"dom.js", "plots.js", "results_view.js", "report.js"}) script += inlined_module(web_dir / "js" / m);

    std::string page = "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>wiredem report</title>\n<style>\n";
    page += checked_inline(read_text(web_dir / "vendor" / "uPlot.min.css"), "uPlot.min.css") + "\n";
    page += checked_inline(read_text(web_dir / "app.css"), "app.css");
    page += "</style>\n</head>\n<body>\n<header><span class=\"brand\">wiredem</span><span id=\"status\">offline report</span></header>\n"
            "<main id=\"main\"></main>\n<script type=\"application/json\" id=\"report-data\">";
    page += script_json(data);
    page += "</script>\n<script>\n" + checked_inline(read_text(web_dir / "vendor" / "uPlot.iife.min.js"), "uPlot.iife.min.js");
    page += "\n</script>\n<script type=\"module\">\n" + checked_inline(script, "the page's modules") + "</script>\n</body>\n</html>\n";
    return page;
}

} // namespace wiredem::api
