// Health, metrics, OpenAPI.
#include "meta.hpp"

#include "../router.hpp"
#include "results.hpp"
#include "spec_schema.hpp"

#include <boost/json.hpp>

#include <cctype>
#include <initializer_list>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

namespace wiredem::server {
namespace json = boost::json;

namespace {

/// The API described as OpenAPI 3.0: each operation's own replies. The rest
/// is added by openapi_document(): components.schemas.JobSpec, the reader's
/// own schema (api::job_spec_json_schema); the result data routes; and, from
/// the router's table, every HEAD, operationId and tag and the replies any
/// route can give (complete_from_route_table).
constexpr const char* openapi_text = R"json({
  "openapi": "3.0.3",
  "info": {
    "title": "wiredem",
    "version": "1",
    "description": "Queues triaxial campaigns of wire-reinforced gravel columns and serves their results (summary JSON, HDF5). Errors are {\"error\": {\"code\", \"message\", \"field\"}}."
  },
  "servers": [{"url": "http://127.0.0.1:8080"}],
  "security": [{"bearer": []}],
  "paths": {
    "/v1/jobs": {
      "post": {
        "summary": "Submit a job",
        "parameters": [{"name": "Idempotency-Key", "in": "header", "required": false,
          "description": "1-255 visible ASCII characters; a retried submit with the same key and spec returns the first job.",
          "schema": {"type": "string", "maxLength": 255}}],
        "requestBody": {"required": true, "content": {"application/json": {"schema": {"$ref": "#/components/schemas/JobSpec"}}}},
        "responses": {
          "201": {"description": "Queued (or replayed: header Idempotent-Replayed: true)",
                  "headers": {"Location": {"schema": {"type": "string"}},
                              "Idempotent-Replayed": {"description": "true when the Idempotency-Key named an earlier job with the same spec: this is its first reply again", "schema": {"type": "string", "enum": ["true"]}}},
                  "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Job"}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"},
          "413": {"$ref": "#/components/responses/Error"},
          "415": {"$ref": "#/components/responses/Error"},
          "429": {"description": "Queue full", "headers": {"Retry-After": {"schema": {"type": "integer"}}},
                  "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
        }
      },
      "get": {
        "summary": "List jobs, newest first",
        "parameters": [
          {"name": "state", "in": "query", "schema": {"$ref": "#/components/schemas/State"}},
          {"name": "limit", "in": "query", "schema": {"type": "integer", "minimum": 1, "maximum": 500, "default": 50}},
          {"name": "cursor", "in": "query", "description": "next_cursor of the previous page", "schema": {"type": "string"}}
        ],
        "responses": {
          "200": {"description": "A page of jobs", "content": {"application/json": {"schema": {
            "type": "object", "required": ["jobs", "next_cursor"],
            "properties": {"jobs": {"type": "array", "items": {"$ref": "#/components/schemas/Job"}},
                           "next_cursor": {"type": "string", "nullable": true}}}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "A job with its progress and spec",
        "responses": {
          "200": {"description": "The job", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Job"}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"}
        }
      },
      "delete": {
        "summary": "Cancel a queued or running job (the runner stops within a second); with remove=true, delete a job that has ended, with its files",
        "parameters": [{"name": "remove", "in": "query", "required": false,
          "description": "true: delete the job, which must have ended, with its files (its results), instead of cancelling it",
          "schema": {"type": "string", "enum": ["true"]}}],
        "responses": {
          "200": {"description": "Cancelled (again: cancelling twice is harmless)", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Job"}}}},
          "204": {"description": "remove=true: deleted with its files"},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"description": "already_finished (cancel of a succeeded or failed job), not_finished (remove of a job still active), in_study (a study's job stays with its study)",
                  "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
        }
      }
    },
    "/v1/jobs/{id}/summary": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "Results of a succeeded job: peak stresses, Mohr-Coulomb fit, specimen, engine figures",
        "responses": {
          "200": {"description": "summary.json", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Summary"}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/jobs/{id}/result.h5": {
      "parameters": [{"$ref": "#/components/parameters/JobId"},
        {"name": "Range", "in": "header", "schema": {"type": "string", "example": "bytes=1048576-"}},
        {"name": "If-Range", "in": "header", "schema": {"type": "string"}}],
      "get": {
        "summary": "The HDF5 result file; byte ranges allow resuming a download",
        "responses": {
          "200": {"description": "The whole file", "headers": {"ETag": {"$ref": "#/components/headers/ETag"},
                    "Accept-Ranges": {"$ref": "#/components/headers/AcceptRanges"},
                    "Content-Disposition": {"$ref": "#/components/headers/ContentDisposition"}},
                  "content": {"application/x-hdf5": {"schema": {"type": "string", "format": "binary"}}}},
          "206": {"description": "One byte range", "headers": {"ETag": {"$ref": "#/components/headers/ETag"},
                    "Accept-Ranges": {"$ref": "#/components/headers/AcceptRanges"},
                    "Content-Disposition": {"$ref": "#/components/headers/ContentDisposition"},
                    "Content-Range": {"schema": {"type": "string", "example": "bytes 1048576-2097151/4194304"}}},
                  "content": {"application/x-hdf5": {"schema": {"type": "string", "format": "binary"}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"$ref": "#/components/responses/Error"},
          "416": {"description": "The range starts past the end", "headers": {"Content-Range": {"schema": {"type": "string", "example": "bytes */1048576"}}},
                  "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
        }
      }
    },
    "/v1/studies": {
      "post": {
        "summary": "Submit a parameter study: a base job and the fields to vary; creates one job per point",
        "requestBody": {"required": true, "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Study"}}}},
        "responses": {
          "201": {"description": "Its jobs are queued", "headers": {"Location": {"schema": {"type": "string"}}},
                  "content": {"application/json": {"schema": {"$ref": "#/components/schemas/StudyInfo"}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"},
          "413": {"$ref": "#/components/responses/Error"},
          "415": {"$ref": "#/components/responses/Error"},
          "429": {"description": "Its jobs do not fit in the queue", "headers": {"Retry-After": {"schema": {"type": "integer"}}},
                  "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
        }
      },
      "get": {
        "summary": "List studies, newest first, with their jobs counted by state",
        "parameters": [
          {"name": "limit", "in": "query", "schema": {"type": "integer", "minimum": 1, "maximum": 500, "default": 50}},
          {"name": "cursor", "in": "query", "description": "next_cursor of the previous page", "schema": {"type": "string"}}
        ],
        "responses": {
          "200": {"description": "A page of studies", "content": {"application/json": {"schema": {
            "type": "object", "required": ["studies", "next_cursor"],
            "properties": {"studies": {"type": "array", "items": {"$ref": "#/components/schemas/StudyInfo"}},
                           "next_cursor": {"type": "string", "nullable": true}}}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/studies/{id}": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "A study: each point's values and job (state, progress)",
        "responses": {
          "200": {"description": "The study", "content": {"application/json": {"schema": {"allOf": [
            {"$ref": "#/components/schemas/StudyInfo"},
            {"type": "object", "properties": {
              "document": {"$ref": "#/components/schemas/Study"},
              "jobs": {"type": "array", "items": {"type": "object", "properties": {
                "index": {"type": "integer"}, "label": {"type": "string"}, "values": {"type": "object"},
                "job": {"$ref": "#/components/schemas/Job"}}}}}}]}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"}
        }
      },
      "delete": {
        "summary": "Cancel every job of the study that has not ended",
        "responses": {
          "200": {"description": "The study", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/StudyInfo"}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/studies/{id}/summary": {
      "parameters": [{"$ref": "#/components/parameters/JobId"}],
      "get": {
        "summary": "One row per point (phi, c, R2, yield and max q per pressure, volume fractions, wire lag) and, over the seeds, mean, sd and n of phi and c per combination",
        "responses": {
          "200": {"description": "The study's summary as its jobs stand", "content": {"application/json": {"schema": {
            "type": "object", "required": ["name", "paths", "points", "groups"],
            "properties": {"id": {"type": "string"}, "name": {"type": "string"},
              "paths": {"type": "array", "items": {"type": "string"}},
              "points": {"type": "array", "items": {"type": "object"}},
              "groups": {"type": "array", "items": {"type": "object", "properties": {
                "values": {"type": "object"}, "points": {"type": "integer"}, "succeeded": {"type": "integer"},
                "friction_angle_deg": {"$ref": "#/components/schemas/Spread"},
                "cohesion_pa": {"$ref": "#/components/schemas/Spread"}}}}}}}}},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"}
        }
      }
    },
    "/v1/health": {
      "get": {"summary": "Liveness and queue figures",
              "responses": {"200": {"description": "Serving", "content": {"application/json": {"schema": {
                "type": "object", "required": ["status", "version", "uptime_s", "queued", "running", "workers", "threads_per_job"],
                "properties": {"status": {"type": "string", "enum": ["ok"]}, "version": {"type": "string"},
                  "uptime_s": {"type": "number"}, "queued": {"type": "integer", "description": "jobs waiting for a worker"},
                  "running": {"type": "integer", "description": "workers running a job"},
                  "workers": {"type": "integer"}, "threads_per_job": {"type": "integer"}}}}}}}}
    },
    "/v1/openapi.json": {
      "get": {"summary": "This document", "responses": {"200": {"description": "OpenAPI 3", "content": {"application/json": {"schema": {"type": "object"}}}}}}
    },
    "/v1/job-spec/schema": {
      "get": {"summary": "The job spec as a JSON Schema (draft 2020-12), made by the reader itself: every field, its type, range or values and default; the checks across fields are not in it (docs/job-spec.md)",
              "responses": {"200": {"description": "JSON Schema", "content": {"application/schema+json": {"schema": {"type": "object"}}}}}}
    },
    "/metrics": {
      "get": {"summary": "Prometheus metrics (no authentication)", "security": [],
              "responses": {"200": {"description": "Text exposition format 0.0.4", "content": {"text/plain": {"schema": {"type": "string"}}}}}}
    }
  },
  "components": {
    "securitySchemes": {"bearer": {"type": "http", "scheme": "bearer",
      "description": "Only when the server runs with --token-file; then every /v1 route needs it."}},
    "parameters": {
      "JobId": {"name": "id", "in": "path", "required": true,
                "schema": {"type": "string", "pattern": "^[0-9a-f]{24}$"}}
    },
    "responses": {
      "Error": {"description": "Error", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
    },
    "headers": {
      "ETag": {"description": "the file's version: send it as If-Range to resume a download", "schema": {"type": "string"}},
      "AcceptRanges": {"schema": {"type": "string", "enum": ["bytes"]}},
      "ContentDisposition": {"schema": {"type": "string", "example": "attachment; filename=\"3f0c9d2e8a61b4c7d5e9f012.h5\""}}
    },
    "schemas": {
      "Summary": {"type": "object", "required": ["tests", "mohr_coulomb", "engine"],
        "description": "The runner's summary.json (docs/results.md): one entry per test, the Mohr-Coulomb fits, the prepared specimen and the engine's figures.",
        "properties": {
          "tests": {"type": "array", "items": {"type": "object", "properties": {
            "confining_pressure_pa": {"type": "number"}, "peak_deviatoric_stress_pa": {"type": "number"},
            "peak_axial_strain": {"type": "number"}, "sigma1_pa": {"type": "number"}, "sigma3_effective_pa": {"type": "number"}}}},
          "mohr_coulomb": {"$ref": "#/components/schemas/MohrCoulomb"},
          "mohr_coulomb_max_q": {"$ref": "#/components/schemas/MohrCoulomb"},
          "specimen": {"type": "object"},
          "engine": {"type": "object", "properties": {"time_step_s": {"type": "number"}, "steps": {"type": "integer"},
            "wall_time_s": {"type": "number"}, "body_steps_per_second": {"type": "number", "nullable": true}}}}},
      "MohrCoulomb": {"type": "object", "properties": {"friction_angle_deg": {"type": "number", "nullable": true},
        "cohesion_pa": {"type": "number", "nullable": true}, "r_squared": {"type": "number", "nullable": true}}},
      "State": {"type": "string", "enum": ["queued", "preparing", "running", "succeeded", "failed", "cancelled"]},
      "Study": {"type": "object", "required": ["name", "base"],
        "description": "docs/studies.md: the base job and either vary (field path -> list of values, a full grid) or points (a list of {field path: value}); every point is validated as a job; at most --max-study-points points.",
        "properties": {"name": {"type": "string", "maxLength": 200}, "comment": {"type": "string"},
          "base": {"$ref": "#/components/schemas/JobSpec"},
          "vary": {"type": "object", "additionalProperties": {"type": "array", "minItems": 1}},
          "points": {"type": "array", "minItems": 1, "items": {"type": "object"}}}},
      "StudyInfo": {"type": "object", "required": ["id", "url", "name", "created_at", "points", "jobs_by_state", "links"],
        "properties": {"id": {"type": "string"}, "url": {"type": "string"}, "name": {"type": "string"},
          "created_at": {"type": "string", "format": "date-time"}, "points": {"type": "integer"},
          "jobs_by_state": {"type": "object", "additionalProperties": {"type": "integer"}},
          "links": {"type": "object", "properties": {"self": {"type": "string"}, "summary": {"type": "string"}}}}},
      "Spread": {"type": "object", "required": ["mean", "sd", "n"],
        "properties": {"mean": {"type": "number", "nullable": true}, "sd": {"type": "number", "nullable": true,
          "description": "sample standard deviation (n - 1); null below n = 2"}, "n": {"type": "integer"}}},
      "Job": {
        "type": "object",
        "required": ["id", "url", "state", "progress", "created_at", "links"],
        "properties": {
          "id": {"type": "string", "pattern": "^[0-9a-f]{24}$"},
          "url": {"type": "string"},
          "name": {"type": "string"},
          "state": {"$ref": "#/components/schemas/State"},
          "stage": {"type": "string", "nullable": true, "enum": ["preparing", "testing", "analysing", "writing", null]},
          "progress": {"type": "number", "minimum": 0, "maximum": 1},
          "eta_s": {"type": "number", "nullable": true},
          "message": {"type": "string"},
          "error": {"type": "string", "nullable": true},
          "attempts": {"type": "integer"},
          "created_at": {"type": "string", "format": "date-time"},
          "started_at": {"type": "string", "format": "date-time", "nullable": true},
          "finished_at": {"type": "string", "format": "date-time", "nullable": true},
          "links": {"type": "object", "properties": {"self": {"type": "string"}, "summary": {"type": "string"}, "result": {"type": "string"}}},
          "slurm": {"type": "object", "description": "GET /v1/jobs/{id} of a server with --executor slurm, once the job is submitted: its Slurm jobs (docs/studies.md)",
            "required": ["prepare_job_id", "test_array_job_id", "analyse_job_id", "submitted_at"],
            "properties": {"prepare_job_id": {"type": "integer"}, "test_array_job_id": {"type": "integer", "description": "array task K runs test K"},
              "analyse_job_id": {"type": "integer"}, "submitted_at": {"type": "string", "format": "date-time"}}},
          "spec": {"$ref": "#/components/schemas/JobSpec"}
        }
      },
      "Error": {
        "type": "object", "required": ["error"],
        "properties": {"error": {"type": "object", "required": ["code", "message", "field"],
          "properties": {
            "code": {"type": "string"},
            "message": {"type": "string"},
            "field": {"type": "string", "nullable": true},
            "details": {"type": "array", "items": {"type": "object", "properties": {"field": {"type": "string"}, "message": {"type": "string"}}}}}}}
      }
    }
  }
})json";

/// An Error reply with `headers` (name → description).
json::object error_reply(std::string_view description, std::initializer_list<std::pair<const char*, const char*>> headers = {})
{
    json::object reply{{"description", description},
        {"content", {{"application/json", {{"schema", {{"$ref", "#/components/schemas/Error"}}}}}}}};
    if (headers.size() > 0) {
        json::object h;
        for (const auto& [name, what] : headers) h[name] = {{"description", what}, {"schema", {{"type", "string"}}}};
        reply["headers"] = std::move(h);
    }
    return reply;
}

/// What any operation can be answered besides its own replies: the router
/// and the session answer these before (or instead of) a handler.
void add_common_replies(json::object& responses, bool needs_token, bool has_body)
{
    auto add = [&](const char* status, json::object reply) {
        if (!responses.contains(status)) responses[status] = std::move(reply);
    };
    add("400", error_reply("bad_host (Host is not one of the server's names), bad_parameter (a query parameter this "
                           "route does not take), bad_id, bad_target, or malformed HTTP (the connection is closed)"));
    if (needs_token)  // over a bare Error the operation may give: this one names the header
        responses["401"] = error_reply(
            "unauthorized: the server runs with --token-file and the request has no valid bearer token",
            {{"WWW-Authenticate", "Bearer realm=\"wiredem\""}});
    add("403", error_reply("forbidden_origin: a browser's request from another site's page"));
    add("405", error_reply("method_not_allowed", {{"Allow", "the methods of this path"}}));
    add("413", error_reply("body_too_large: the body exceeds --max-body-bytes (the connection is closed)"));
    add("431", error_reply("headers_too_large: the headers exceed --max-header-bytes (the connection is closed)"));
    add("500", error_reply("internal: the server could not answer (its log says why)"));
    if (has_body)
        add("503", error_reply("busy: --max-pending-submits are waiting for validation", {{"Retry-After", "seconds"}}));
    add("503", error_reply("too_many_connections: every one of --max-connections is busy with a request (sent at "
                           "once on connecting; the connection is closed)", {{"Retry-After", "seconds"}}));
}

/// HEAD of a GET: the same replies, headers included, without their bodies.
json::object head_of(const json::object& get, std::string operation_id)
{
    json::object head = get;
    head["operationId"] = std::move(operation_id);
    head["summary"] = "Headers of: " + std::string(get.contains("summary") ? get.at("summary").as_string().c_str() : "GET");
    for (auto& [status, reply] : head["responses"].as_object()) {
        json::object& r = reply.as_object();
        if (r.contains("$ref")) r = json::object{{"description", "as for GET, without the body"}};
        r.erase("content");
    }
    return head;
}

/// An operationId for a result data path that has none:
/// "/v1/jobs/{id}/tests/{test}/series" → "getJobTestsTestSeries".
std::string operation_id_of(std::string_view path)
{
    std::string id = "getJob";
    bool upper = true;
    for (char c : path.substr(std::string_view("/v1/jobs/{id}").size())) {
        if (c == '/' || c == '{' || c == '}' || c == '_' || c == '.') {
            upper = true;
            continue;
        }
        id += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
        upper = false;
    }
    return id;
}

/// Completes `doc` from the router's table: each operation's operationId and
/// tag, a HEAD beside each GET, and the replies every route can give.
void complete_from_route_table(json::object& doc)
{
    json::object& paths = doc.at("paths").as_object();
    std::vector<std::pair<std::string, Route>> ops;
    for (const Route& r : route_table()) ops.emplace_back(std::string(http::to_string(r.method)), r);
    // The result data routes (handlers/results.hpp): GET each, tag "results".
    for (const auto& [path, item] : result_data_openapi_paths())
        ops.emplace_back("GET", Route{path, http::verb::get, {}, "results", true, nullptr});
    for (const auto& [method, r] : ops) {
        json::value* item = paths.if_contains(r.path);
        std::string name = method;
        for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        json::value* op_value = item && item->is_object() ? item->as_object().if_contains(name) : nullptr;
        json::object* op = op_value ? op_value->if_object() : nullptr;
        if (!op) continue;  // undocumented: tests/server/test_routes.cpp says so
        if (!r.operation_id.empty()) (*op)["operationId"] = r.operation_id;
        else if (!op->contains("operationId")) (*op)["operationId"] = operation_id_of(r.path);
        (*op)["tags"] = json::array{json::string(r.tag)};
        add_common_replies((*op)["responses"].as_object(), r.path.substr(0, 4) == "/v1/", r.method == http::verb::post);
        if (r.method == http::verb::get)
            item->as_object()["head"] = head_of(*op, std::string((*op)["operationId"].as_string()) + "Head");
    }
    doc["tags"] = json::array{
        json::object{{"name", "jobs"}, {"description", "Submit, follow, cancel and delete jobs"}},
        json::object{{"name", "results"}, {"description", "A succeeded job's summary, result file and data"}},
        json::object{{"name", "studies"}, {"description", "Parameter studies: one job per point"}},
        json::object{{"name", "service"}, {"description", "Health, metrics, this document, the job spec's schema"}}};
}

double uptime_s(const Metrics& m)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m.started).count();
}

} // namespace

const json::value& openapi_document()
{
    static const json::value doc = [] {
        json::value d = json::parse(openapi_text);
        // The result data routes describe themselves (handlers/results.cpp).
        for (const auto& [path, item] : result_data_openapi_paths()) d.at("paths").as_object()[path] = item;
        for (const auto& [kind, entries] : result_data_openapi_components())
            for (const auto& [name, entry] : entries.as_object()) d.at("components").as_object()[kind].as_object()[name] = entry;
        // The job spec as the reader in api/ describes itself (handlers/spec_schema.hpp).
        d.at("components").at("schemas").as_object()["JobSpec"] = job_spec_openapi_schema();
        complete_from_route_table(d.as_object());
        return d;
    }();
    return doc;
}

Response handle_health(const Request& req, Services& svc)
{
    const StateCounts counts = svc.store.count_by_state();
    json::object body;
    body["status"] = "ok";
    body["version"] = "0.1.0";
    body["uptime_s"] = uptime_s(svc.metrics);
    body["queued"] = counts[static_cast<std::size_t>(JobState::queued)];
    body["running"] = svc.queue.busy_workers();
    body["workers"] = svc.queue.config().concurrent_jobs;
    body["threads_per_job"] = svc.queue.config().threads_per_job;
    body["executor"] = svc.queue.config().slurm ? "slurm" : "local";
    return json_response(req, http::status::ok, body);
}

Response handle_metrics(const Request& req, Services& svc)
{
    const StateCounts counts = svc.store.count_by_state();
    std::ostringstream out;
    out.imbue(std::locale::classic());
    auto family = [&](const char* name, const char* type, const char* help) {
        out << "# HELP " << name << ' ' << help << "\n# TYPE " << name << ' ' << type << '\n';
    };
    family("wiredem_queue_length", "gauge", "Jobs waiting for a worker.");
    out << "wiredem_queue_length " << counts[static_cast<std::size_t>(JobState::queued)] << '\n';
    family("wiredem_jobs", "gauge", "Jobs in the store by state.");
    for (JobState s : all_job_states)
        out << "wiredem_jobs{state=\"" << to_string(s) << "\"} " << counts[static_cast<std::size_t>(s)] << '\n';
    family("wiredem_workers", "gauge", "Worker slots (concurrent jobs).");
    out << "wiredem_workers " << svc.queue.config().concurrent_jobs << '\n';
    family("wiredem_workers_busy", "gauge", "Workers running a job now.");
    out << "wiredem_workers_busy " << svc.queue.busy_workers() << '\n';
    family("wiredem_body_steps_per_second", "gauge",
        "Engine throughput (bodies x steps per second) last reported by a job; 0 before any.");
    out << "wiredem_body_steps_per_second " << svc.queue.body_steps_per_second().value_or(0.0) << '\n';
    family("wiredem_jobs_submitted_total", "counter", "Jobs accepted since the server started.");
    out << "wiredem_jobs_submitted_total " << svc.metrics.jobs_submitted.load(std::memory_order_relaxed) << '\n';
    family("wiredem_http_responses_total", "counter", "HTTP replies by status class.");
    for (int c = 1; c <= 5; ++c)
        out << "wiredem_http_responses_total{code=\"" << c << "xx\"} "
            << svc.metrics.responses_by_class[c].load(std::memory_order_relaxed) << '\n';
    family("wiredem_http_connections_open", "gauge", "Open client connections.");
    out << "wiredem_http_connections_open " << svc.metrics.connections_open.load(std::memory_order_relaxed) << '\n';
    family("wiredem_http_connections_rejected_total", "counter", "Connections closed at once: too many open.");
    out << "wiredem_http_connections_rejected_total "
        << svc.metrics.connections_rejected.load(std::memory_order_relaxed) << '\n';
    family("wiredem_uptime_seconds", "gauge", "Seconds since the server started.");
    out << "wiredem_uptime_seconds " << uptime_s(svc.metrics) << '\n';
    return text_response(req, http::status::ok, out.str(), "text/plain; version=0.0.4; charset=utf-8");
}

Response handle_openapi(const Request& req, Services&)
{
    return json_response(req, http::status::ok, openapi_document());
}

} // namespace wiredem::server
