// The job spec's schema, served and converted for the OpenAPI document.
#include "spec_schema.hpp"

#include "api/job_spec.hpp"

#include <boost/json.hpp>

namespace wiredem::server {
namespace json = boost::json;

namespace {

/// Rewrites one schema node (and everything below it) from draft 2020-12 to OpenAPI 3.0.
json::value to_openapi_30(const json::value& v)
{
    if (const auto* a = v.if_array()) {
        json::array out;
        for (const auto& x : *a) out.push_back(to_openapi_30(x));
        return out;
    }
    const auto* o = v.if_object();
    if (!o) return v;
    json::object out;
    for (const auto& [k, x] : *o) {
        if (k == "$schema" || k == "$id") continue;
        if (k == "exclusiveMinimum" || k == "exclusiveMaximum") {
            out[k == "exclusiveMinimum" ? "minimum" : "maximum"] = x;
            out[k] = true;
        } else if (k == "const") {
            out["enum"] = json::array{x};
            if (x.is_string()) out["type"] = "string";
        } else if (k == "type" && x.is_array()) {  // ["number", "null"]
            for (const auto& t : x.as_array())
                if (t == "null") out["nullable"] = true;
                else out["type"] = t;
        } else {
            out[k] = to_openapi_30(x);
        }
    }
    return out;
}

} // namespace

Response handle_job_spec_schema(const Request& req, Services&)
{
    static const json::value schema = api::job_spec_json_schema();
    auto res = json_response(req, http::status::ok, schema);
    res.set(http::field::content_type, "application/schema+json");
    return res;
}

const json::object& job_spec_openapi_schema()
{
    static const json::object schema = to_openapi_30(api::job_spec_json_schema()).as_object();
    return schema;
}

} // namespace wiredem::server
