// The web page's files (server/handlers/static_files.hpp): only regular files
// of --web-dir, by plain names, no symlink anywhere on the way, known types
// with their content type, the CSP on every one; the Host check and the token
// apply as on the API.
#include "harness.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

namespace wiredem::test {
namespace {
namespace fs = std::filesystem;

/// A web folder with a page, a module, and the traps a request must not reach.
fs::path make_web_dir(const TempDir& tmp)
{
    const fs::path web = tmp.path() / "web";
    fs::create_directories(web / "js");
    write_file(web / "index.html", "<!doctype html><title>wiredem</title>\n");
    write_file(web / "js" / "main.js", "export const x = 1;\n");
    write_file(web / ".hidden.js", "secret\n");
    write_file(web / "tool.sh", "#!/bin/sh\n");
    write_file(tmp.path() / "outside.js", "outside\n");
    fs::create_symlink(tmp.path() / "outside.js", web / "link.js");
    fs::create_directory_symlink(tmp.path(), web / "up");
    return web;
}

TEST(StaticFiles, ServesThePageWithItsTypeAndAStrictPolicy)
{
    TempDir tmp;
    const fs::path web = make_web_dir(tmp);
    ServerProcess server(tmp.path() / "data", {"--web-dir", web.string()});
    const auto index = http(server.port(), "GET", "/");
    ASSERT_EQ(index.status, 200) << index.body;
    EXPECT_EQ(index.body, read_file(web / "index.html"));
    EXPECT_EQ(index.headers.at("content-type"), "text/html; charset=utf-8");
    const std::string csp = index.headers.at("content-security-policy");
    EXPECT_NE(csp.find("script-src 'self'"), std::string::npos) << csp;
    EXPECT_EQ(csp.find("unsafe-inline"), std::string::npos) << csp;
    EXPECT_NE(csp.find("frame-ancestors 'none'"), std::string::npos) << csp;
    EXPECT_EQ(index.headers.at("x-content-type-options"), "nosniff");

    const auto js = http(server.port(), "GET", "/js/main.js");
    ASSERT_EQ(js.status, 200);
    EXPECT_EQ(js.headers.at("content-type"), "text/javascript; charset=utf-8");
    EXPECT_EQ(http(server.port(), "GET", "/index.html").body, index.body);

    // Revalidation by ETag; HEAD gives the length without the body.
    const auto again = http(server.port(), "GET", "/js/main.js", {}, {{"If-None-Match", js.headers.at("etag")}});
    EXPECT_EQ(again.status, 304);
    EXPECT_TRUE(again.body.empty());
    // Compared weakly (RFC 9110 §13.1.2): W/ and lists match, "*" too; another tag does not.
    for (const std::string& inm : {"W/" + js.headers.at("etag"), "\"other\", " + js.headers.at("etag"), std::string("*")})
        EXPECT_EQ(http(server.port(), "GET", "/js/main.js", {}, {{"If-None-Match", inm}}).status, 304) << inm;
    EXPECT_EQ(http(server.port(), "GET", "/js/main.js", {}, {{"If-None-Match", "W/\"other\""}}).status, 200);
    const auto head = http(server.port(), "HEAD", "/js/main.js");
    EXPECT_EQ(head.status, 200);
    EXPECT_EQ(head.headers.at("content-length"), std::to_string(js.body.size()));
    EXPECT_TRUE(head.body.empty());
    EXPECT_EQ(http(server.port(), "POST", "/", "{}").status, 405);
}

TEST(StaticFiles, NothingOutsideTheFolderNorHiddenNorUnknownTypesNorThroughSymlinks)
{
    TempDir tmp;
    const fs::path web = make_web_dir(tmp);
    ServerProcess server(tmp.path() / "data", {"--web-dir", web.string()});
    for (const char* target : {"/link.js", "/up/outside.js", "/up/web/index.html", "/../outside.js", "/%2e%2e/outside.js",
             "/js/..%2f..%2foutside.js", "/js/%2e%2e/index.html", "/.hidden.js", "/tool.sh", "/js", "/js/", "/nope.html",
             "/index.html%00.js", "/js//main.js"}) {
        const auto res = http(server.port(), "GET", target);
        EXPECT_TRUE(res.status == 404 || res.status == 400) << target << ": " << res.status;
        EXPECT_EQ(res.body.find("outside"), std::string::npos) << target;
    }
}

TEST(StaticFiles, TheHostCheckAppliesAndThePageNeedsNoTokenButTheApiDoes)
{
    TempDir tmp;
    const fs::path web = make_web_dir(tmp);
    write_file(tmp.path() / "token", "s3cret\n");
    ServerProcess server(tmp.path() / "data", {"--web-dir", web.string(), "--token-file", (tmp.path() / "token").string()});
    EXPECT_EQ(http(server.port(), "GET", "/").status, 200) << "the page holds no secret: it asks for the token";
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs").status, 401);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs", {}, {{"Authorization", "Bearer s3cret"}}).status, 200);
    EXPECT_EQ(http(server.port(), "GET", "/", {}, {{"Host", "attacker.example:80"}}).error_code(), "bad_host");
}

TEST(StaticFiles, WithoutAWebFolderThePageIs404AndAMissingIndexIsASetupError)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--web-dir", "none"});
    EXPECT_EQ(http(server.port(), "GET", "/").status, 404);
    EXPECT_EQ(http(server.port(), "GET", "/v1/health").status, 200);

    fs::create_directories(tmp.path() / "empty");
    const std::string cmd = std::string("'") + WIREDEM_SERVER_BIN + "' --listen 127.0.0.1:0 --data-dir '" + (tmp.path() / "d2").string()
                            + "' --runner /bin/true --web-dir '" + (tmp.path() / "empty").string() + "' 2>/dev/null";
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WEXITSTATUS(status), 3);
}

} // namespace
} // namespace wiredem::test
