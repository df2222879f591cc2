// The job spec from raw bytes: the JSON text parser and the validator
// (api::parse_job_spec), as a submitted body reaches them. Any input must
// give a spec or errors, never a crash, within the validation time bound;
// every error names a field and says something; an accepted spec has the
// properties of spec_properties.hpp.
#include "spec_properties.hpp"

#include <cstddef>
#include <cstdint>

using namespace wiredem;

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    fuzz::warm_clump_templates();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const double t0 = fuzz::thread_cpu_seconds();
    const auto parsed = api::parse_job_spec(text);
    const double took = fuzz::thread_cpu_seconds() - t0;
    FUZZ_CHECK(took <= fuzz::max_validation_cpu_s, "validation took " + std::to_string(took) + " s of CPU");
    if (!parsed.ok()) {
        FUZZ_CHECK(!parsed.error().empty(), "rejected without a reason");
        for (const api::FieldError& e : parsed.error()) FUZZ_CHECK(!e.message.empty(), "empty message at " + e.path);
        return 0;
    }
    fuzz::check_parsed_spec(parsed.value());
    return 0;
}
