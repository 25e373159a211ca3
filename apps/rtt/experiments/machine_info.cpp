#include "experiments/machine_info.h"

#include <cstdio>
#include <ctime>
#include <fstream>
#include <thread>

#include "rtt/isa.h"
#include "rtt_git_commit.h"  // generated at build time

namespace rtt::bench {
namespace {

std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\t')) s.pop_back();
    size_t b = 0;
    while (b < s.size() && (s[b] == ' ' || s[b] == '\t')) ++b;
    return s.substr(b);
}

std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const size_t colon = line.find(':');
            if (colon != std::string::npos) return trim(line.substr(colon + 1));
        }
    return "unknown";
}

/// The commit these sources were compiled from, recorded at build time (cmake/git_commit.cmake).
std::string git_commit() {
    return RTT_GIT_COMMIT;
}

std::string compiler() {
#if defined(__clang__)
    return "clang++ " __clang_version__;
#elif defined(__GNUC__)
    return "g++ " __VERSION__;
#else
    return "unknown";
#endif
}

std::string now_iso8601() {
    const std::time_t t = std::time(nullptr);
    std::tm local{};
    localtime_r(&t, &local);
    char text[64];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S%z", &local);
    return text;
}

}  // namespace

double load_average() {
    std::ifstream in("/proc/loadavg");
    double one = -1;
    if (!(in >> one)) return -1;
    return one;
}

MachineInfo machine_info() {
    MachineInfo m;
    m.cpu_model = cpu_model();
    m.logical_cpus = int(std::thread::hardware_concurrency());
    const Isa isa = active_isa();
    m.simd_width = isa == Isa::avx512 ? 16 : isa == Isa::avx2 ? 8 : 4;
    m.isa = std::string(isa_name(isa));
    m.compiler = compiler();
    m.git_commit = git_commit();
    m.date = now_iso8601();
    m.load_average = load_average();
    return m;
}

}  // namespace rtt::bench
