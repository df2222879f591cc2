// The web page: files of the installed front end (--web-dir) at every path
// outside /v1 and /metrics, `/` being index.html. Same origin as the API, so
// the page needs no CORS and the Host/Origin checks apply to it unchanged.
//
// Only regular files inside the folder are served: each path segment must be
// a plain name ([A-Za-z0-9_.-], not starting with a dot: no "..", no hidden
// files), every directory on the way and the file itself are opened with
// O_NOFOLLOW relative to the one before (a symlink anywhere is refused), and
// only known file types are served, with their content type and
// `X-Content-Type-Options: nosniff`. Every reply carries a strict
// Content-Security-Policy: scripts, styles and requests only from this origin,
// no inline script or style, no framing.
#pragma once

#include "../http.hpp"
#include "../services.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace wiredem::server {

/// The Content-Security-Policy sent with every file of the page.
inline constexpr std::string_view web_content_security_policy =
    "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; "
    "connect-src 'self'; font-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

/// Content type of a file name by its extension; nullopt: not served.
[[nodiscard]] std::optional<std::string_view> web_content_type(std::string_view file_name) noexcept;

/// GET/HEAD of a path outside /v1: `seg` are its decoded segments (empty for
/// `/`). 404 for anything that is not a servable file of --web-dir, or when
/// the server has no web folder; 304 when If-None-Match names the file's ETag.
[[nodiscard]] Response handle_static(const Request& req, const std::vector<std::string>& seg, Services& svc);

} // namespace wiredem::server
