// What a benchmark result needs to be read later: which machine, which code, when, how loaded.
#pragma once

#include <string>

namespace rtt::bench {

struct MachineInfo {
    std::string cpu_model;     ///< /proc/cpuinfo "model name" ("unknown" if unreadable).
    int logical_cpus = 0;      ///< std::thread::hardware_concurrency().
    std::string isa;           ///< The kernels that run (rtt/isa.h): "avx512", "avx2" or "sse4.2".
    int simd_width = 4;        ///< Lanes of their widest packets.
    std::string compiler;      ///< e.g. "g++ 12.2.0".
    std::string git_commit;    ///< HEAD of the source tree, "+dirty" if modified; "unknown" if
                               ///< the sources are not a git checkout or git is missing.
    std::string date;          ///< Local time of the run, ISO 8601.
    double load_average = -1;  ///< 1-minute load average at the start (/proc/loadavg).
};

/// Gathers the fields above. Never throws: missing information reads "unknown" / -1.
MachineInfo machine_info();

/// The current 1-minute load average, or -1 when /proc/loadavg is unreadable.
double load_average();

}  // namespace rtt::bench
