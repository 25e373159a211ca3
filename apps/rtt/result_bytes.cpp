#include "result_bytes.h"

#include <cstring>
#include <type_traits>

#include "rtt/error.h"

namespace rtt::cli {
namespace {

template <typename T>
void append(std::vector<char>& bytes, const std::vector<T>& v) {
    const char* p = reinterpret_cast<const char*>(v.data());
    bytes.insert(bytes.end(), p, p + v.size() * sizeof(T));
}

template <typename T>
void take(const char*& p, std::vector<T>& into, size_t offset, size_t count) {
    if (into.empty()) return;  // this array is not asked for
    std::memcpy(into.data() + offset, p, count * sizeof(T));
    p += count * sizeof(T);
}

}  // namespace

std::vector<char> pack(const RenderResult& b) {
    std::vector<char> bytes;
    append(bytes, b.pixels);
    append(bytes, b.hits);
    append(bytes, b.shadows);
    append(bytes, b.primary_map);
    append(bytes, b.shadow_map);
    append(bytes, b.depth);
    append(bytes, b.first_triangle);
    return bytes;
}

void unpack(const char* p, RenderResult& whole, int first_row, const BandLayout& band) {
    const size_t px = size_t(first_row) * size_t(whole.width),
                 spp = size_t(whole.aa) * size_t(whole.aa);
    take(p, whole.pixels, px, band.pixels);
    take(p, whole.hits, px * spp, band.samples);
    take(p, whole.shadows, px * spp, band.samples);
    take(p, whole.primary_map, px, band.pixels);
    take(p, whole.shadow_map, px, band.pixels);
    take(p, whole.depth, px, band.pixels);
    take(p, whole.first_triangle, px, band.pixels);
}

void allocate_whole(RenderResult& out, const RenderOptions& o, const AnswerMaps& maps) {
    const size_t pixels = size_t(o.width) * size_t(o.height),
                 samples = pixels * size_t(o.aa) * size_t(o.aa);
    out.width = o.width, out.height = o.height, out.aa = o.aa, out.first_row = 0,
    out.rows = o.height;
    out.pixels.resize(pixels);
    if (o.hits_buffer) out.hits.resize(samples);
    if (o.shadow_buffer) out.shadows.resize(samples);
    if (maps.primary) out.primary_map.resize(pixels);
    if (maps.shadow_light >= 0) out.shadow_map.resize(pixels);
    if (o.pixel_hits) out.depth.resize(pixels), out.first_triangle.resize(pixels);
}

std::vector<char> pack_stats(const RenderStats& s) {
    std::vector<uint64_t> counts;
    std::vector<double> values;
    for (const KindStats* k : {&s.primary, &s.shadow, &s.secondary}) {
        const auto counters = k->counter_values();
        counts.insert(counts.end(), counters.begin(), counters.end());
        values.push_back(k->seconds);
    }
    counts.insert(counts.end(), s.rays_by_depth.begin(), s.rays_by_depth.end());
    counts.push_back(uint64_t(s.threads));
    values.push_back(s.wall_seconds);
    std::vector<char> bytes;
    append(bytes, counts);
    append(bytes, values);
    return bytes;
}

void unpack_stats(const char* p, RenderStats& s) {
    std::vector<uint64_t> counts(3 * KindStats{}.counters().size() + s.rays_by_depth.size() + 1);
    std::vector<double> values(4);
    take(p, counts, 0, counts.size());
    take(p, values, 0, values.size());
    size_t i = 0;
    KindStats* kinds[3] = {&s.primary, &s.shadow, &s.secondary};
    for (int k = 0; k < 3; ++k) {
        for (uint64_t* field : kinds[k]->counters()) *field = counts[i++];
        kinds[k]->seconds = values[size_t(k)];
    }
    for (uint64_t& d : s.rays_by_depth) d = counts[i++];
    s.threads = int(counts[i]);
    s.wall_seconds = values[3];
}

std::vector<char> pack_tree(const KdTree& tree) {
    static_assert(std::is_trivially_copyable_v<KdNode> && std::is_trivially_copyable_v<KdStats> &&
                  std::is_trivially_copyable_v<Bbox3f>);
    const uint64_t sizes[2] = {tree.nodes.size(), tree.leaf_triangles.size()};
    const size_t node_bytes = tree.nodes.size() * sizeof(KdNode);
    std::vector<char> bytes(sizeof sizes + sizeof tree.bounds + sizeof tree.stats + node_bytes +
                            tree.leaf_triangles.size() * sizeof(uint32_t));
    char* p = bytes.data();
    for (const auto& [data, size] :
         {std::pair<const void*, size_t>{sizes, sizeof sizes},
          {&tree.bounds, sizeof tree.bounds},
          {&tree.stats, sizeof tree.stats},
          {tree.nodes.data(), node_bytes},
          {tree.leaf_triangles.data(), tree.leaf_triangles.size() * sizeof(uint32_t)}}) {
        if (size) std::memcpy(p, data, size);
        p += size;
    }
    return bytes;
}

KdTree unpack_tree(const std::vector<char>& bytes) {
    KdTree tree;
    uint64_t sizes[2];
    const size_t head = sizeof sizes + sizeof tree.bounds + sizeof tree.stats;
    if (bytes.size() < head) throw Error("a shared kd-tree arrived incomplete");
    std::memcpy(sizes, bytes.data(), sizeof sizes);
    if (bytes.size() != head + sizes[0] * sizeof(KdNode) + sizes[1] * sizeof(uint32_t))
        throw Error("a shared kd-tree arrived with the wrong size");
    std::memcpy(&tree.bounds, bytes.data() + sizeof sizes, sizeof tree.bounds);
    std::memcpy(&tree.stats, bytes.data() + sizeof sizes + sizeof tree.bounds, sizeof tree.stats);
    tree.nodes.resize(sizes[0]);
    tree.leaf_triangles.resize(sizes[1]);
    const char* p = bytes.data() + head;
    take(p, tree.nodes, 0, tree.nodes.size());
    take(p, tree.leaf_triangles, 0, tree.leaf_triangles.size());
    return tree;
}

uint64_t geometry_hash(const Scene& scene) {
    // FNV-1a over the bytes: cheap next to a build, and any changed coordinate changes it.
    uint64_t h = 0xcbf29ce484222325ull;
    const auto add = [&](const void* data, size_t size) {
        const auto* b = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < size; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
    };
    const uint64_t counts[2] = {scene.vertices.size(), scene.triangles.size()};
    add(counts, sizeof counts);
    add(scene.vertices.data(), scene.vertices.size() * sizeof(Vec3f));
    add(scene.triangles.data(), scene.triangles.size() * sizeof(TriangleIndices));
    return h;
}

}  // namespace rtt::cli
