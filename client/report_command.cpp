// The offline report: api::report_html on an output folder, written beside it.
#include "report_command.hpp"

#include "exit_codes.hpp"
#include "local_file.hpp"

#include "api/report.hpp"

#include <fstream>
#include <iostream>

namespace wiredem::client {
namespace fs = std::filesystem;

namespace {

fs::path default_web_dir()
{
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : self.parent_path().parent_path() / "share" / "wiredem" / "web";
}

} // namespace

int cmd_report(const fs::path& out_dir, const fs::path& html_in, const fs::path& web_dir_in)
{
    const fs::path html = html_in.empty() ? out_dir / "report.html" : html_in;
    const fs::path web = web_dir_in.empty() ? default_web_dir() : web_dir_in;
    std::string page;
    try {
        page = api::report_html(out_dir / "summary.json", out_dir / "result.h5", web, fs::absolute(out_dir).string());
    } catch (const std::exception& e) {
        throw CommandError(exit_code::local_io, std::string(e.what()) + (web_dir_in.empty() ? " (see --web-dir)" : ""));
    }
    write_local_file(html, page);
    std::cout << html.string() << " (" << page.size() / 1024 << " KiB)\n";
    return exit_code::ok;
}

} // namespace wiredem::client
