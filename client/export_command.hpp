// `wiredem export-xdmf`: the XDMF sidecar of an existing result file, so that
// ParaView opens it (engine/io/xdmf.hpp; layout in docs/results.md).
#pragma once

#include <filesystem>

namespace wiredem::client {

/// Writes the XDMF sidecar of `h5_file` to `xdmf_file` (empty: the same name with
/// the extension .xdmf) and prints what it describes.
/// @return exit_code::ok; throws CommandError(local_io) when the result file
///         cannot be read or the sidecar cannot be written
int cmd_export_xdmf(const std::filesystem::path& h5_file, const std::filesystem::path& xdmf_file);

} // namespace wiredem::client
