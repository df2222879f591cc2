// Static files of the web page, opened component by component with O_NOFOLLOW.
#include "static_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <memory>
#include <utility>

namespace wiredem::server {
namespace {

/// A descriptor closed when the last copy goes (FileRangeBody shares it).
std::shared_ptr<int> owned_fd(int fd)
{
    return std::shared_ptr<int>(new int(fd), [](int* p) {
        ::close(*p);
        delete p;
    });
}

/// If-None-Match against the file's (strong) ETag, compared weakly as RFC
/// 9110 §13.1.2 asks: "*", or any entry of the list, W/ or not, that is it.
bool none_match_hits(std::string_view header, std::string_view etag) noexcept
{
    const auto trim = [](std::string_view v) {
        while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
        while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
        return v;
    };
    if (trim(header) == "*") return true;
    while (!header.empty()) {
        const auto comma = header.find(',');
        std::string_view entry = trim(header.substr(0, comma));
        header = comma == std::string_view::npos ? std::string_view() : header.substr(comma + 1);
        if (entry.substr(0, 2) == "W/") entry.remove_prefix(2);
        if (entry == etag) return true;
    }
    return false;
}

bool plain_name(std::string_view s) noexcept
{
    if (s.empty() || s.size() > 255 || s.front() == '.') return false;
    for (char c : s) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
        if (!ok) return false;
    }
    return true;
}

void set_page_headers(http::response_header<>& h)
{
    h.set(http::field::server, server_name);
    h.set("Content-Security-Policy", web_content_security_policy);
    h.set("X-Content-Type-Options", "nosniff");
    h.set("Referrer-Policy", "no-referrer");
    h.set("Cross-Origin-Opener-Policy", "same-origin");
    // Revalidate every time (cheap: 304 by ETag) so an upgraded server's page is never mixed with an old cache.
    h.set(http::field::cache_control, "no-cache");
}

Response not_found(const Request& req, std::string message)
{
    auto res = error_response(req, http::status::not_found, "not_found", message);
    res.set("Content-Security-Policy", web_content_security_policy);
    return res;
}

} // namespace

std::optional<std::string_view> web_content_type(std::string_view name) noexcept
{
    static constexpr std::array<std::pair<std::string_view, std::string_view>, 11> types{{
        {".html", "text/html; charset=utf-8"},
        {".js", "text/javascript; charset=utf-8"},
        {".mjs", "text/javascript; charset=utf-8"},
        {".css", "text/css; charset=utf-8"},
        {".json", "application/json"},
        {".svg", "image/svg+xml"},
        {".png", "image/png"},
        {".ico", "image/x-icon"},
        {".txt", "text/plain; charset=utf-8"},
        {".map", "application/json"},
        {".woff2", "font/woff2"},
    }};
    for (const auto& [ext, type] : types)
        if (name.size() > ext.size() && name.substr(name.size() - ext.size()) == ext) return type;
    return std::nullopt;
}

Response handle_static(const Request& req, const std::vector<std::string>& seg_in, Services& svc)
{
    if (svc.config.web_dir.empty())
        return not_found(req, "no such route (this server serves no web page: see --web-dir)");
    std::vector<std::string> seg = seg_in;
    if (seg.empty()) seg.push_back("index.html");
    for (const auto& s : seg)
        if (!plain_name(s)) return not_found(req, "no such file");
    const auto type = web_content_type(seg.back());
    if (!type) return not_found(req, "no such file");

    int dir = ::open(svc.config.web_dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir < 0)
        return error_response(req, http::status::internal_server_error, "internal",
            "the web folder " + svc.config.web_dir.string() + " cannot be opened");
    for (std::size_t i = 0; i + 1 < seg.size(); ++i) {
        const int next = ::openat(dir, seg[i].c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        ::close(dir);
        if (next < 0) return not_found(req, "no such file");
        dir = next;
    }
    const int fd = ::openat(dir, seg.back().c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
    ::close(dir);
    if (fd < 0) return not_found(req, "no such file");
    auto owned = owned_fd(fd);
    struct stat st{};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return not_found(req, "no such file");

    char etag_buf[64];
    std::snprintf(etag_buf, sizeof etag_buf, "\"%llx-%llx\"", static_cast<unsigned long long>(st.st_size),
        static_cast<unsigned long long>(st.st_mtim.tv_sec) * 1000000000ull + static_cast<unsigned long long>(st.st_mtim.tv_nsec));
    if (auto inm = req.find(http::field::if_none_match); inm != req.end() && none_match_hits(inm->value(), etag_buf)) {
        StringResponse res{http::status::not_modified, req.version()};
        set_page_headers(res.base());
        res.set(http::field::etag, etag_buf);
        res.keep_alive(req.keep_alive());
        return res;
    }
    FileResponse res{http::status::ok, req.version()};
    set_page_headers(res.base());
    res.set(http::field::content_type, *type);
    res.set(http::field::etag, etag_buf);
    res.keep_alive(req.keep_alive());
    res.body().fd = std::move(owned);
    res.body().offset = 0;
    res.body().length = static_cast<std::uint64_t>(st.st_size);
    res.content_length(res.body().length);
    return res;
}

} // namespace wiredem::server
