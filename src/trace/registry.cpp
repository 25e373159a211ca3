// Tracer kinds -> constructors. Each tracer lives in its own file and exposes one factory.
#include <functional>

#include "rtt/error.h"
#include "rtt/rtt_options.h"
#include "rtt/tracer.h"
#include "simd/simd.h"
#include "trace/factories.h"

namespace rtt {

TraceStats& TraceStats::operator+=(const TraceStats& o) {
    const auto values = o.counter_values();
    const auto fields = counters();
    for (size_t i = 0; i < fields.size(); ++i) *fields[i] += values[i];
    return *this;
}

namespace {

struct TracerEntry {
    const char* kind;
    std::function<std::unique_ptr<Tracer>(const Scene&, const KdTree&)> make;
};

#ifdef RTT_HAVE_EMBREE
auto embree(EmbreeMode mode, bool medium) {
    return [=](const Scene& s, const KdTree&) { return make_embree_tracer(s, mode, medium); };
}
#endif

const std::vector<TracerEntry>& registry() {
    static const std::vector<TracerEntry> entries = {
        {"ray", make_ray_tracer},
        {"brute", make_brute_force_tracer},
        {"packet", make_packet_tracer<4>},
        {"rtt", [](const Scene& s, const KdTree& t) { return make_rtt_tracer(s, t); }},
        {"rtt-paper",
         [](const Scene& s, const KdTree& t) {
             return make_rtt_tracer(s, t, {.rules = RttRules::paper});
         }},
        {"frustum", make_frustum_tracer},
#ifdef RTT_HAVE_SIMD8
        {"packet8", make_packet_tracer<8>},
#endif
#ifdef RTT_HAVE_SIMD16
        {"packet16", make_packet_tracer<16>},
#endif
#ifdef RTT_HAVE_EMBREE
        {"embree", embree(EmbreeMode::packets, false)},
        {"embree-stream", embree(EmbreeMode::stream, false)},
        {"embree1", embree(EmbreeMode::single, false)},
        {"embree-medium", embree(EmbreeMode::packets, true)},
        {"embree-stream-medium", embree(EmbreeMode::stream, true)},
        {"embree1-medium", embree(EmbreeMode::single, true)},
#endif
    };
    return entries;
}

}  // namespace

std::vector<std::string> tracer_kinds() {
    std::vector<std::string> kinds;
    for (const TracerEntry& e : registry()) kinds.emplace_back(e.kind);
    return kinds;
}

void check_tracer_kind(std::string_view kind) {
    for (const TracerEntry& e : registry())
        if (kind == e.kind) return;
    std::string known;
    for (const TracerEntry& e : registry())
        known += (known.empty() ? "" : ", ") + std::string(e.kind);
    throw Error("unknown tracer '" + std::string(kind) + "' (this build has: " + known + ")");
}

std::unique_ptr<Tracer> make_tracer(std::string_view kind, const Scene& scene, const KdTree& tree) {
    check_tracer_kind(kind);
    for (const TracerEntry& e : registry())
        if (kind == e.kind) return e.make(scene, tree);
    return nullptr;  // not reached: check_tracer_kind threw
}

}  // namespace rtt
