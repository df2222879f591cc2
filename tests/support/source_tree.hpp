// Files of the source tree and others, read whole by the tests: the one
// helper the tests that hold code to its docs (docs/results.md, the OpenAPI
// document, the web page's JavaScript, the Python package) and the tests of
// the files a run writes share. WIREDEM_SOURCE_DIR comes from the target
// wiredem_test_support (tests/CMakeLists.txt).
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace wiredem::test_support {

/// The bytes of the file at `p`; empty when it cannot be read (a test that
/// needs the file checks that it is there: source_text).
inline std::string read_text(const std::filesystem::path& p)
{
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// The file `relative` (e.g. "docs/results.md") of the source tree.
inline std::filesystem::path source(const std::string& relative)
{
    return std::filesystem::path(WIREDEM_SOURCE_DIR) / relative;
}

} // namespace wiredem::test_support
