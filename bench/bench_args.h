// Values of the benchmark programs' own flags (--aa=K, --threads=N, ...); sizes use the command
// line's parser (apps/rtt/cli_values.h).
#pragma once

#include <cstdint>
#include <cstdlib>

namespace rtt::bench {

/// The integer of `text` (all of it), or false.
inline bool parse_int(const char* text, int& out) {
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || v < INT32_MIN || v > INT32_MAX) return false;
    out = int(v);
    return true;
}

}  // namespace rtt::bench
