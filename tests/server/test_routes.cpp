// The OpenAPI document against the router's own table (server/router.hpp):
// every operation the router dispatches is documented with its methods, every
// documented operation is one the router dispatches, and every status the
// router answers — probed through the real Router over a real store, every
// route with every method and the usual mistakes — is documented for that
// operation. Also what a list reads of the store (item 7 of issue 18).
#include "server_fixture.hpp"

#include "handlers/meta.hpp"
#include "handlers/results.hpp"
#include "router.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <set>

namespace wiredem::server {
namespace {
namespace json = boost::json;

std::string lower(std::string_view s)
{
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

const json::object& paths() { return openapi_document().at("paths").as_object(); }

/// The fourth segment of a result data path ("/v1/jobs/{id}/tests/…" → "tests"), or "".
std::string result_data_segment(std::string_view path)
{
    constexpr std::string_view prefix = "/v1/jobs/{id}/";
    if (path.substr(0, prefix.size()) != prefix) return {};
    const std::string_view rest = path.substr(prefix.size());
    return std::string(rest.substr(0, rest.find('/')));
}

const std::set<std::string> http_methods{"get", "head", "post", "put", "delete", "patch", "options", "trace"};

TEST(OpenApi, EveryOperationOfTheRoutersTableIsDocumentedWithItsMethods)
{
    ASSERT_FALSE(route_table().empty());
    for (const Route& r : route_table()) {
        const std::string method = lower(http::to_string(r.method));
        const json::value* item = paths().if_contains(r.path);
        ASSERT_TRUE(item) << r.path << " is served but not documented";
        const json::value* op = item->as_object().if_contains(method);
        ASSERT_TRUE(op) << method << " " << r.path << " is served but not documented";
        EXPECT_EQ(op->at("operationId").as_string(), r.operation_id) << r.path;
        EXPECT_EQ(op->at("tags").at(0).as_string(), r.tag) << r.path;
        EXPECT_TRUE(op->as_object().contains("summary")) << method << " " << r.path;
        if (r.method == http::verb::get) {
            EXPECT_TRUE(item->as_object().contains("head")) << "HEAD " << r.path;
        }
        // the replies every route can give
        const auto& responses = op->at("responses").as_object();
        for (const char* status : {"400", "403", "405", "413", "431", "500", "503"})
            EXPECT_TRUE(responses.contains(status)) << method << " " << r.path << " lacks " << status;
        if (r.path.substr(0, 4) == "/v1/") {
            ASSERT_TRUE(responses.contains("401")) << method << " " << r.path;
            EXPECT_TRUE(responses.at("401").at("headers").as_object().contains("WWW-Authenticate"));
        }
    }
}

// The web page's files are served outside the table (handle_static): the
// document names them too, with HEAD, as the table's GETs.
TEST(OpenApi, TheWebPagesRoutesAreDocumented)
{
    for (const Route& r : page_openapi_routes()) {
        const json::value* item = paths().if_contains(r.path);
        ASSERT_TRUE(item) << r.path << " is served but not documented";
        EXPECT_EQ(item->at("get").at("operationId").as_string(), r.operation_id);
        EXPECT_EQ(item->at("get").at("tags").at(0).as_string(), "page");
        EXPECT_TRUE(item->as_object().contains("head")) << r.path;
    }
}

TEST(OpenApi, EveryDocumentedOperationIsOneTheRouterAnswers)
{
    std::set<std::string> operation_ids;
    for (const auto& [path, item] : paths()) {
        for (const auto& [key, op] : item.as_object()) {
            if (!http_methods.count(std::string(key))) continue;  // parameters, summary
            const std::string method = key == "head" ? "get" : std::string(key);
            bool served = false;
            for (const Route& r : route_table())
                served = served || (r.path == path && lower(http::to_string(r.method)) == method);
            // the result data routes, answered before the table (handlers/results.hpp)
            if (!served && method == "get") served = is_result_data_route(result_data_segment(path));
            // the web page's files, answered after it (handlers/static_files.hpp)
            for (const Route& r : page_openapi_routes())
                served = served || (r.path == path && method == "get");
            EXPECT_TRUE(served) << key << " " << path << " is documented but not served";
            ASSERT_TRUE(op.as_object().contains("operationId")) << key << " " << path;
            EXPECT_TRUE(operation_ids.insert(std::string(op.at("operationId").as_string())).second)
                << "operationId " << op.at("operationId") << " twice";
        }
    }
}

/// A request as a client sends it.
Request request(http::verb method, const std::string& target, const std::string& body = {},
    std::initializer_list<std::pair<http::field, std::string>> headers = {})
{
    Request req{method, target, 11};
    req.set(http::field::host, "127.0.0.1:8080");
    for (const auto& [f, v] : headers) req.set(f, v);
    if (!body.empty()) {
        req.set(http::field::content_type, "application/json");
        req.body() = body;
    }
    req.prepare_payload();
    return req;
}

TEST(OpenApi, EveryStatusTheRouterAnswersIsDocumentedForItsOperation)
{
    fuzz::ServerFixture f;
    // The paths to probe: the table's and the result data routes', each id
    // as a succeeded, a failed, a queued, an unknown and a malformed job.
    std::set<std::string> templates;
    for (const Route& r : route_table()) templates.insert(std::string(r.path));
    for (const auto& [path, item] : result_data_openapi_paths()) templates.insert(std::string(path));
    const std::vector<std::pair<std::string, std::string>> fill{
        {"{test}", "sigma3_20000"}, {"{k}", "0"}, {"{array}", "positions"}};
    const std::vector<std::string> ids{fuzz::succeeded_job_id, fuzz::failed_job_id, fuzz::queued_job_id,
        "ffffffffffffffffffffffff", "not-an-id"};
    const std::vector<http::verb> methods{http::verb::get, http::verb::head, http::verb::post, http::verb::put,
        http::verb::patch, http::verb::delete_};
    int probes = 0;
    std::set<std::string> seen;  // "status path"
    // DELETE last: it removes the succeeded job the other probes read.
    for (http::verb m : methods)
    for (const std::string& tmpl : templates) {
        for (const std::string& id : ids) {
            if (tmpl.find("{id}") == std::string::npos && id != ids.front()) break;  // one target is enough
            std::string target = tmpl;
            for (const auto& [name, value] : fill)
                for (auto at = target.find(name); at != std::string::npos; at = target.find(name))
                    target.replace(at, name.size(), value);
            if (const auto at = target.find("{id}"); at != std::string::npos) target.replace(at, 4, id);
            const std::vector<std::string> targets{target, target + "?unknown=1", target + "?remove=true"};
            for (const std::string& t : targets)
                    for (const std::string& body : {std::string(), std::string("{}"), std::string("{")}) {
                        std::vector<Request> variants{request(m, t, body),
                            request(m, t, body, {{http::field::origin, "https://evil.example"}}),
                            request(m, t, body, {{http::field::host, "evil.example"}})};
                        for (const Request& req : variants) {
                            const unsigned status = status_of(f.router().dispatch(req));
                            ++probes;
                            const json::object& item = paths().at(tmpl).as_object();
                            const std::string method = lower(http::to_string(m));
                            const std::string code = std::to_string(status);
                            seen.insert(code + " " + tmpl);
                            if (item.contains(method)) {
                                EXPECT_TRUE(item.at(method).at("responses").as_object().contains(code))
                                    << method << " " << t << " answered " << code << ", not documented for " << tmpl;
                            } else {
                                // An operation the path has not: 405, or what the router answers
                                // before it looks at the method (Host, Origin, id): documented
                                // on every operation the path has.
                                for (const auto& [key, op] : item) {
                                    if (!http_methods.count(std::string(key))) continue;
                                    EXPECT_TRUE(op.at("responses").as_object().contains(code))
                                        << method << " " << t << " answered " << code << ", not documented for "
                                        << key << " " << tmpl;
                                }
                            }
                        }
                    }
        }
    }
    EXPECT_GT(probes, 1000);
    // The probes reached the handlers, not only the router's refusals.
    for (const char* s : {"200 /v1/jobs/{id}", "204 /v1/jobs/{id}", "200 /v1/jobs/{id}/result.h5", "404 /v1/jobs/{id}",
             "409 /v1/jobs/{id}/summary", "400 /v1/jobs/{id}", "403 /v1/jobs", "405 /v1/health"})
        EXPECT_TRUE(seen.count(s)) << s << " never answered";
    // The fixture puts back what the probes deleted (the fuzz target relies on it).
    f.restore();
    const std::string succeeded = std::string("/v1/jobs/") + fuzz::succeeded_job_id;
    EXPECT_EQ(status_of(f.router().dispatch(request(http::verb::get, succeeded + "/result.h5"))), 200u);
    EXPECT_EQ(status_of(f.router().dispatch(request(http::verb::get, succeeded + "/summary"))), 200u);
}

TEST(OpenApi, ByteRangesAreDocumentedWithTheirHeaders)
{
    fuzz::ServerFixture f;
    const auto res = f.router().dispatch(request(http::verb::get,
        std::string("/v1/jobs/") + fuzz::succeeded_job_id + "/result.h5", {}, {{http::field::range, "bytes=10-19"}}));
    ASSERT_EQ(status_of(res), 206u);
    const auto& headers = paths().at("/v1/jobs/{id}/result.h5").at("get").at("responses").at("206").at("headers").as_object();
    for (const char* h : {"ETag", "Accept-Ranges", "Content-Range", "Content-Disposition"})
        EXPECT_TRUE(headers.contains(h)) << h;
}

TEST(JobList, ShowsTheStoredNameWithoutReadingTheSpec)
{
    // The list takes a job's name from its own column: a spec it cannot
    // even parse does not matter to it (GET /v1/jobs/{id} does read it).
    fuzz::ServerFixture f;
    JobRecord job;
    job.id = "0000000000000000000000aa";
    job.created_ms = 2;
    job.name = "listed by its column";
    job.spec_json = "not JSON: a list that parsed it would show no name";
    JobRecord stored;
    ASSERT_EQ(f.store().insert(job, 1000, stored), InsertOutcome::created);
    const auto res = f.router().dispatch(request(http::verb::get, "/v1/jobs?limit=1"));
    ASSERT_EQ(status_of(res), 200u);
    const json::value body = json::parse(std::get<StringResponse>(res).body());
    const json::value& first = body.at("jobs").at(0);
    EXPECT_EQ(first.at("id").as_string(), job.id);
    EXPECT_EQ(first.at("name").as_string(), "listed by its column");
    EXPECT_FALSE(first.as_object().contains("spec"));
}

} // namespace
} // namespace wiredem::server
