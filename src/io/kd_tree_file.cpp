// kd-tree files (rtt/kd_tree_file.h). Loading trusts nothing in the file: the sizes must match
// the file's length before anything is allocated, a checksum covers every byte, and the nodes
// are walked once to check that they form one tree in the builder's layout (below child next,
// above child right after the below subtree), no deeper than the traversal stacks, with every
// leaf range and triangle index in bounds.
#include "rtt/kd_tree_file.h"

#include <bit>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "rtt/error.h"
#include "rtt/io.h"

namespace rtt {
namespace {

static_assert(std::endian::native == std::endian::little, "kd-tree files are little-endian");

constexpr char magic[8] = {'R', 'T', 'T', 'K', 'D', 'T', 'R', 'E'};

/// A 64-bit hash of a byte stream (xxHash64's round and avalanche on four lanes). Not a
/// cryptographic hash: it catches a changed mesh or damaged bytes, while the structural checks
/// alone keep a crafted file from crashing traversal.
class Hasher {
public:
    void update(const void* data, size_t size) {
        if (size == 0) return;  // data may be null (an empty array), which memcpy must not see
        const auto* p = static_cast<const uint8_t*>(data);
        total_ += size;
        if (pending_ > 0) {
            const size_t take = std::min(size, sizeof buffer_ - pending_);
            std::memcpy(buffer_ + pending_, p, take);
            pending_ += take;
            p += take;
            size -= take;
            if (pending_ < sizeof buffer_) return;
            block(buffer_);
            pending_ = 0;
        }
        for (; size >= sizeof buffer_; p += sizeof buffer_, size -= sizeof buffer_) block(p);
        std::memcpy(buffer_, p, size);
        pending_ = size;
    }

    uint64_t digest() const {
        uint64_t h = std::rotl(lane_[0], 1) + std::rotl(lane_[1], 7) + std::rotl(lane_[2], 12) +
                     std::rotl(lane_[3], 18) + total_;
        for (size_t i = 0; i < pending_; ++i) h = std::rotl(h ^ (buffer_[i] * p5), 11) * p1;
        h ^= h >> 33;
        h *= p2;
        h ^= h >> 29;
        h *= p3;
        return h ^ (h >> 32);
    }

private:
    static constexpr uint64_t p1 = 0x9E3779B185EBCA87ull, p2 = 0xC2B2AE3D27D4EB4Full,
                              p3 = 0x165667B19E3779F9ull, p5 = 0x27D4EB2F165667C5ull;

    void block(const uint8_t* p) {
        for (int i = 0; i < 4; ++i) {
            uint64_t w;
            std::memcpy(&w, p + 8 * i, 8);
            lane_[i] = std::rotl(lane_[i] + w * p2, 31) * p1;
        }
    }

    uint64_t lane_[4] = {p1 + p2, p2, 0, 0 - p1};
    uint8_t buffer_[32] = {};
    size_t pending_ = 0;
    uint64_t total_ = 0;
};

/// Everything before the nodes, in file order; each field is written and read one by one.
struct Header {
    uint32_t version = kd_tree_file_version;
    float isect_cost = 0, trav_cost = 0, empty_bonus = 0;
    int32_t max_depth = 0, max_leaf_size = 0;
    uint64_t triangles = 0, mesh_hash = 0;
    uint64_t nodes = 0, leaf_refs = 0;
    // Statistics that take a pass over the tree to compute (compute_stats), kept as built.
    uint64_t leaves = 0, empty_leaves = 0, binned_nodes = 0, small_subtrees = 0;
    int32_t max_leaf_depth = 0;
    double avg_leaf_depth = 0, avg_leaf_triangles = 0, sah_cost = 0;

