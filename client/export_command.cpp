// `wiredem export-xdmf RESULT.h5 [-o RESULT.xdmf]`: a thin wrapper around
// engine::io::write_xdmf that turns its exceptions into the client's exit codes.
#include "export_command.hpp"

#include "exit_codes.hpp"

#include "io/xdmf.hpp"

#include <iostream>

namespace wiredem::client {

int cmd_export_xdmf(const std::filesystem::path& h5_file, const std::filesystem::path& xdmf_file)
{
    std::filesystem::path out = xdmf_file;
    if (out.empty()) out = std::filesystem::path(h5_file).replace_extension(".xdmf");
    if (!std::filesystem::is_regular_file(h5_file))
        throw CommandError(exit_code::local_io, "cannot read result file " + h5_file.string());
    try {
        const engine::io::XdmfSummary s = engine::io::write_xdmf(h5_file, out);
        std::cout << out.string() << ": " << (s.specimen ? "specimen, " : "no specimen, ") << s.tests << " test(s), " << s.snapshots << " snapshot(s), "
                  << s.grids << " grid(s)\n";
    } catch (const std::exception& e) {
        throw CommandError(exit_code::local_io, e.what());
    }
    return exit_code::ok;
}

} // namespace wiredem::client
