// GET /v1/job-spec/schema: the job spec's JSON Schema (draft 2020-12), as the
// reader in api/ describes itself (api::job_spec_json_schema), for forms and
// editors; the OpenAPI document embeds the same schema in OpenAPI 3.0's dialect.
#pragma once

#include "../http.hpp"
#include "../services.hpp"

#include <boost/json/object.hpp>

namespace wiredem::server {

/// GET /v1/job-spec/schema.
[[nodiscard]] Response handle_job_spec_schema(const Request& req, Services& svc);

/// The job spec schema in OpenAPI 3.0.3's dialect of JSON Schema (exclusive
/// bounds as booleans beside minimum/maximum, `nullable` for [T, "null"], no
/// `const`), for components.schemas.JobSpec.
[[nodiscard]] const boost::json::object& job_spec_openapi_schema();

} // namespace wiredem::server
