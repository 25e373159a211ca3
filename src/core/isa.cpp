// Which kernels run: the build's variants (RTT_KERNELS_* from CMakeLists.txt), the CPU's
// features and the cap (RTT_ISA, limit_isa).
#include "simd/isa.h"

#include <atomic>
#include <cstdlib>
#include <string>

#include "rtt/error.h"

namespace rtt {
namespace {

// The features of each x86-64 level the compiler may use at that -march, by the names GCC and
// clang both know (clang 14 has no "x86-64-vN" or "f16c" strings; every CPU with AVX2, FMA and
// BMI2 has F16C, LZCNT and MOVBE).
bool cpu_runs(Isa isa) {
    __builtin_cpu_init();
    const bool v2 = __builtin_cpu_supports("sse4.2") && __builtin_cpu_supports("popcnt");
    const bool v3 = v2 && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                    __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2");
    const bool v4 = v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                    __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
                    __builtin_cpu_supports("avx512vl");
    switch (isa) {
        case Isa::sse42:
            return v2;
        case Isa::avx2:
            return v3;
        case Isa::avx512:
            return v4;
    }
    return false;
}

bool build_has(Isa isa) {
    if (isa == compiled_isa) return true;  // the library's own compilation: always there
#ifdef RTT_KERNELS_AVX2
    if (isa == Isa::avx2) return true;
#endif
#ifdef RTT_KERNELS_AVX512
    if (isa == Isa::avx512) return true;
#endif
    return false;
}

constexpr Isa all_isas[] = {Isa::sse42, Isa::avx2, Isa::avx512};

// The cap, first read from RTT_ISA: -1 until then.
std::atomic<int> cap_value{-1};

Isa cap() {
    int c = cap_value.load(std::memory_order_relaxed);
    if (c < 0) {
        const char* env = std::getenv("RTT_ISA");
        Isa from_env = Isa::avx512;
        if (env && *env) {
            try {
                from_env = parse_isa(env);
            } catch (const Error& e) {
                throw Error(std::string("environment variable RTT_ISA: ") + e.what());
            }
        }
        int expected = -1;
        cap_value.compare_exchange_strong(expected, int(from_env));
        c = cap_value.load(std::memory_order_relaxed);
    }
    return Isa(c);
}

}  // namespace

std::string_view isa_name(Isa isa) {
    switch (isa) {
        case Isa::sse42:
            return "sse4.2";
        case Isa::avx2:
            return "avx2";
        case Isa::avx512:
            return "avx512";
    }
    return "?";
}

Isa parse_isa(std::string_view name) {
    for (Isa isa : all_isas)
        if (name == isa_name(isa)) return isa;
    throw Error("unknown ISA '" + std::string(name) + "' (choose sse4.2, avx2 or avx512)");
}

std::vector<Isa> runnable_isas() {
    std::vector<Isa> isas;
    for (Isa isa : all_isas)
        if (build_has(isa) && (isa == compiled_isa || cpu_runs(isa))) isas.push_back(isa);
    return isas;
}

Isa active_isa() {
    const std::vector<Isa> isas = runnable_isas();
    Isa chosen = isas.front();  // below the cap when the build has nothing narrower
    for (Isa isa : isas)
        if (int(isa) <= int(cap())) chosen = isa;
    return chosen;
}

void limit_isa(Isa c) {
    cap_value.store(int(c), std::memory_order_relaxed);
}

}  // namespace rtt
