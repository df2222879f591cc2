// Placeholder until the campaign runner lands: this file will be replaced by
// the real definition of run_campaign_main.
#include "run_command.hpp"

#include <iostream>

int run_campaign_main(const wiredem::api::JobSpec&, const std::filesystem::path&, unsigned, bool)
{
    std::cerr << "campaign runner not yet available\n";
    return 70;  // EX_SOFTWARE
}
