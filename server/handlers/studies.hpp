// /v1/studies: parameter studies (api/study.hpp). A study is a document and
// one job per point, created together in one transaction; its jobs are
// ordinary jobs (listed, run, cancelled and downloaded like any other), and
// the study routes show them together and summarise them.
#pragma once

#include "../http.hpp"
#include "../services.hpp"
#include "jobs.hpp"

#include <string>

namespace wiredem::server {

/// POST /v1/studies: validates the study and every point (as a job, and
/// against this server's limits), then creates its jobs; 201 with the study.
[[nodiscard]] Response handle_submit_study(const Request& req, Services& svc);
/// GET /v1/studies?limit=N&cursor=C: newest first, with counts of its jobs by state.
[[nodiscard]] Response handle_list_studies(const Request& req, const QueryParams& params, Services& svc);
/// GET /v1/studies/{id}: the study with each point's values and job.
[[nodiscard]] Response handle_get_study(const Request& req, const std::string& id, Services& svc);
/// DELETE /v1/studies/{id}: cancels every job of the study that has not
/// ended; with ?remove=true, deletes a study whose jobs have all ended, with
/// its jobs and their files (204; 409 while one has not ended).
[[nodiscard]] Response handle_delete_study(
    const Request& req, const std::string& id, const QueryParams& params, Services& svc);
/// GET /v1/studies/{id}/summary: api::study_summary of its jobs as they are now.
[[nodiscard]] Response handle_get_study_summary(const Request& req, const std::string& id, Services& svc);

} // namespace wiredem::server
