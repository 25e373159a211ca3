#include "experiments/machine_info.h"

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <thread>

#include "simd/simd.h"

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

/// First line printed by `command`, or "" when it fails.
std::string first_line_of(const std::string& command) {
    std::FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return "";
    char buffer[256] = {};
    const bool got = std::fgets(buffer, sizeof buffer, pipe) != nullptr;
    const int status = pclose(pipe);
    return got && status == 0 ? trim(buffer) : "";
}

/// The commit of the tree these sources were compiled from. The source folder is known from
/// __FILE__ (CMake passes absolute paths), so this works from any working directory and needs
/// no configure-time step; a tarball or a machine without git reads "unknown".
std::string git_commit() {
    const std::filesystem::path source_root =
        std::filesystem::path(__FILE__).parent_path().parent_path().parent_path();
    std::error_code ec;
    if (!std::filesystem::exists(source_root / ".git", ec)) return "unknown";
    const std::string git = "git -C '" + source_root.string() + "' ";
    const std::string head = first_line_of(git + "rev-parse HEAD 2>/dev/null");
    if (head.empty()) return "unknown";
    const std::string dirty =
        first_line_of(git + "status --porcelain --untracked-files=no 2>/dev/null | head -n 1");
    return dirty.empty() ? head : head + "+dirty";
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
    m.simd_width = simd_max_width;
    m.isa = simd_max_width == 16 ? "AVX-512" : simd_max_width == 8 ? "AVX2" : "SSE";
    m.compiler = compiler();
    m.git_commit = git_commit();
    m.date = now_iso8601();
    m.load_average = load_average();
    return m;
}

}  // namespace rtt::bench
