// Tracer kinds -> constructors. Each tracer lives in its own file and exposes one factory.
#include <functional>

#include "rtt/error.h"
#include "rtt/rtt_options.h"
#include "rtt/tracer.h"
#include "simd/isa.h"
#include "trace/factories.h"
#include "trace/kernels.h"

namespace rtt {

// The other ISAs' kernels (trace/kernels.h, compiled once per ISA by CMakeLists.txt); this
// file's own ISA's come from trace/kernels.h.
#ifdef RTT_KERNELS_AVX2
namespace isa_avx2 {
std::unique_ptr<Tracer> make_kernel_tracer(std::string_view, const Scene&, const KdTree&,
                                           const RttOptions&);
}
#endif
#ifdef RTT_KERNELS_AVX512
namespace isa_avx512 {
std::unique_ptr<Tracer> make_kernel_tracer(std::string_view, const Scene&, const KdTree&,
                                           const RttOptions&);
}
#endif

namespace {

struct TracerEntry {
    const char* kind;
    std::function<std::unique_ptr<Tracer>(const Scene&, const KdTree&)> make;
    Isa needs = Isa::sse42;  ///< the narrowest ISA whose kernels have the kind
    bool kd_tree = true;     ///< reads the kd-tree (tracer_uses_kdtree)
};

// The kernel tracer `kind` of the active ISA (rtt/isa.h).
std::unique_ptr<Tracer> make_kernels(std::string_view kind, const Scene& s, const KdTree& t,
                                     const RttOptions& options) {
    const Isa isa = active_isa();
    std::unique_ptr<Tracer> tracer;
    if (isa == compiled_isa) tracer = RTT_ISA_NS::make_kernel_tracer(kind, s, t, options);
#ifdef RTT_KERNELS_AVX2
    if (isa == Isa::avx2) tracer = isa_avx2::make_kernel_tracer(kind, s, t, options);
#endif
#ifdef RTT_KERNELS_AVX512
    if (isa == Isa::avx512) tracer = isa_avx512::make_kernel_tracer(kind, s, t, options);
#endif
    if (!tracer)  // not reached: check_tracer_kind knows which kinds each ISA has
        throw Error("tracer '" + std::string(kind) + "' is not in this run's " +
                    std::string(isa_name(isa)) + " kernels");
    return tracer;
}

auto kernels(const char* kind) {
    return [=](const Scene& s, const KdTree& t) { return make_kernels(kind, s, t, {}); };
}

#ifdef RTT_HAVE_EMBREE
auto embree(EmbreeMode mode, bool medium) {
    return [=](const Scene& s, const KdTree&) { return make_embree_tracer(s, mode, medium); };
}
#endif

const std::vector<TracerEntry>& registry() {
    static const std::vector<TracerEntry> entries = {
        {"ray", make_ray_tracer},
        {"brute", make_brute_force_tracer, Isa::sse42, false},
        {"bvh", kernels("bvh"), Isa::sse42, false},
        {"bvh-high", kernels("bvh-high"), Isa::sse42, false},
        {"packet", kernels("packet")},
        {"rtt", kernels("rtt")},
        {"rtt-paper",
         [](const Scene& s, const KdTree& t) {
             return make_rtt_tracer(s, t, {.rules = RttRules::paper});
         }},
        {"frustum", kernels("frustum")},
        {"packet8", kernels("packet8"), Isa::avx2},
        {"packet16", kernels("packet16"), Isa::avx512},
#ifdef RTT_HAVE_EMBREE
        {"embree", embree(EmbreeMode::packets, false), Isa::sse42, false},
        {"embree-stream", embree(EmbreeMode::stream, false), Isa::sse42, false},
        {"embree1", embree(EmbreeMode::single, false), Isa::sse42, false},
        {"embree-medium", embree(EmbreeMode::packets, true), Isa::sse42, false},
        {"embree-stream-medium", embree(EmbreeMode::stream, true), Isa::sse42, false},
        {"embree1-medium", embree(EmbreeMode::single, true), Isa::sse42, false},
#endif
    };
    return entries;
}

}  // namespace

std::unique_ptr<Tracer> make_rtt_tracer(const Scene& scene, const KdTree& tree,
                                        const RttOptions& options) {
    options.validate();
    return make_kernels("rtt", scene, tree, options);
}

std::vector<std::string> tracer_kinds() {
    const Isa isa = active_isa();
    std::vector<std::string> kinds;
    for (const TracerEntry& e : registry())
        if (int(e.needs) <= int(isa)) kinds.emplace_back(e.kind);
    return kinds;
}

void check_tracer_kind(std::string_view kind) {
    const Isa isa = active_isa();
    std::string known;
    for (const TracerEntry& e : registry()) {
        if (kind == e.kind && int(e.needs) <= int(isa)) return;
        if (kind == e.kind)
            throw Error("tracer '" + std::string(kind) + "' needs " +
                        std::string(isa_name(e.needs)) + " kernels; this run has " +
                        std::string(isa_name(isa)) + " (the CPU, the build, rtt --isa or RTT_ISA)");
        if (int(e.needs) <= int(isa)) known += (known.empty() ? "" : ", ") + std::string(e.kind);
    }
    throw Error("unknown tracer '" + std::string(kind) + "' (this build has: " + known + ")");
}

bool tracer_uses_kdtree(std::string_view kind) {
    check_tracer_kind(kind);
    for (const TracerEntry& e : registry())
        if (kind == e.kind) return e.kd_tree;
    return true;  // not reached: check_tracer_kind threw
}

std::unique_ptr<Tracer> make_tracer(std::string_view kind, const Scene& scene, const KdTree& tree) {
    check_tracer_kind(kind);
    for (const TracerEntry& e : registry())
        if (kind == e.kind) return e.make(scene, tree);
    return nullptr;  // not reached: check_tracer_kind threw
}

}  // namespace rtt
