// Hostile and malformed input: each answered with the right 4xx, and the
// server still serves afterwards. Also the service routes (health, metrics,
// OpenAPI) and bearer-token authentication.
#include "harness.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <iterator>

#include <thread>

namespace wiredem::test {
namespace {
namespace fs = std::filesystem;
namespace json = boost::json;

class HostileInput : public ::testing::Test {
protected:
    void SetUp() override { server_ = std::make_unique<ServerProcess>(tmp_.path() / "data", std::vector<std::string>{"--read-timeout", "2"}); }
    void TearDown() override
    {
        // Whatever came before, the server still answers.
        const auto health = http(server_->port(), "GET", "/v1/health");
        EXPECT_EQ(health.status, 200);
        EXPECT_EQ(health.json().at("status").as_string(), "ok");
    }
    std::uint16_t port() const { return server_->port(); }
    TempDir tmp_;
    std::unique_ptr<ServerProcess> server_;
};

TEST_F(HostileInput, MalformedJsonIs400InvalidJson)
{
    for (const std::string body : {"{\"name\": ", "not json", "{\"name\": \"a\",}", "[1, 2", "{\"seed\": 1} trailing"}) {
        const auto r = http(port(), "POST", "/v1/jobs", body);
        EXPECT_EQ(r.status, 400) << body;
        EXPECT_EQ(r.error_code(), "invalid_json") << body;
    }
    EXPECT_EQ(http(port(), "POST", "/v1/jobs", "", {{"Content-Type", "application/json"}}).error_code(), "invalid_json");
}

TEST_F(HostileInput, WrongTypesAndUnknownKeysAre400WithEveryFieldPath)
{
    const auto r = http(port(), "POST", "/v1/jobs", R"({"name": 5, "seed": "x", "bogus": true, "triaxial": []})");
    ASSERT_EQ(r.status, 400);
    EXPECT_EQ(r.error_code(), "invalid_job");
    const json::value doc = r.json();
    const auto& err = doc.at("error").as_object();
    EXPECT_EQ(err.at("field").as_string(), "name");
    std::vector<std::string> fields;
    for (const auto& d : err.at("details").as_array()) fields.emplace_back(d.at("field").as_string());
    for (const char* f : {"name", "seed", "bogus", "triaxial"})
        EXPECT_NE(std::find(fields.begin(), fields.end(), f), fields.end()) << f;
    const auto not_object = http(port(), "POST", "/v1/jobs", "[]");
    EXPECT_EQ(not_object.status, 400);
    EXPECT_EQ(not_object.error_code(), "invalid_job");
    const auto text = http(port(), "POST", "/v1/jobs", "{}", {{"Content-Type", "text/plain"}});
    EXPECT_EQ(text.status, 415);
}

TEST_F(HostileInput, TooManyBodiesIs400)
{
    const auto r = http(port(), "POST", "/v1/jobs", R"({"specimen": {"grain_count": 50000000}, "engine": {"max_bodies": 1000000000}})");
    EXPECT_EQ(r.status, 400);
    EXPECT_EQ(r.error_code(), "invalid_job");
}

TEST_F(HostileInput, HugeBodyIs413WhetherAnnouncedOrStreamed)
{
    // Announced: the limit applies as soon as the headers arrive.
    const auto announced = raw_exchange(port(),
        "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: 50000000\r\n\r\n{\"name\":");
    EXPECT_EQ(announced.status, 413);
    EXPECT_EQ(announced.error_code(), "body_too_large");
    // Streamed in chunks with no length given.
    std::string req = "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n";
    const std::string chunk(64 * 1024, ' ');
    for (int i = 0; i < 24; ++i) req += "10000\r\n" + chunk + "\r\n";
    req += "0\r\n\r\n";
    const auto streamed = raw_exchange(port(), req);
    EXPECT_EQ(streamed.status, 413);
}

TEST_F(HostileInput, TransferCodingsOtherThanChunkedAreRefusedAndTheConnectionClosed)
{
    // A body framed by a coding the server does not decode would otherwise be
    // read as the next request on the connection (request smuggling). The
    // refusal comes at once and the server closes the connection (the
    // exchange, left open by the client, ends long before its timeout):
    // 400 when chunked is not the final coding (RFC 9112 §6.3: the length
    // cannot be determined), 501 for a coding before it that is not served.
    const std::string smuggled = "GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
    const struct {
        const char* coding;
        int status;
    } cases[] = {{"gzip", 400}, {"gzip, chunked", 501}, {"chunked, gzip", 400}, {"identity", 400}, {"chunked ,", 400}};
    for (const auto& c : cases) {
        const auto t0 = std::chrono::steady_clock::now();
        const auto r = raw_exchange(port(),
            std::string("POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nTransfer-Encoding: ")
                + c.coding + "\r\n\r\n" + smuggled,
            std::chrono::milliseconds(6000), false);
        EXPECT_EQ(r.status, c.status) << c.coding;
        EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(3)) << c.coding << ": connection left open";
    }
    // Both a length and a coding: ambiguous, refused.
    EXPECT_EQ(raw_exchange(port(), "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                                   "Content-Length: 2\r\nTransfer-Encoding: chunked\r\n\r\n2\r\n{}\r\n0\r\n\r\n")
                  .status,
        400);
    // Chunked alone, in any case, is served.
    const auto ok = raw_exchange(port(), "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                                         "Transfer-Encoding: Chunked\r\nConnection: close\r\n\r\n2\r\n{}\r\n0\r\n\r\n");
    EXPECT_EQ(ok.status, 201) << ok.body;
}

TEST_F(HostileInput, AnErrorReplyToHeadHasNoBodySoTheNextReplyIsNotShifted)
{
    // fuzz_http_request (tests/fuzz): a HEAD that matched no route, or was
    // refused before routing, got its error body on the wire, which a client
    // reads as the start of the next reply on the connection.
    for (const std::string target : {"/v1/nope", "/v1/jobs/not-an-id", "/v1/health?x=1"}) {
        const auto r = raw_exchange(port(), "HEAD " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"
                                              "GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
        EXPECT_GE(r.status, 400) << target;
        EXPECT_EQ(r.body.rfind("HTTP/1.1 200", 0), 0u) << target << ": after the HEAD reply's headers came\n" << r.body;
    }
}

TEST_F(HostileInput, ErrorsThatEchoTheRequestAreStillValidUtf8Json)
{
    // fuzz_http_request (tests/fuzz): a Host header, or a percent-decoded
    // query parameter, that is not UTF-8 went into the error message as it
    // was, and the reply was not JSON any client would read.
    const auto host = raw_exchange(port(), "GET /v1/health HTTP/1.1\r\nHost: 1\xff" "27.0.0.1\r\nConnection: close\r\n\r\n");
    EXPECT_EQ(host.status, 400);
    EXPECT_EQ(host.error_code(), "bad_host") << host.body;
    EXPECT_NE(host.body.find("1\\\\xff27.0.0.1"), std::string::npos) << host.body;  // written as \xff
    const auto param = http(port(), "GET", "/v1/jobs?%FF%C3=1");
    EXPECT_EQ(param.status, 400);
    EXPECT_EQ(param.error_code(), "bad_parameter") << param.body;
}

// What an error reply echoes is bounded: a 0.9 MB unknown key (once a 400
// of 2.7 MB, the key in the field and the message, control bytes escaped)
// is cut and says its length; a thousand unknown keys give 100 details and
// one "and N more problems".
TEST_F(HostileInput, ErrorRepliesEchoTheRequestBoundedNotWhole)
{
    const auto huge = http(port(), "POST", "/v1/jobs", "{\"" + std::string(900'000, 'k') + "\": 1}");
    EXPECT_EQ(huge.status, 400);
    EXPECT_EQ(huge.error_code(), "invalid_job") << huge.body.substr(0, 300);
    EXPECT_LT(huge.body.size(), 8192u);
    EXPECT_NE(huge.body.find("(900000 bytes)"), std::string::npos) << huge.body.substr(0, 3000);

    std::string many = "{";
    for (int k = 0; k < 1000; ++k) many += (k ? ", \"" : "\"") + std::string("bogus_") + std::to_string(k) + "\": 1";
    many += "}";
    const auto r = http(port(), "POST", "/v1/jobs", many);
    EXPECT_EQ(r.status, 400);
    const json::value doc = r.json();
    const json::array& details = doc.at("error").at("details").as_array();
    ASSERT_EQ(details.size(), 101u);
    EXPECT_EQ(details.back().at("message").as_string(), "and 900 more problems");
}

// Expect: 100-continue is answered with 100 as soon as the headers pass
// (curl waited a second for it on every submit), and the body then read;
// any other expectation is 417.
TEST_F(HostileInput, ExpectContinueIsAnsweredWith100BeforeTheBody)
{
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    ASSERT_GE(fd, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port());
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    const std::string body = R"({"name": "expecting"})";
    const std::string head = "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                             "Content-Length: " + std::to_string(body.size()) + "\r\nExpect: 100-continue\r\n"
                             "Connection: close\r\n\r\n";
    ASSERT_EQ(::send(fd, head.data(), head.size(), MSG_NOSIGNAL), static_cast<ssize_t>(head.size()));
    const auto read_some = [&](int timeout_ms) {
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, timeout_ms) <= 0) return std::string();
        char buf[4096];
        const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
        return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
    };
    const std::string interim = read_some(5000);
    EXPECT_EQ(interim.rfind("HTTP/1.1 100 Continue\r\n", 0), 0u) << interim;
    ASSERT_EQ(::send(fd, body.data(), body.size(), MSG_NOSIGNAL), static_cast<ssize_t>(body.size()));
    std::string reply;
    for (std::string more; !(more = read_some(5000)).empty();) reply += more;
    ::close(fd);
    EXPECT_EQ(reply.rfind("HTTP/1.1 201", 0), 0u) << reply;

    const auto other = raw_exchange(port(), "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                                            "Content-Length: 2\r\nExpect: 200-ok\r\nConnection: close\r\n\r\n{}");
    EXPECT_EQ(other.status, 417) << other.body;
}

// Host, Origin and Idempotency-Key given twice are refused (RFC 9112 §3.2
// for Host): the first was taken, and a proxy may have read the second.
TEST_F(HostileInput, SingleHeadersGivenTwiceAre400)
{
    for (const std::string twice : {"Host: 127.0.0.1\r\nHost: evil.example\r\n",
             "Host: 127.0.0.1\r\nOrigin: http://127.0.0.1\r\nOrigin: http://evil.example\r\n",
             "Host: 127.0.0.1\r\nIdempotency-Key: a\r\nIdempotency-Key: b\r\n"}) {
        const auto r = raw_exchange(port(), "GET /v1/health HTTP/1.1\r\n" + twice + "Connection: close\r\n\r\n");
        EXPECT_EQ(r.status, 400) << twice << r.body;
        EXPECT_NE(r.body.find("more than once"), std::string::npos) << r.body;
    }
}

TEST_F(HostileInput, AnotherSitesPageCannotReachTheServer)
{
    // DNS rebinding: a page of evil.example whose name now points at
    // 127.0.0.1 sends Host: evil.example; refused on every route.
    for (const char* target : {"/v1/health", "/v1/jobs", "/metrics"}) {
        const auto r = raw_exchange(port(), std::string("GET ") + target + " HTTP/1.1\r\nHost: evil.example:" + std::to_string(port())
                                                + "\r\nConnection: close\r\n\r\n");
        EXPECT_EQ(r.status, 400) << target;
        EXPECT_EQ(r.error_code(), "bad_host") << target;
    }
    // The server's own names, with its port or none, are served; another port is not.
    for (const std::string& host : {std::string("127.0.0.1"), "127.0.0.1:" + std::to_string(port()), "LOCALHOST:" + std::to_string(port())})
        EXPECT_EQ(http(port(), "GET", "/v1/health", {}, {{"Host", host}}).status, 200) << host;
    EXPECT_EQ(raw_exchange(port(), "GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1:1\r\nConnection: close\r\n\r\n").status, 400);
    // HTTP/1.1 without Host is malformed (RFC 9112 §3.2).
    EXPECT_EQ(raw_exchange(port(), "GET /v1/health HTTP/1.1\r\nConnection: close\r\n\r\n").error_code(), "bad_host");

    // A cross-site POST: a foreign Origin is refused (403) and creates no job,
    // whatever the body's type; the server's own origin is served.
    const auto before = http(port(), "GET", "/v1/jobs").json().at("jobs").as_array().size();
    const std::string host = "127.0.0.1:" + std::to_string(port());
    const auto foreign = raw_exchange(port(), "POST /v1/jobs HTTP/1.1\r\nHost: " + host
                                                  + "\r\nOrigin: http://evil.example\r\nContent-Type: application/json\r\n"
                                                    "Content-Length: 2\r\nConnection: close\r\n\r\n{}");
    EXPECT_EQ(foreign.status, 403);
    EXPECT_EQ(foreign.error_code(), "forbidden_origin");
    EXPECT_EQ(http(port(), "POST", "/v1/jobs", "{}", {{"Host", host}, {"Origin", "null"}}).status, 403);
    // A Blob body from a page carries no Content-Type and needs no preflight: 415.
    const auto untyped = raw_exchange(port(), "POST /v1/jobs HTTP/1.1\r\nHost: " + host
                                                  + "\r\nContent-Length: 2\r\nConnection: close\r\n\r\n{}");
    EXPECT_EQ(untyped.status, 415);
    EXPECT_EQ(http(port(), "GET", "/v1/jobs").json().at("jobs").as_array().size(), before);
    EXPECT_EQ(http(port(), "POST", "/v1/jobs", "{}", {{"Host", host}, {"Origin", "http://" + host}}).status, 201);
}

TEST(WorkLimits, JobsThatWouldNeverEndAreRefusedNamingTheField)
{
    // The server's default limit on steps (2e7, ~10 paper-size campaigns),
    // and a small limit on rows per test.
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--max-steps-per-job", "2e7", "--max-samples-per-test", "1000"});
    const std::uint16_t port = server.port();
    const auto refused = [&](const std::string& spec, const std::string& field, const std::string& fragment) {
        const auto r = http(port, "POST", "/v1/jobs", spec);
        EXPECT_EQ(r.status, 400) << spec;
        EXPECT_EQ(r.error_code(), "invalid_job") << spec;
        const std::string message(r.json().at("error").at("message").as_string());
        EXPECT_EQ(message.rfind(field + ":", 0), 0u) << message;
        EXPECT_NE(message.find(fragment), std::string::npos) << message;
    };
    std::ifstream in(std::filesystem::path(WIREDEM_SOURCE_DIR) / "examples/tiny.json");
    const std::string tiny((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto with = [&](const char* section, const char* key, const char* value) {
        boost::json::value j = boost::json::parse(tiny);
        j.at(section).as_object()[key] = boost::json::parse(value);
        return boost::json::serialize(j);
    };
    // A valid δt far below the stable one: steps without end.
    refused(with("engine", "time_step_s", "1e-12"), "engine.time_step_s", "at most 2e+07 (--max-steps-per-job)");
    // One so small that no server may run it (docs/job-spec.md: 1e15 steps at most).
    refused(with("engine", "time_step_s", "5e-324"), "engine.time_step_s", "no job may take more than 1e+15");
    // A plate that barely moves.
    refused(with("triaxial", "plate_speed_m_per_s", "1e-12"), "triaxial.plate_speed_m_per_s", "time steps");
    // Rows more often than steps: the job spec refuses it (docs/job-spec.md).
    refused(with("triaxial", "sample_interval_s", "1e-300"), "triaxial.sample_interval_s", "shorter than the time step");
    // Rows every other step of a test that is otherwise fine: more than this server keeps.
    refused(with("triaxial", "sample_interval_s", "1e-5"), "triaxial.sample_interval_s", "(--max-samples-per-test)");
    // The paper-literal default spec (no mass scaling, 0.2 mm/s): ~10⁹ steps.
    refused("{}", "triaxial.plate_speed_m_per_s", "time steps");
    // tiny.json itself is accepted.
    EXPECT_EQ(http(port, "POST", "/v1/jobs", tiny).status, 201);
}

TEST_F(HostileInput, HugeHeaderIs431)
{
    const auto r = raw_exchange(port(), "GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Junk: " + std::string(100000, 'a') + "\r\n\r\n");
    EXPECT_EQ(r.status, 431);
}

TEST_F(HostileInput, AChunkedBodysTrailerIsBoundedLikeTheHeaders)
{
    // Beast bounds the headers but not a chunked body's trailer, and throws
    // std::length_error out of io_context::run() for a field of 65 534 bytes
    // or more: one such request, before any routing or token check, aborted
    // the process (exit 134). The trailer now has to fit in the session's
    // read buffer, as the headers do (server/framing.hpp, read_buffer_limit):
    // over it, 431; and the fixture's TearDown checks that the server lives.
    const std::string head = "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                             "Transfer-Encoding: chunked\r\n\r\n2\r\n{}\r\n0\r\n";
    for (const std::size_t n : {std::size_t{20'000}, std::size_t{65'534}, std::size_t{65'535}, std::size_t{300'000}}) {
        const auto r = raw_exchange(port(), head + "X-T: " + std::string(n, 'a') + "\r\n\r\n");
        EXPECT_EQ(r.status, 431) << n << "-byte trailer field";
        EXPECT_EQ(r.error_code(), "headers_too_large") << n;
    }
    // Many small trailer fields add up the same way.
    std::string many;
    for (int i = 0; i < 4000; ++i) many += "X-" + std::to_string(i) + ": v\r\n";
    EXPECT_EQ(raw_exchange(port(), head + many + "\r\n").status, 431);
    // So does a chunk-size line padded with extensions.
    EXPECT_EQ(raw_exchange(port(), "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                                   "Transfer-Encoding: chunked\r\n\r\n2;x=" + std::string(70'000, 'e') + "\r\n{}\r\n0\r\n\r\n")
                  .status,
        431);
    // A trailer within the limit is read, and the job judged on its body.
    const auto ok = raw_exchange(port(), head + "X-T: small\r\n\r\n");
    EXPECT_EQ(ok.status, 201) << ok.body;
}

TEST(HeaderLimit, TheLargestAllowedHeaderLimitHoldsAnyFieldAndLargerIsRefusedAtStart)
{
    // --max-header-bytes allowed 1 MiB, so a plain header field of 64 KiB
    // reached Beast's 16-bit field length and aborted the server. Its range
    // is now what the parser can hold (1024 … 65535).
    TempDir tmp;
    std::string log;
    EXPECT_EQ(server_exit_code(tmp.path() / "refused", {"--max-header-bytes", "65536"}, log), 2) << log;
    EXPECT_NE(log.find("--max-header-bytes"), std::string::npos) << log;
    ServerProcess server(tmp.path() / "data", {"--max-header-bytes", "65535"});
    for (const std::size_t n : {std::size_t{60'000}, std::size_t{65'534}, std::size_t{65'535}, std::size_t{70'000}}) {
        const auto r = raw_exchange(server.port(),
            "GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\nX-Junk: " + std::string(n, 'a') + "\r\n\r\n");
        EXPECT_EQ(r.status, n < 65'000 ? 200 : 431) << n << "-byte header field";
    }
    const auto trailer = raw_exchange(server.port(),
        "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n"
        "2\r\n{}\r\n0\r\nX-T: " + std::string(65'535, 'a') + "\r\n\r\n");
    EXPECT_EQ(trailer.status, 431);
    EXPECT_EQ(http(server.port(), "GET", "/v1/health").status, 200);
}

TEST_F(HostileInput, GarbageAndBadRequestLinesAre400)
{
    EXPECT_EQ(raw_exchange(port(), "\x16\x03\x01\x02\x00 hello TLS?\r\n\r\n").status, 400);
    EXPECT_EQ(raw_exchange(port(), "GET\r\n\r\n").status, 400);
    EXPECT_EQ(raw_exchange(port(), "GET /v1/health HTTP/9.9\r\n\r\n").status, 400);
    EXPECT_EQ(http(port(), "GET", "http://evil.example/v1/health").status, 400);  // absolute form is not served
}

TEST_F(HostileInput, StalledClientIsCutOffAfterTheReadTimeout)
{
    // Half a request, then silence with the connection open: the server
    // closes it after the read timeout (2 s here).
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = raw_exchange(port(), "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 100\r\n\r\n{",
        std::chrono::milliseconds(8000), false);
    const auto took = std::chrono::steady_clock::now() - t0;
    EXPECT_EQ(r.status, 0) << "closed without a reply";
    EXPECT_GT(took, std::chrono::milliseconds(1500));
    EXPECT_LT(took, std::chrono::seconds(5));
    // A truncated request (client went away mid-body) is a 400.
    EXPECT_EQ(raw_exchange(port(), "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 100\r\n\r\n{").status, 400);
}

TEST_F(HostileInput, UnknownRoutesAre404AndWrongMethods405)
{
    EXPECT_EQ(http(port(), "GET", "/no-such-page.html").status, 404);  // "/" is the web page (test_static.cpp)
    EXPECT_EQ(http(port(), "GET", "/v2/jobs").status, 404);
    EXPECT_EQ(http(port(), "GET", "/v1/jobs/0123456789abcdef01234567/other").status, 404);
    EXPECT_EQ(http(port(), "GET", "/v1/jobs/").status, 404);
    const auto put = http(port(), "PUT", "/v1/jobs");
    EXPECT_EQ(put.status, 405);
    EXPECT_EQ(put.headers.at("allow"), "GET, HEAD, POST");
    EXPECT_EQ(http(port(), "POST", "/v1/health").status, 405);
    EXPECT_EQ(http(port(), "GET", "/v1/jobs?color=blue").status, 400);
    EXPECT_EQ(http(port(), "GET", "/v1/jobs?limit=0").status, 400);
    EXPECT_EQ(http(port(), "GET", "/v1/jobs?state=done").status, 400);
    EXPECT_EQ(http(port(), "GET", "/v1/jobs?limit=5&limit=6").status, 400);
    // Other routes take no query parameters: refused, not ignored.
    for (const char* target : {"/v1/jobs/0123456789abcdef01234567?verbose=1", "/v1/health?x", "/metrics?format=json"}) {
        const auto r = http(port(), "GET", target);
        EXPECT_EQ(r.status, 400) << target;
        EXPECT_EQ(r.error_code(), "bad_parameter") << target;
    }
    // A malformed target is answered and the connection closed (the client
    // keeps it open; the exchange ends long before its timeout).
    const auto t0 = std::chrono::steady_clock::now();
    const auto bad = raw_exchange(port(), "GET /v1/%zz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n", std::chrono::milliseconds(6000), false);
    EXPECT_EQ(bad.error_code(), "bad_target");
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(3)) << "connection left open";
}

TEST_F(HostileInput, BadIdsAre400AndUnknownIds404)
{
    for (const std::string& id : std::vector<std::string>{"123", "0123456789ABCDEF01234567", "0123456789abcdef0123456z", "%00%00", std::string(5000, 'a')}) {
        const auto r = http(port(), "GET", "/v1/jobs/" + id);
        EXPECT_EQ(r.status, 400) << id;
        EXPECT_EQ(r.error_code(), "bad_id") << id;
    }
    EXPECT_EQ(http(port(), "GET", "/v1/jobs/0123456789abcdef01234567").status, 404);
    EXPECT_EQ(http(port(), "DELETE", "/v1/jobs/0123456789abcdef01234567").status, 404);
    EXPECT_EQ(http(port(), "GET", "/v1/jobs/0123456789abcdef01234567/result.h5").status, 404);
}

TEST_F(HostileInput, PathTraversalNeverReachesAFile)
{
    // A file the server must never serve, next to the data directory.
    write_file(tmp_.path() / "secret.txt", "top secret");
    for (const std::string target : {"/v1/jobs/../../secret.txt", "/v1/jobs/..%2F..%2Fsecret.txt/result.h5",
             "/v1/jobs/%2e%2e/result.h5", "/v1/jobs/..%2f..%2f..%2fetc%2fpasswd/summary", "/../../etc/passwd",
             "/v1/jobs/0123456789abcdef01234567%2F..%2F..%2Fsecret.txt/result.h5", "/v1/jobs//etc/passwd/result.h5"}) {
        const auto r = http(port(), "GET", target);
        EXPECT_TRUE(r.status == 400 || r.status == 404) << target << " -> " << r.status;
        EXPECT_EQ(r.body.find("top secret"), std::string::npos) << target;
        EXPECT_EQ(r.body.find("root:"), std::string::npos) << target;
    }
}

TEST_F(HostileInput, HealthMetricsAndOpenApiAnswer)
{
    const auto metrics = http(port(), "GET", "/metrics");
    EXPECT_EQ(metrics.status, 200);
    EXPECT_EQ(metrics.headers.at("content-type").rfind("text/plain; version=0.0.4", 0), 0u);
    for (const char* name : {"wiredem_queue_length ", "wiredem_jobs{state=\"running\"} ", "wiredem_body_steps_per_second ",
             "# TYPE wiredem_http_responses_total counter"})
        EXPECT_NE(metrics.body.find(name), std::string::npos) << name;
    const auto api = http(port(), "GET", "/v1/openapi.json");
    ASSERT_EQ(api.status, 200);
    const json::value doc = api.json();
    EXPECT_EQ(doc.at("openapi").as_string().subview().substr(0, 2), "3.");
    for (const char* path : {"/v1/jobs", "/v1/jobs/{id}", "/v1/jobs/{id}/summary", "/v1/jobs/{id}/result.h5", "/v1/health", "/metrics"})
        EXPECT_TRUE(doc.at("paths").as_object().contains(path)) << path;
}

TEST(Authentication, EveryV1RouteNeedsTheBearerToken)
{
    TempDir tmp;
    write_file(tmp.path() / "token", "s3cret-token\n");
    ServerProcess server(tmp.path() / "data", {"--token-file", (tmp.path() / "token").string()});
    for (const std::string target : {"/v1/jobs", "/v1/health", "/v1/openapi.json", "/v1/jobs/0123456789abcdef01234567", "/v1/nothing"}) {
        const auto missing = http(server.port(), "GET", target);
        EXPECT_EQ(missing.status, 401) << target;
        EXPECT_EQ(missing.headers.at("www-authenticate"), "Bearer realm=\"wiredem\"");
        EXPECT_EQ(http(server.port(), "GET", target, {}, {{"Authorization", "Bearer wrong-token!"}}).status, 401) << target;
        EXPECT_EQ(http(server.port(), "GET", target, {}, {{"Authorization", "Bearer s3cret-toke"}}).status, 401) << target;
        EXPECT_EQ(http(server.port(), "GET", target, {}, {{"Authorization", "Basic czNjcmV0LXRva2Vu"}}).status, 401) << target;
    }
    EXPECT_EQ(http(server.port(), "POST", "/v1/jobs", "{}").status, 401);
    EXPECT_EQ(http(server.port(), "GET", "/v1/health", {}, {{"Authorization", "Bearer s3cret-token"}}).status, 200);
    EXPECT_EQ(http(server.port(), "GET", "/metrics").status, 200) << "Prometheus scrapes without the token";

    // The client with and without --token-file.
    const auto without = run_client({"list", "--server", server.url()});
    EXPECT_EQ(without.exit_code, 5) << without.err;
    EXPECT_NE(without.err.find("401"), std::string::npos);
    const fs::path job = tmp.path() / "job.json";
    write_file(job, R"({"name": "authorised"})");
    const auto submit = run_client({"submit", job.string(), "--wait", "--interval", "0.05", "--server", server.url(),
        "--token-file", (tmp.path() / "token").string()});
    EXPECT_EQ(submit.exit_code, 0) << submit.err;
}

TEST(Client, ErrorsAreOneLineWithDocumentedExitCodes)
{
    TempDir tmp;
    const fs::path bad = tmp.path() / "bad.json";
    write_file(bad, R"({"seed": -3})");
    const auto invalid = run_client({"submit", bad.string(), "--server", "http://127.0.0.1:9"});
    EXPECT_EQ(invalid.exit_code, 3) << "validated locally before any network";
    EXPECT_NE(invalid.err.find("seed: "), std::string::npos) << invalid.err;
    EXPECT_EQ(run_client({"submit", (tmp.path() / "missing.json").string()}).exit_code, 9);
    const auto not_an_id = run_client({"study", "status", "zz"});
    EXPECT_EQ(not_an_id.exit_code, 2);
    EXPECT_EQ(not_an_id.err, "wiredem: 'zz' is not a study id (24 lower-case hex digits)\n");
    EXPECT_EQ(run_client({"status", "nope"}).exit_code, 2);
    const auto usage = run_client({"frobnicate"});  // CLI11's error: one line too
    EXPECT_EQ(usage.exit_code, 2);
    EXPECT_EQ(std::count(usage.err.begin(), usage.err.end(), '\n'), 1) << usage.err;
    EXPECT_EQ(usage.err.rfind("wiredem: ", 0), 0u) << usage.err;
    EXPECT_EQ(run_client({"--help"}).exit_code, 0);
    EXPECT_EQ(run_client({"list", "--server", "https://127.0.0.1:1"}).exit_code, 2);
    const auto refused = run_client({"list", "--server", "http://127.0.0.1:9", "--timeout", "2"});
    EXPECT_EQ(refused.exit_code, 7);
    EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
    EXPECT_EQ(refused.err.rfind("wiredem: cannot connect to http://127.0.0.1:9", 0), 0u) << refused.err;
}

TEST(Client, RunValidatesTheJobFileBeforeRunning)
{
    TempDir tmp;
    const fs::path bad = tmp.path() / "bad.json";
    write_file(bad, R"({"specimen": {"grain_count": 0}})");
    const auto r = run_client({"run", bad.string(), "-o", (tmp.path() / "out").string(), "--progress", "json"});
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_NE(r.err.find("specimen.grain_count"), std::string::npos) << r.err;
    EXPECT_EQ(run_client({"run", bad.string(), "-o", "x", "--progress", "yaml"}).exit_code, 2);
}

} // namespace
} // namespace wiredem::test
