// Health, metrics, OpenAPI.
#include "meta.hpp"

#include "../router.hpp"
#include "analysis/strength.hpp"
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
        "summary": "Cancel every job of the study that has not ended; with remove=true, delete a study whose jobs have all ended, with its jobs and their files",
        "parameters": [{"name": "remove", "in": "query", "required": false,
          "description": "true: delete the study, every job of which must have ended, with its jobs and their files, instead of cancelling them",
          "schema": {"type": "string", "enum": ["true"]}}],
        "responses": {
          "200": {"description": "Its jobs cancelled", "content": {"application/json": {"schema": {"$ref": "#/components/schemas/StudyInfo"}}}},
          "204": {"description": "remove=true: deleted with its jobs and their files"},
          "400": {"$ref": "#/components/responses/Error"},
          "401": {"$ref": "#/components/responses/Error"},
          "404": {"$ref": "#/components/responses/Error"},
          "409": {"description": "not_finished: remove of a study with a job that has not ended",
                  "content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
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
    },
    "/": {
      "get": {"summary": "The web page (docs/web.md): index.html of --web-dir (no authentication; it asks for the token itself)", "security": [],
              "responses": {"200": {"description": "index.html", "headers": {"ETag": {"schema": {"type": "string"}}},
                                    "content": {"text/html": {"schema": {"type": "string"}}}},
                            "304": {"description": "If-None-Match names the file's ETag (compared weakly)"},
                            "404": {"$ref": "#/components/responses/Error"}}}
    },
    "/{file}": {
      "parameters": [{"name": "file", "in": "path", "required": true, "schema": {"type": "string"},
        "description": "a file of the web page below --web-dir, e.g. js/main.js: plain names (letters, digits, _ - .), not starting with a dot, in folders (the template names one segment; the page's files may be folders deep)"}],
      "get": {"summary": "A file of the web page (no authentication); any other path outside /v1 is 404", "security": [],
              "responses": {"200": {"description": "The file, with its content type (only the page's known file types are served)",
                                    "headers": {"ETag": {"schema": {"type": "string"}}},
                                    "content": {"*/*": {"schema": {"type": "string", "format": "binary"}}}},
                            "304": {"description": "If-None-Match names the file's ETag (compared weakly)"},
                            "404": {"$ref": "#/components/responses/Error"}}}
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
      "Summary": {"type": "object",
        "description": "The runner's summary.json (docs/results.md), written by campaign/stages.cpp (analyse); tests/server/test_summary_schema.cpp checks a real campaign's against this schema, every key and type. Key names carry their units: _pa Pa, _m m, _m3 m^3, _s s, _deg degrees; the rest are dimensionless or counts. A figure that can be undefined (not finite) is written as null: those marked nullable; the others are finite by construction.",
        "required": ["name", "tests", "mohr_coulomb", "mohr_coulomb_max_q", "definitions", "specimen", "wire", "warnings", "engine"],
        "properties": {
          "name": {"type": "string", "description": "the job's name"},
          "tests": {"type": "array", "description": "one per confining pressure, in the job's order", "items": {"$ref": "#/components/schemas/SummaryTest"}},
          "mohr_coulomb": {"$ref": "#/components/schemas/MohrCoulomb"},
          "mohr_coulomb_max_q": {"$ref": "#/components/schemas/MohrCoulomb"},
          "definitions": {"$ref": "#/components/schemas/SummaryDefinitions"},
          "specimen": {"$ref": "#/components/schemas/SummarySpecimen"},
          "wire": {"$ref": "#/components/schemas/SummaryWire"},
          "warnings": {"type": "array", "description": "not settled, nozzle blocked, not quasi-static (per test, prefixed with the test), fit or wire autocorrelation problems", "items": {"type": "string"}},
          "engine": {"$ref": "#/components/schemas/SummaryEngine"},
          "free_standing": {"$ref": "#/components/schemas/SummaryFreeStanding"}}},
      "SummaryFreeStanding": {"type": "object",
        "description": "The free-standing test (job free_standing.enabled; docs/model.md, \"The free-standing test\"): the formwork removed, the column settled on the bottom plate, an optional dead load, unconfined compression. Only in the summary of a job that ran it.",
        "required": ["settling", "dead_load", "compression", "steps", "wall_time_s", "threads"],
        "properties": {
          "settling": {"type": "object", "description": "the formwork's removal and the settling under the column's own weight",
            "required": ["stands", "at_rest", "time_to_rest_s", "height_before_m", "height_m", "height_loss", "bulk_height_before_m", "bulk_height_m", "bulk_height_loss", "radius_before_m", "radius_m", "grains", "escaped_grains", "lost_fraction", "weight_n", "base_force_n", "base_force_tolerance_n", "max_removal_kinetic_energy_j"],
            "properties": {
              "stands": {"type": "boolean", "description": "at rest, with a loss of the grains' bulk height (bulk_height_loss) of at most free_standing.max_height_loss and at most free_standing.max_lost_fraction of the grains' volume lost (lost_fraction); not read from the top of the highest grain or wire node, which a wire left standing keeps"},
              "at_rest": {"type": "boolean", "description": "the kinetic energy per grain fell below free_standing.settle_kinetic_energy_per_grain_j within max_settling_time_s"},
              "time_to_rest_s": {"type": "number", "nullable": true, "description": "from the end of the removal to rest (the limit when not at rest) [s]"},
              "height_before_m": {"type": "number", "nullable": true, "description": "top of the highest standing grain or wire node above the bottom plate, before the removal [m]"},
              "height_m": {"type": "number", "nullable": true, "description": "the same after settling: h0 of the compression, where its plate is set [m]"},
              "height_loss": {"type": "number", "nullable": true, "description": "(height_before_m - height_m) / height_before_m [1]"},
              "bulk_height_before_m": {"type": "number", "nullable": true, "description": "the grains' bulk height before the removal: z_q / q, z_q the height below which the share q = free_standing.bulk_fraction of the standing grains' volume lies (docs/model.md, \"What stands\") [m]"},
              "bulk_height_m": {"type": "number", "nullable": true, "description": "the same after settling [m]"},
              "bulk_height_loss": {"type": "number", "nullable": true, "description": "(bulk_height_before_m - bulk_height_m) / bulk_height_before_m, which the verdict reads [1]"},
              "radius_before_m": {"type": "number", "nullable": true, "description": "equivalent radius sqrt(2 <rho^2>) + <r> of the standing grains before the removal [m]"},
              "radius_m": {"type": "number", "nullable": true, "description": "the same after settling: r0 of the compression's stress [m]"},
              "grains": {"type": "integer", "description": "the column's grains (a clump counts once)"},
              "escaped_grains": {"type": "integer", "description": "grains farther than free_standing.escape_distance_m from the axis (a clump by its centre of mass)"},
              "lost_fraction": {"type": "number", "nullable": true, "description": "the escaped grains' share of the grains' volume, which the verdict bounds by free_standing.max_lost_fraction [1]"},
              "weight_n": {"type": "number", "nullable": true, "description": "the real weight of the moving bodies [N]"},
              "base_force_n": {"type": "number", "nullable": true, "description": "the bottom plate's force averaged over the last millisecond of settling [N]"},
              "base_force_tolerance_n": {"type": "number", "nullable": true, "description": "the largest |base_force_n - weight_n| the column's motion allows, (sqrt(2 M K0) + sqrt(2 M K1)) / tau [N]"},
              "max_removal_kinetic_energy_j": {"type": "number", "nullable": true, "description": "the largest kinetic energy during the removal (a removal at speed v gives at most 2 M v^2) [J]"}}},
          "dead_load": {"type": "object", "nullable": true, "description": "the dead load (free_standing.dead_load_n); null without one",
            "required": ["force_n", "stress_pa", "holds", "strain_at_load", "creep_strain"],
            "properties": {
              "force_n": {"type": "number", "description": "F [N]"},
              "stress_pa": {"type": "number", "nullable": true, "description": "F / (pi r0^2) [Pa]"},
              "holds": {"type": "boolean", "description": "the axial strain stayed below free_standing.target_axial_strain through the ramp and hold"},
              "strain_at_load": {"type": "number", "nullable": true, "description": "axial strain when the ramp ended [1]"},
              "creep_strain": {"type": "number", "nullable": true, "description": "axial strain gained over the hold [1]"}}},
          "compression": {"type": "object", "description": "the unconfined compression",
            "required": ["unconfined_strength_pa", "shape", "strain_at_failure", "max_sigma1_pa", "failed", "failure_mode", "spilled_fraction", "bulge_m", "predicted_unconfined_strength_pa", "definition", "quasi_static", "max_inertial_number", "mean_kinetic_to_elastic"],
            "properties": {
              "unconfined_strength_pa": {"type": "number", "nullable": true, "description": "the maximum of the smoothed sigma1 = F_top / (pi r0^2) [Pa]; null when the curve cannot be read (a warning says why)"},
              "shape": {"type": "string", "nullable": true, "description": "what kind of maximum it is (definitions.shape): rising is a lower bound"},
              "strain_at_failure": {"type": "number", "nullable": true, "description": "axial strain at that maximum [1]"},
              "max_sigma1_pa": {"type": "number", "nullable": true, "description": "the largest raw sigma1 [Pa]"},
              "failed": {"type": "boolean", "nullable": true, "description": "the compression ended by free_standing.failure_drop before the target strain"},
              "failure_mode": {"type": "string", "nullable": true, "enum": ["wire_break", "grains_spilling", "bulging", "unresolved", null], "description": "how it failed, as far as the record shows it (docs/model.md, \"How it failed\"), the first that holds: wire_break (a wire segment broke within a row of the largest raw sigma1), grains_spilling (spilled_fraction > free_standing.max_lost_fraction), bulging (bulge_m > free_standing.max_height_loss x the settled radius), else unresolved (a failure inside the column's width, such as a shear band, or none); null without a compression reading, or for a record written before it was read"},
              "spilled_fraction": {"type": "number", "nullable": true, "description": "share of the grains' volume that left the column (beyond free_standing.escape_distance_m) during the compression: lost at its end minus lost when settled [1]"},
              "bulge_m": {"type": "number", "nullable": true, "description": "how much the column's widest slice widened, settled to the end of the compression (largest radius of profile_at_end minus largest of profile_settled) [m]"},
              "predicted_unconfined_strength_pa": {"type": "number", "nullable": true, "description": "2 c cos(phi) / (1 - sin(phi)) of mohr_coulomb [Pa]; null without an envelope"},
              "definition": {"type": "string"},
              "quasi_static": {"type": "boolean", "description": "the triaxial test's criteria over the compression rows that bear at least 10 % of the largest sigma1"},
              "max_inertial_number": {"type": "number", "nullable": true, "description": "largest inertial number, with the column's own sigma1 as its pressure [1]"},
              "mean_kinetic_to_elastic": {"type": "number", "nullable": true, "description": "mean kinetic/elastic energy ratio over those rows [1]"},
              "wire_breaks": {"type": "array", "description": "only with a breakable wire: the segments that broke during the test, in order", "items": {"$ref": "#/components/schemas/SummaryWireBreak"}},
              "peak_failure": {"type": "string", "nullable": true, "enum": ["grains", "wire", "grains_after_break", null], "description": "only with a breakable wire: what gave way at the largest raw sigma1 (as a test's peak_failure); null when the curve cannot be read"}}},
          "pull_out": {"type": "object", "description": "only with a pull-out (free_standing.pull_out_speed_m_per_s), which replaces the compression (whose figures are then null): one end of the wire pulled out of the settled column (docs/model.md, \"Pulling the wire out\")",
            "required": ["peak_pull_force_n", "pulled_length_at_peak_m", "pulled_length_m", "wire_in_column_before_m", "wire_in_column_m", "grains_in_column", "wire_broke", "ramp_inertia_n", "end", "pulled_node", "definition"],
            "properties": {
              "peak_pull_force_n": {"type": "number", "nullable": true, "description": "the largest pull force, a mean over one sample interval [N]"},
              "pulled_length_at_peak_m": {"type": "number", "nullable": true, "description": "how far the end had been pulled then [m]"},
              "pulled_length_m": {"type": "number", "nullable": true, "description": "how far the end was pulled in all [m]"},
              "wire_in_column_before_m": {"type": "number", "nullable": true, "description": "wire in the settled column when the pull began (rest length) [m]"},
              "wire_in_column_m": {"type": "number", "nullable": true, "description": "wire left in it at the end [m]"},
              "grains_in_column": {"type": "integer", "description": "grains within free_standing.escape_distance_m of the axis at the end"},
              "wire_broke": {"type": "boolean", "description": "a segment broke during the pull (a breakable wire; the breaks are in wire_breaks)"},
              "ramp_inertia_n": {"type": "number", "nullable": true, "description": "M_w v pi / (2 T): the force that accelerates the whole wire (masses as scaled) at the ramp's largest acceleration [N]; null without a ramp. A peak during the ramp of this order is inertia (a warning says so)"},
              "end": {"type": "string", "enum": ["length", "wire_out", "time", "host"], "description": "what ended it: the pulled length, the pulled piece's exit from the column, pull_out_max_time_s, or the host"},
              "pulled_node": {"type": "integer", "description": "the wire node driven"},
              "definition": {"type": "string"}}},
          "steps": {"type": "integer", "description": "time steps of the test"},
          "wall_time_s": {"type": "number", "description": "wall time of the test [s]"},
          "threads": {"type": "integer", "description": "engine threads the test ran with"}}},
      "SummaryWireBreak": {"type": "object", "description": "A segment of the wire removed during a test (docs/model.md, \"A wire that breaks\").",
        "required": ["time_s", "axial_strain", "position_m", "segment", "cause", "segment_strain", "released_energy_j"],
        "properties": {
          "time_s": {"type": "number", "description": "since the test started [s]"},
          "axial_strain": {"type": "number", "nullable": true, "description": "the test's axial strain after that step [1]"},
          "position_m": {"type": "number", "description": "along the wire: the rest length from its first node to the segment's middle [m]"},
          "segment": {"type": "integer", "description": "the segment, between nodes segment and segment + 1"},
          "cause": {"type": "string", "enum": ["broke", "cut"]},
          "segment_strain": {"type": "number", "nullable": true, "description": "its strain when it broke [1]"},
          "released_energy_j": {"type": "number", "nullable": true, "description": "1/2 k (strain l_w)^2, the elastic energy its spring held, dissipated by the break [J]"}}},
      "SummaryTest": {"type": "object",
        "description": "One triaxial test. peak_*, sigma1_pa, sigma3_effective_pa: the state at the largest raw sample of q = sigma1 - sigma3_eff during loading (definitions.max_q); yield: the state at the maximum of the smoothed stress ratio (definitions.yield).",
        "required": ["confining_pressure_pa", "plate_speed_m_per_s", "peak_deviatoric_stress_pa", "peak_axial_strain", "sigma1_pa", "sigma3_effective_pa",
          "max_q_shape", "yield", "residual_stress_ratio", "consolidation", "hold_time_s", "consolidated_sigma1_pa",
          "consolidation_target_pa", "consolidated", "loading_start", "quasi_static",
          "max_inertial_number", "mean_kinetic_to_elastic", "max_kinetic_to_elastic", "steps", "wall_time_s", "threads"],
        "properties": {
          "confining_pressure_pa": {"type": "number", "description": "sigma3 applied (triaxial.confining_pressures_pa) [Pa]"},
          "plate_speed_m_per_s": {"type": "number", "description": "the top plate's loading speed in this test (triaxial.plate_speed_m_per_s) [m/s]"},
          "peak_deviatoric_stress_pa": {"type": "number", "nullable": true, "description": "largest raw q during loading [Pa]"},
          "wire_breaks": {"type": "array", "description": "only with a breakable wire (specimen.wire.breaking_strain): the segments that broke during the test, in order", "items": {"$ref": "#/components/schemas/SummaryWireBreak"}},
          "peak_failure": {"type": "string", "enum": ["grains", "wire", "grains_after_break"], "description": "only with a breakable wire: what gave way at the peak of q: the grains with the wire whole, the wire (its first break within a row of the peak), or the grains on a wire broken before"},
          "peak_axial_strain": {"type": "number", "nullable": true, "description": "axial strain at that sample [1]"},
          "sigma1_pa": {"type": "number", "nullable": true, "description": "sigma1 at that sample [Pa]"},
          "sigma3_effective_pa": {"type": "number", "nullable": true, "description": "sigma3_eff at that sample [Pa]"},
          "max_q_shape": {"type": "string", "nullable": true,
            "description": "what kind of maximum the smoothed q curve has (definitions.shape); null when the loading curves cannot be read (a warning says why)"},
          "yield": {"type": "object", "nullable": true,
            "description": "the yield state: the maximum of the smoothed stress ratio, with its Mohr circle (docs/model.md, \"How yield is read\"); null when the loading curves cannot be read",
            "required": ["shape", "stress_ratio", "axial_strain", "sigma1_pa", "sigma3_effective_pa", "deviatoric_stress_pa"],
            "properties": {
              "shape": {"type": "string", "description": "what kind of maximum the smoothed stress ratio has (definitions.shape); rising: the state is a lower bound"},
              "stress_ratio": {"type": "number", "nullable": true, "description": "(sigma1 - sigma3_eff)/(sigma1 + sigma3_eff) there, = sin of the mobilised friction angle [1]"},
              "axial_strain": {"type": "number", "nullable": true, "description": "axial strain there [1]"},
              "sigma1_pa": {"type": "number", "nullable": true, "description": "smoothed sigma1 there [Pa]"},
              "sigma3_effective_pa": {"type": "number", "nullable": true, "description": "smoothed sigma3_eff there [Pa]"},
              "deviatoric_stress_pa": {"type": "number", "nullable": true, "description": "sigma1_pa - sigma3_effective_pa [Pa]"}}},
          "residual_stress_ratio": {"type": "number", "nullable": true, "description": "mean raw stress ratio over the last definitions.end_window_strain of axial strain [1]; null when the curves cannot be read"},
          "consolidation": {"type": "string", "enum": ["cell_pressure", "effective"], "description": "what sigma1 was brought to while sigma3 was held (triaxial.consolidation): sigma3 (cell_pressure) or sigma3_eff (effective)"},
          "hold_time_s": {"type": "number", "description": "how long sigma3 was held before loading: triaxial.hold_time_s, or longer until the column had consolidated [s]"},
          "consolidated_sigma1_pa": {"type": "number", "nullable": true, "description": "sigma1 averaged over the last consolidation window before loading [Pa]"},
          "consolidation_target_pa": {"type": "number", "nullable": true, "description": "what sigma1 was to be brought to as loading started: sigma3 (cell_pressure) or sigma3_eff over the last consolidation window (effective) [Pa]; null in a test file written before it was recorded"},
          "consolidated": {"type": "boolean", "nullable": true, "description": "consolidated_sigma1_pa within definitions.max_consolidation_mismatch of consolidation_target_pa (otherwise the test warns \"had not consolidated\"); null in a test file written before it was recorded"},
          "loading_start": {"type": "object", "nullable": true,
            "description": "the column as loading started, and what the pressure ramp and hold did to it (definitions.loading_start); null when the test has no loading row",
            "required": ["sigma1_pa", "sigma3_effective_pa", "stress_ratio", "axial_strain", "rebound_axial_strain", "radial_strain"],
            "properties": {
              "sigma1_pa": {"type": "number", "nullable": true, "description": "sigma1 averaged over the last consolidation window (5 ms) up to the first loading row [Pa]"},
              "sigma3_effective_pa": {"type": "number", "nullable": true, "description": "sigma3_eff averaged over the same rows [Pa]"},
              "stress_ratio": {"type": "number", "nullable": true, "description": "(sigma1 - sigma3_eff)/(sigma1 + sigma3_eff) of those means [1]; < 0: the membrane squeezes the column harder than the plate presses it"},
              "axial_strain": {"type": "number", "nullable": true, "description": "axial strain of the ramp and hold, from the test's first row to the first loading row (> 0 shortened) [1]"},
              "rebound_axial_strain": {"type": "number", "nullable": true, "description": "how much the column lengthened after its shortest before loading, relative to its first height (>= 0) [1]: extension flow during the hold"},
              "radial_strain": {"type": "number", "nullable": true, "description": "radial strain of the ramp and hold (> 0 narrowed) [1]"}}},
          "quasi_static": {"type": "boolean", "description": "the largest inertial number and the mean kinetic/elastic energy ratio during loading were within their thresholds (docs/model.md)"},
          "max_inertial_number": {"type": "number", "nullable": true, "description": "largest inertial number during loading [1]"},
          "mean_kinetic_to_elastic": {"type": "number", "nullable": true, "description": "mean kinetic/elastic energy ratio during loading (the criterion) [1]"},
          "max_kinetic_to_elastic": {"type": "number", "nullable": true, "description": "its largest sample (slip events; not a criterion) [1]"},
          "steps": {"type": "integer", "description": "time steps of this test"},
          "wall_time_s": {"type": "number", "description": "wall time of this test [s]"},
          "threads": {"type": "integer", "description": "engine threads this test ran with"}}},
      "MohrCoulomb": {"type": "object",
        "description": "A Mohr-Coulomb envelope fitted to the tests' circles (definitions.friction_angle). When the fit is impossible every figure is null and error says why.",
        "required": ["friction_angle_deg", "cohesion_pa", "cohesion_fixed_at_zero", "r_squared", "paper_top_line_angle_deg", "caveats", "nonnegative", "cohesionless", "states"],
        "properties": {
          "friction_angle_deg": {"type": "number", "nullable": true, "description": "phi, from sin(phi) = slope of the line through the circle tops [deg]"},
          "cohesion_pa": {"type": "number", "nullable": true, "description": "c = intercept / cos(phi) [Pa]"},
          "cohesion_fixed_at_zero": {"type": "boolean", "nullable": true, "description": "true with a single test: c = 0 was imposed, not fitted"},
          "r_squared": {"type": "number", "nullable": true, "description": "of the line through the tops [1]; null with one or two tests (no degree of freedom left)"},
          "paper_top_line_angle_deg": {"type": "number", "nullable": true, "description": "alpha = atan(slope), the paper's reading [deg]"},
          "caveats": {"type": "array", "description": "what could make a reader misread this unconstrained fit (definitions.caveats); each is also in warnings. Empty when the fit is impossible",
            "items": {"type": "object", "required": ["code", "message"], "properties": {
              "code": {"type": "string", "enum": ["single_pressure", "two_pressures", "narrow_band", "negative_cohesion", "negative_friction_angle"]},
              "message": {"type": "string", "description": "one sentence for a reader, with the figures and the constrained fits"}}}},
          "nonnegative": {"$ref": "#/components/schemas/MohrEnvelope"},
          "cohesionless": {"$ref": "#/components/schemas/MohrEnvelope"},
          "error": {"type": "string", "description": "why the fit is impossible; only then"},
          "states": {"type": "string", "description": "which states of the tests the fit went through"}}},
      "MohrEnvelope": {"type": "object", "nullable": true,
        "description": "A constrained Mohr-Coulomb envelope (definitions.constrained_fits): nonnegative, the least-squares fit with c >= 0 and phi >= 0; cohesionless, the one-parameter fit with c = 0. Null when the fit is impossible",
        "required": ["friction_angle_deg", "cohesion_pa", "r_squared"],
        "properties": {
          "friction_angle_deg": {"type": "number", "nullable": true, "description": "phi [deg]"},
          "cohesion_pa": {"type": "number", "nullable": true, "description": "c [Pa]"},
          "r_squared": {"type": "number", "nullable": true, "description": "1 - SS_res/SS_tot of the circle tops (may be below 0); null when no degree of freedom is left"}}},
      "SummaryDefinitions": {"type": "object",
        "description": "What the strength figures mean, in words, with the tolerances used (engine/analysis/strength.hpp, CurveTolerances)",
        "required": ["yield", "max_q", "shape", "residual_stress_ratio", "loading_start", "consolidated", "max_consolidation_mismatch", "smoothing_strain", "shape_tolerance", "end_window_strain", "autocorrelation_lag", "friction_angle", "constrained_fits", "caveats"],
        "properties": {
          "yield": {"type": "string"}, "max_q": {"type": "string"}, "shape": {"type": "string"},
          "residual_stress_ratio": {"type": "string"},
          "loading_start": {"type": "string"},
          "consolidated": {"type": "string"},
          "max_consolidation_mismatch": {"type": "number", "description": "largest relative difference of sigma1 from its consolidation target as loading starts for a consolidated test [1]"},
          "smoothing_strain": {"type": "number", "description": "width of the centred moving average, in axial strain [1]"},
          "shape_tolerance": {"type": "number", "description": "a drop after the maximum, or a rise over the end window, counts above this fraction of the maximum [1]"},
          "end_window_strain": {"type": "number", "description": "strain window at the end of a test for rising and the residual ratio [1]"},
          "autocorrelation_lag": {"type": "string"}, "friction_angle": {"type": "string"},
          "constrained_fits": {"type": "string"}, "caveats": {"type": "string"}}},
      "SummarySpecimen": {"type": "object",
        "description": "The prepared specimen. Volume fractions: of the whole sample (sample_volume_m3) and of its core, a grain diameter away from the membrane's inner surface and both plates (engine/specimen/packing.hpp); wire as a cylinder along its length.",
        "required": ["cell", "grain_volume_fraction", "wire_volume_fraction", "wire_length_per_volume_m_per_m3", "core_grain_volume_fraction", "core_wire_volume_fraction",
          "sample_volume_m3", "grains", "wire_nodes", "wire_length_m", "nozzle_path_m", "pile_height_m", "settled",
          "preparation_time_step_s", "preparation_steps", "preparation_wall_time_s"],
        "properties": {
          "cell": {"type": "string", "enum": ["membrane", "cuboid"], "description": "the triaxial cell that ran (triaxial.cell): membrane, the flexible pressurised membrane round a column; cuboid, six rigid walls round a box (its series' membrane_contacts count the grains' contacts with its four side walls)"},
          "grain_volume_fraction": {"type": "number", "description": "[1]"},
          "wire_volume_fraction": {"type": "number", "description": "[1]"},
          "wire_length_per_volume_m_per_m3": {"type": "number", "nullable": true, "description": "string length per volume: wire_length_m / sample_volume_m3, the figure printed columns are designed by [m/m^3]"},
          "wire_pieces": {"type": "array", "description": "only for a breakable or cut wire (specimen.wire.breaking_strain, cuts_at_m, cut_every_loops): the prepared wire's pieces in chain order",
            "items": {"type": "object", "required": ["first_node", "nodes", "rest_length_m", "length_m"],
              "properties": {
                "first_node": {"type": "integer", "description": "its first node"},
                "nodes": {"type": "integer", "description": "its nodes"},
                "rest_length_m": {"type": "number", "description": "(nodes - 1) l_w, its length as laid, unstretched [m]"},
                "length_m": {"type": "number", "description": "its length along its nodes [m]"}}}},
          "wire_cuts": {"type": "integer", "description": "only with wire_pieces: segments the job cut"},
          "wire_breaks_in_preparation": {"type": "integer", "description": "only with wire_pieces: segments that broke while the specimen was prepared"},
          "core_grain_volume_fraction": {"type": "number", "description": "[1]"},
          "core_wire_volume_fraction": {"type": "number", "description": "[1]"},
          "sample_volume_m3": {"type": "number", "description": "pi R^2 h of the pile [m^3]"},
          "grains": {"type": "integer"},
          "wire_nodes": {"type": "integer"},
          "wire_length_m": {"type": "number", "description": "wire laid [m]"},
          "nozzle_path_m": {"type": "number", "description": "path the nozzle travelled while laying: the wire it would have laid had it never been blocked (a warning below 80 % laid) [m]"},
          "pile_height_m": {"type": "number", "description": "bottom plate to top plate [m]"},
          "settled": {"type": "boolean", "description": "the kinetic energy fell below the threshold within specimen.pouring.max_preparation_time_s (else a warning)"},
          "preparation_time_step_s": {"type": "number", "description": "[s]"},
          "preparation_steps": {"type": "integer"},
          "preparation_wall_time_s": {"type": "number", "description": "[s]"},
          "grain_sizes": {"type": "object",
            "description": "only with specimen.grain_sizes: the grains drawn against the curve asked for (docs/model.md, \"Size distribution\"). D_x: the diameter below which a fraction x of the mass lies; ks_distance: the Kolmogorov-Smirnov distance between the drawn and requested number distributions, which a true draw exceeds with probability 1 % at ks_critical_1pct",
            "required": ["requested", "drawn", "ks_distance", "ks_critical_1pct", "grains"],
            "properties": {
              "requested": {"$ref": "#/components/schemas/GradingFigures"},
              "drawn": {"$ref": "#/components/schemas/GradingFigures"},
              "ks_distance": {"type": "number", "description": "[1]"},
              "ks_critical_1pct": {"type": "number", "description": "1.628/sqrt(grains) [1]"},
              "grains": {"type": "integer"}}}}},
      "GradingFigures": {"type": "object",
        "required": ["d10_m", "d50_m", "d60_m", "uniformity_coefficient"],
        "properties": {
          "d10_m": {"type": "number", "description": "[m]"},
          "d50_m": {"type": "number", "description": "[m]"},
          "d60_m": {"type": "number", "description": "[m]"},
          "uniformity_coefficient": {"type": "number", "description": "C_u = D60/D10 [1]"}}},
      "SummaryWire": {"type": "object",
        "description": "The wire and the autocorrelation of its segment strains at the end of the test at the highest pressure (docs/model.md, \"Wire autocorrelation\"; definitions.autocorrelation_lag). Lags are null without wire or without such a maximum (a warning says why).",
        "required": ["pattern", "autocorrelation_lag_m", "autocorrelation_prominent_lag_m"],
        "properties": {
          "pattern": {"$ref": "#/components/schemas/JobSpec/properties/specimen/properties/wire/properties/pattern"},
          "autocorrelation_lag_m": {"type": "number", "nullable": true, "description": "first local maximum after lag 0 [m]"},
          "autocorrelation_prominent_lag_m": {"type": "number", "nullable": true, "description": "first local maximum whose prominence exceeds the white-noise 95 % band [m]"}}},
      "SummaryEngine": {"type": "object",
        "required": ["time_step_s", "steps", "wall_time_s", "body_steps_per_second", "threads", "density_scale"],
        "properties": {
          "time_step_s": {"type": "number", "description": "the tests' time step [s]"},
          "steps": {"type": "integer", "description": "the preparation's and all tests' steps"},
          "wall_time_s": {"type": "number", "description": "the stages' wall times added (tests that ran at once overlap) [s]"},
          "body_steps_per_second": {"type": "number", "nullable": true, "description": "bodies x steps / wall_time_s; null when wall_time_s is 0"},
          "threads": {"type": "integer", "description": "the preparation's engine threads (each test's: tests[].threads)"},
          "density_scale": {"type": "number", "description": "engine.density_scale of the job [1]"}}},
      "State": {"type": "string", "enum": ["queued", "preparing", "running", "succeeded", "failed", "cancelled"]},
      "Study": {"type": "object", "required": ["name", "base"],
        "description": "docs/studies.md: the base job and either vary (field path -> list of values, a full grid) or points (a list of {field path: value}); every point is validated as a job; at most --max-study-points points.",
        "properties": {"name": {"type": "string", "maxLength": 200}, "comment": {"type": "string", "maxLength": 10000},
          "base": {"$ref": "#/components/schemas/JobSpec"},
          "vary": {"type": "object", "additionalProperties": {"type": "array", "minItems": 1,
            "items": {"description": "one value of the field (its type is the field's)"}}},
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
void add_common_replies(json::object& responses, bool needs_token, bool has_body, bool writes)
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
    if (writes)
        add("507", error_reply("insufficient_storage: the data directory's disk is full (the message names the file "
                               "that could not be written)", {{"Retry-After", "seconds"}}));
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
    // The web page's files, answered outside /v1 (handlers/static_files.hpp).
    for (const auto& page : page_openapi_routes()) ops.emplace_back("GET", page);
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
        add_common_replies((*op)["responses"].as_object(), r.path.substr(0, 4) == "/v1/", r.method == http::verb::post,
            r.method == http::verb::post || r.method == http::verb::delete_);
        if (r.method == http::verb::get)
            item->as_object()["head"] = head_of(*op, std::string((*op)["operationId"].as_string()) + "Head");
    }
    doc["tags"] = json::array{
        json::object{{"name", "jobs"}, {"description", "Submit, follow, cancel and delete jobs"}},
        json::object{{"name", "results"}, {"description", "A succeeded job's summary, result file and data"}},
        json::object{{"name", "studies"}, {"description", "Parameter studies: one job per point"}},
        json::object{{"name", "service"}, {"description", "Health, metrics, this document, the job spec's schema"}},
        json::object{{"name", "page"}, {"description", "The web page's files (docs/web.md), served outside /v1"}}};
}

/// The summary's shape strings (tests[].max_q_shape, tests[].yield.shape) as
/// the engine writes them, into the Summary schema of `doc`.
void add_curve_shapes(json::object& doc)
{
    namespace an = engine::analysis;
    json::array shapes;
    for (an::CurveShape s : {an::CurveShape::peak, an::CurveShape::plateau, an::CurveShape::rising})
        shapes.emplace_back(an::to_string(s));
    json::object& test = doc.at("components").at("schemas").at("SummaryTest").as_object();
    test.at("properties").at("yield").at("properties").at("shape").as_object()["enum"] = shapes;
    shapes.emplace_back(nullptr);  // OpenAPI 3.0: a nullable enum lists null among its values
    test.at("properties").at("max_q_shape").as_object()["enum"] = std::move(shapes);
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
        add_curve_shapes(d.as_object());
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
    // Each stage's threads: under Slurm, the CPUs each Slurm job asks for
    // (--slurm-cpus-per-task, passed to wiredem as --threads).
    const auto& queue_config = svc.queue.config();
    body["threads_per_job"] = queue_config.slurm ? queue_config.slurm->cpus_per_task : queue_config.threads_per_job;
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