    template <class F>
    void fields(F&& f) {
        f(version, isect_cost, trav_cost, empty_bonus, max_depth, max_leaf_size, triangles,
          mesh_hash, nodes, leaf_refs, leaves, empty_leaves, binned_nodes, small_subtrees,
          max_leaf_depth, avg_leaf_depth, avg_leaf_triangles, sah_cost);
    }
};

std::vector<uint8_t> encode(Header h) {
    size_t size = sizeof magic;
    h.fields([&](auto&... v) { size += (sizeof v + ...); });
    std::vector<uint8_t> out(size);
    std::memcpy(out.data(), magic, sizeof magic);
    uint8_t* p = out.data() + sizeof magic;
    h.fields([&](auto&... v) { ((std::memcpy(p, &v, sizeof v), p += sizeof v), ...); });
    return out;
}

size_t header_size() {
    return encode(Header{}).size();
}

Header decode(const uint8_t* p) {
    Header h;
    p += sizeof magic;
    h.fields([&](auto&... v) { ((std::memcpy(&v, p, sizeof v), p += sizeof v), ...); });
    return h;
}

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

std::string number(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%g", v);
    return s;
}

std::string config_text(float isect, float trav, float bonus, int depth, int leaf) {
    return "isect " + number(isect) + ", traversal " + number(trav) + ", empty bonus " +
           number(bonus) + ", max depth " + std::to_string(depth) + ", leaf size " +
           std::to_string(leaf);
}

/// Checks the nodes form one tree in the builder's layout; returns the index after the subtree
/// at `i` (whose leaves' lists are in range), or 0 for a bad subtree (`why` says what). Recursion
/// is bounded by kd_max_depth.
size_t check_subtree(const KdTree& tree, size_t i, int depth, std::string& why) {
    const size_t n = tree.nodes.size();
    if (i >= n) {
        why = "node index " + std::to_string(i) + " out of range (" + std::to_string(n) + " nodes)";
        return 0;
    }
    const KdNode& node = tree.nodes[i];
    if (node.is_leaf()) {
        const uint64_t first = node.first_triangle(), count = node.triangle_count();
        if (first + count > tree.leaf_triangles.size()) {
            why = "leaf " + std::to_string(i) + "'s triangle list out of range";
            return 0;
        }
        return i + 1;
    }
    if (depth >= kd_max_depth) {
        why = "tree deeper than " + std::to_string(kd_max_depth);
        return 0;
    }
    if (!std::isfinite(node.split)) {
        why = "node " + std::to_string(i) + " splits at a NaN or infinity";
        return 0;
    }
    const size_t below_end = check_subtree(tree, i + 1, depth + 1, why);
    if (below_end == 0) return 0;
    if (node.above_child() != below_end) {
        why = "node " + std::to_string(i) + "'s above child " + std::to_string(node.above_child()) +
              " is not node " + std::to_string(below_end);
        return 0;
    }
    return check_subtree(tree, below_end, depth + 1, why);
}

/// kd_mesh_hash, and the bounds of the triangles (the tree's bounds, as the build computes
/// them, so a file need not hold them). Throws rtt::Error on a vertex index out of range.
uint64_t mesh_digest(const Scene& scene, Bbox3f& bounds) {
    Hasher h;
    constexpr size_t chunk = 1024;
    std::vector<Vec3f> verts;
    verts.reserve(3 * chunk);
    for (size_t first = 0; first < scene.triangles.size(); first += chunk) {
        verts.clear();
        const size_t end = std::min(scene.triangles.size(), first + chunk);
        for (size_t t = first; t < end; ++t)
            for (uint32_t v : scene.triangles[t]) {
                if (v >= scene.vertices.size())
                    throw Error("kd-tree: triangle " + std::to_string(t) + " uses vertex " +
                                std::to_string(v) + " but there are " +
                                std::to_string(scene.vertices.size()));
                verts.push_back(scene.vertices[v]);
                bounds.extend(scene.vertices[v]);
            }
        h.update(verts.data(), verts.size() * sizeof(Vec3f));
    }
    static_assert(sizeof(Vec3f) == 12, "a vertex is 12 bytes");
    return h.digest();
}

}  // namespace

uint64_t kd_mesh_hash(const Scene& scene) {
    Bbox3f bounds;
    return mesh_digest(scene, bounds);
}

void save_kd_tree(const std::string& path, const KdTree& tree, const Scene& scene,
                  const KdBuildConfig& config) {
    Header h;
    h.isect_cost = config.isect_cost;
    h.trav_cost = config.trav_cost;
    h.empty_bonus = config.empty_bonus;
    h.max_depth = config.max_depth;
    h.max_leaf_size = config.max_leaf_size;
    h.triangles = scene.triangle_count();
    h.mesh_hash = kd_mesh_hash(scene);
    h.nodes = tree.nodes.size();
    h.leaf_refs = tree.leaf_triangles.size();
    const KdStats& s = tree.stats;
    h.leaves = s.leaves;
    h.empty_leaves = s.empty_leaves;
    h.binned_nodes = s.binned_nodes;
    h.small_subtrees = s.small_subtrees;
    h.max_leaf_depth = s.max_depth;
    h.avg_leaf_depth = s.avg_leaf_depth;
    h.avg_leaf_triangles = s.avg_leaf_triangles;
    h.sah_cost = s.sah_cost;
    const std::vector<uint8_t> header = encode(h);

    Hasher sum;
    write_file_atomically(path, [&](std::FILE* f) {
        const auto put = [&](const void* data, size_t size) {
            sum.update(data, size);
            if (size > 0 && std::fwrite(data, 1, size, f) != size)
                throw Error(path + ": cannot write file: " + std::strerror(errno));
        };
        put(header.data(), header.size());
        put(tree.nodes.data(), tree.nodes.size() * sizeof(KdNode));
        put(tree.leaf_triangles.data(), tree.leaf_triangles.size() * sizeof(uint32_t));
        const uint64_t checksum = sum.digest();
        put(&checksum, sizeof checksum);
    });
}

KdTree load_kd_tree(const std::string& path, const Scene& scene, const KdBuildConfig& config) {
    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file) throw Error(path + ": cannot open kd-tree file: " + std::strerror(errno));
    std::FILE* f = file.get();
    if (std::fseek(f, 0, SEEK_END) != 0)
        throw Error(path + ": cannot read kd-tree file: " + std::strerror(errno));
    const long length = std::ftell(f);
    std::rewind(f);
    const std::string corrupt = path + ": truncated or corrupt kd-tree file";
    Hasher sum;
    const auto get = [&](void* data, size_t size) {
        if (size > 0 && std::fread(data, 1, size, f) != size) throw Error(corrupt);
        sum.update(data, size);
    };

