#include "rtt/memory_budget.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include "rtt/error.h"

namespace rtt {
namespace {

constexpr uint64_t unlimited = std::numeric_limits<uint64_t>::max();

/// The first number in `path`, or `unlimited` when the file is missing or says "max".
uint64_t read_limit_file(const char* path) {
    std::ifstream in(path);
    std::string word;
    if (!(in >> word) || word.empty() || word.find_first_not_of("0123456789") != std::string::npos)
        return unlimited;
    try {
        return std::stoull(word);
    } catch (...) {
        return unlimited;
    }
}

/// Physical memory and cgroup limit: fixed for the life of the process, read once.
uint64_t machine_limit() {
    static const uint64_t limit = [] {
        uint64_t bytes = unlimited;
        const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
        if (pages > 0 && page > 0) bytes = uint64_t(pages) * uint64_t(page);
        // cgroup v2, then v1 (whose "no limit" is a huge number, harmless under min).
        bytes = std::min(bytes, read_limit_file("/sys/fs/cgroup/memory.max"));
        bytes = std::min(bytes, read_limit_file("/sys/fs/cgroup/memory/memory.limit_in_bytes"));
        return bytes;
    }();
    return limit;
}

/// ulimit -v / -d: may change while the process runs (tests lower them), so read every time.
uint64_t rlimit_bytes(int resource) {
    rlimit r{};
    if (getrlimit(resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return unlimited;
    return uint64_t(r.rlim_cur);
}

std::string gib(uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", double(bytes) / double(uint64_t(1) << 30));
    return text;
}

}  // namespace

uint64_t saturating_mul_add(uint64_t a, uint64_t b, uint64_t c) {
    if (b != 0 && a > (unlimited - c) / b) return unlimited;
    return a * b + c;
}

uint64_t memory_budget() {
    return std::min({machine_limit(), rlimit_bytes(RLIMIT_AS), rlimit_bytes(RLIMIT_DATA)});
}

void require_memory(uint64_t bytes, const std::string& what) {
    const uint64_t budget = memory_budget();
    if (bytes <= budget) return;
    throw Error(what + " needs about " + gib(bytes) + " GiB of memory, but at most " + gib(budget) +
                " GiB is available (physical memory, cgroup and ulimit)");
}

uint64_t scene_memory_bytes(uint64_t vertices, uint64_t triangles) {
    // Per vertex: position and shading normal (12 + 12). Per triangle: indices and material
    // (16), gathered vertices (36, once for the build and once in a tracer), the build's
    // triangle lists and clipped bounds with parent and children alive together, nodes and
    // leaf lists, and per-tracer extras: 384 bytes per triangle covers the build's measured
    // peak (docs/robustness.md, "Limits").
    constexpr uint64_t per_vertex = 24, per_triangle = 384;
    return saturating_mul_add(triangles, per_triangle, saturating_mul_add(vertices, per_vertex, 0));
}

}  // namespace rtt
