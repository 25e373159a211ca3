// Which SIMD kernels run. rtt compiles its hot kernels (packets, the frustum, relevant
// triangles) once per x86-64 ISA and picks, when a tracer is made, the widest that both the
// build has and the CPU runs, capped by the environment variable RTT_ISA and by limit_isa.
// Every ISA gives byte-identical results; only the speed differs.
#pragma once

#include <string_view>
#include <vector>

namespace rtt {

enum class Isa {
    sse42,   ///< "sse4.2": 4-wide SSE kernels (x86-64-v2, every x86-64 CPU since about 2009)
    avx2,    ///< "avx2": 8-wide AVX2 kernels (x86-64-v3)
    avx512,  ///< "avx512": 16-wide AVX-512 kernels (x86-64-v4)
};

/// "sse4.2", "avx2" or "avx512".
std::string_view isa_name(Isa isa);

/// The ISA named `name` (as isa_name writes it); throws rtt::Error naming the choices otherwise.
Isa parse_isa(std::string_view name);

/// The ISAs whose kernels this build has and this CPU runs, narrowest first (never empty).
std::vector<Isa> runnable_isas();

/// The ISA of the tracers make_tracer builds now: the widest runnable one not above the cap.
Isa active_isa();

/// Caps the ISA for tracers made from now on (tracers already made keep theirs). The first cap
/// is the environment's RTT_ISA, when set; an ISA this machine cannot run falls back to the
/// widest below it. Throws rtt::Error for an RTT_ISA that names no ISA.
void limit_isa(Isa cap);

}  // namespace rtt