    std::vector<uint8_t> bytes(header_size());
    if (length < 0 || size_t(length) < sizeof magic) throw Error(corrupt);
    get(bytes.data(), sizeof magic);
    if (std::memcmp(bytes.data(), magic, sizeof magic) != 0)
        throw Error(path + ": not an rtt kd-tree file (no RTTKDTRE header)");
    if (size_t(length) < bytes.size()) throw Error(corrupt + " (shorter than its header)");
    get(bytes.data() + sizeof magic, bytes.size() - sizeof magic);
    const Header h = decode(bytes.data());
    if (h.version != kd_tree_file_version)
        throw Error(path + ": kd-tree file version " + std::to_string(h.version) +
                    ", this rtt reads version " + std::to_string(kd_tree_file_version));

    // Sizes against the file's length before any allocation (no overflow: both counts are
    // bounded first).
    if (h.nodes == 0 || h.nodes > uint64_t(KdNode::max_index) + 1 || h.leaf_refs > UINT32_MAX)
        throw Error(corrupt + " (" + std::to_string(h.nodes) + " nodes, " +
                    std::to_string(h.leaf_refs) + " leaf references)");
    const uint64_t expected =
        bytes.size() + h.nodes * sizeof(KdNode) + h.leaf_refs * sizeof(uint32_t) + 8;
    if (uint64_t(length) != expected)
        throw Error(corrupt + " (" + std::to_string(length) + " bytes, its header says " +
                    std::to_string(expected) + ")");

    KdTree tree;
    tree.nodes.resize(h.nodes);
    tree.leaf_triangles.resize(h.leaf_refs);
    get(tree.nodes.data(), tree.nodes.size() * sizeof(KdNode));
    get(tree.leaf_triangles.data(), tree.leaf_triangles.size() * sizeof(uint32_t));
    const uint64_t computed = sum.digest();
    uint64_t stored = 0;
    get(&stored, sizeof stored);
    if (stored != computed) throw Error(corrupt + " (checksum mismatch)");

    // The file is intact; is it this mesh's tree, built this way?
    if (h.triangles != scene.triangle_count())
        throw Error(path + ": the tree was built for a mesh of " + std::to_string(h.triangles) +
                    " triangles, this one has " + std::to_string(scene.triangle_count()) +
                    " (build it again with --save-tree)");
    if (h.mesh_hash != mesh_digest(scene, tree.bounds))
        throw Error(path + ": the tree was built for another mesh of " +
                    std::to_string(h.triangles) +
                    " triangles (vertices differ; build it again with --save-tree)");
    if (h.isect_cost != config.isect_cost || h.trav_cost != config.trav_cost ||
        h.empty_bonus != config.empty_bonus || h.max_depth != config.max_depth ||
        h.max_leaf_size != config.max_leaf_size)
        throw Error(
            path + ": the tree was built with another configuration (" +
            config_text(h.isect_cost, h.trav_cost, h.empty_bonus, h.max_depth, h.max_leaf_size) +
            "; this build uses " +
            config_text(config.isect_cost, config.trav_cost, config.empty_bonus, config.max_depth,
                        config.max_leaf_size) +
            ")");

    for (uint32_t t : tree.leaf_triangles)
        if (t >= h.triangles)
            throw Error(corrupt + " (a leaf names triangle " + std::to_string(t) + " of " +
                        std::to_string(h.triangles) + ")");
    std::string why;
    if (check_subtree(tree, 0, 0, why) != tree.nodes.size())
        throw Error(corrupt + " (" + (why.empty() ? "nodes after the tree's last one" : why) + ")");

    KdStats& s = tree.stats;
    s.triangles = h.triangles;
    s.nodes = tree.nodes.size();
    s.leaves = h.leaves;
    s.empty_leaves = h.empty_leaves;
    s.max_depth = h.max_leaf_depth;
    s.avg_leaf_depth = h.avg_leaf_depth;
    s.avg_leaf_triangles = h.avg_leaf_triangles;
    s.triangle_references = tree.leaf_triangles.size();
    s.sah_cost = h.sah_cost;
    s.binned_nodes = h.binned_nodes;
    s.small_subtrees = h.small_subtrees;
    s.memory_bytes =
        tree.nodes.size() * sizeof(KdNode) + tree.leaf_triangles.size() * sizeof(uint32_t);
    s.build_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return tree;
}

}  // namespace rtt
