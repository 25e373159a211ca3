// RttOptions' checks (rtt/rtt_options.h); compiled once, outside the per-ISA kernels.
#include "rtt/rtt_options.h"

#include <string>

#include "rtt/error.h"

namespace rtt {

void RttOptions::validate() const {
    if (walk_budget_base < 1 || walk_budget_per_sample < 0 || deferred_budget_base < 1)
        throw Error(
            "RttOptions: the walk and deferred budgets must be at least 1 node (per-sample part >= "
            "0)");
    if (region_budget_divisor < 1 || shadow_region_budget_divisor < 1)
        throw Error("RttOptions: the region budget divisors must be at least 1");
    if (lean_max_samples < 0 || lean_max_samples > rtt_max_samples_per_tile)
        throw Error("RttOptions: lean_max_samples must be in 0.." +
                    std::to_string(rtt_max_samples_per_tile));
}

}  // namespace rtt
