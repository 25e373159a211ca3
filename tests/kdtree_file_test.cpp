// kd-tree files: a saved tree loads back identical and traces identically; a file for another
// mesh or config, or a damaged one, is refused with rtt::Error and never crashes.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

#include "geom/triangle.h"
#include "rtt/error.h"
#include "rtt/kd_tree_file.h"
#include "rtt/kdtree.h"
#include "rtt/tracer.h"
#include "temp_dir.h"
#include "triangle_soup.h"

namespace rtt {
namespace {

using test::scene_of;
using test::TempDir;
using test::Tris;

Scene test_scene() {
    Tris tris;
    test::add_box(tris, {-2, -2, -2}, {2, 2, 2}, 6);
    test::add_sphere(tris, {0.3f, -0.2f, 0.1f}, 1.f, 24, 12);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.8f, 1.8f), d(-0.2f, 0.2f);
    for (int i = 0; i < 300; ++i) {
        const Vec3f p{u(rng), u(rng), u(rng)};
        tris.push_back({p, p + Vec3f{d(rng), d(rng), d(rng)}, p + Vec3f{d(rng), d(rng), d(rng)}});
    }
    return scene_of(tris);
}

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

/// The load's error message, or "" when it loaded.
std::string load_error(const std::string& path, const Scene& scene,
                       const KdBuildConfig& config = {}) {
    try {
        load_kd_tree(path, scene, config);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

std::vector<Hit> trace(const Scene& scene, const KdTree& tree, const std::vector<Ray>& rays) {
    const std::unique_ptr<Tracer> tracer = make_tracer("ray", scene, tree);
    std::vector<Hit> hits(rays.size());
    intersect_rays(*tracer, rays, hits);
    return hits;
}

TEST(KdTreeFile, RoundTripGivesTheSameTreeAndHits) {
    const TempDir dir("kdfile_round");
    const Scene scene = test_scene();
    const KdTree built = build_kdtree(scene);
    const std::string path = dir.file("scene.kdtree");
    save_kd_tree(path, built, scene);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"scene.kdtree"});  // no temporary left
    const KdTree loaded = load_kd_tree(path, scene);

    ASSERT_EQ(loaded.nodes.size(), built.nodes.size());
    EXPECT_EQ(
        std::memcmp(loaded.nodes.data(), built.nodes.data(), built.nodes.size() * sizeof(KdNode)),
        0);
    EXPECT_EQ(loaded.leaf_triangles, built.leaf_triangles);
    EXPECT_EQ(std::memcmp(&loaded.bounds, &built.bounds, sizeof built.bounds), 0);
    const KdStats &a = loaded.stats, &b = built.stats;
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.nodes, b.nodes);
    EXPECT_EQ(a.leaves, b.leaves);
    EXPECT_EQ(a.empty_leaves, b.empty_leaves);
    EXPECT_EQ(a.max_depth, b.max_depth);
    EXPECT_EQ(a.avg_leaf_depth, b.avg_leaf_depth);
    EXPECT_EQ(a.avg_leaf_triangles, b.avg_leaf_triangles);
    EXPECT_EQ(a.triangle_references, b.triangle_references);
    EXPECT_EQ(a.sah_cost, b.sah_cost);
    EXPECT_EQ(a.memory_bytes, b.memory_bytes);
    EXPECT_EQ(a.binned_nodes, b.binned_nodes);
    EXPECT_EQ(a.small_subtrees, b.small_subtrees);

    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.9f, 1.9f);
    std::vector<Ray> rays(4000);
    for (Ray& r : rays) {
        r.org = {u(rng), u(rng), u(rng)};
        r.dir = Vec3f{u(rng), u(rng), u(rng)} - r.org;
        if (r.dir == Vec3f{}) r.dir = {1, 0, 0};
    }
    const std::vector<Hit> h1 = trace(scene, built, rays), h2 = trace(scene, loaded, rays);
    size_t hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(h1[i].tri, h2[i].tri) << i;
        ASSERT_EQ(std::memcmp(&h1[i].t, &h2[i].t, sizeof(float)), 0) << i;
        hits += h1[i].tri != invalid_triangle;
    }
    EXPECT_EQ(hits, rays.size());  // inside a closed box: every ray hits
}

TEST(KdTreeFile, EmptySceneRoundTrips) {
    const TempDir dir("kdfile_empty");
    const Scene scene = scene_of({});
    const KdTree built = build_kdtree(scene);
    save_kd_tree(dir.file("t"), built, scene);
    const KdTree loaded = load_kd_tree(dir.file("t"), scene);
    EXPECT_EQ(loaded.nodes.size(), built.nodes.size());
    EXPECT_TRUE(loaded.leaf_triangles.empty());
}

TEST(KdTreeFile, OtherMeshOrConfigIsRefused) {
    const TempDir dir("kdfile_mismatch");
    const Scene scene = test_scene();
    const std::string path = dir.file("scene.kdtree");
    save_kd_tree(path, build_kdtree(scene), scene);
    ASSERT_EQ(load_error(path, scene), "");

    Scene moved = scene;  // same count, one coordinate nudged
    moved.vertices[7].x = std::nextafter(moved.vertices[7].x, 10.f);
    EXPECT_NE(load_error(path, moved).find("another mesh"), std::string::npos);

    Scene reordered = scene;  // same vertices, triangles in another order
    std::swap(reordered.triangles[0], reordered.triangles[1]);
    EXPECT_NE(load_error(path, reordered).find("another mesh"), std::string::npos);

    Scene fewer = scene;
    fewer.triangles.pop_back();
    fewer.triangle_material.pop_back();
    EXPECT_NE(load_error(path, fewer).find("mesh of"), std::string::npos);

    KdBuildConfig config;
    config.max_leaf_size = 2;
    EXPECT_NE(load_error(path, scene, config).find("another configuration"), std::string::npos);

    write_bytes(dir.file("text"), "v 0 0 0\n");
    EXPECT_NE(load_error(dir.file("text"), scene).find("not an rtt kd-tree file"),
              std::string::npos);
    EXPECT_NE(load_error(dir.file("absent"), scene).find("cannot open"), std::string::npos);
}

TEST(KdTreeFile, TruncatedAndBitFlippedFilesAreRefused) {
    const TempDir dir("kdfile_damaged");
    const Scene scene = test_scene();
    const std::string good = dir.file("good");
    save_kd_tree(good, build_kdtree(scene), scene);
    const std::string bytes = read_bytes(good);
    const std::string bad = dir.file("bad");

    for (size_t size :
         {size_t(0), size_t(3), size_t(8), size_t(40), bytes.size() / 2, bytes.size() - 1}) {
        write_bytes(bad, bytes.substr(0, size));
        EXPECT_NE(load_error(bad, scene), "") << size;
    }
    write_bytes(bad, bytes + "x");
    EXPECT_NE(load_error(bad, scene), "");

    // Every bit of the header (124 bytes) and random bits of the rest.
    std::mt19937 rng(3);
    std::vector<std::pair<size_t, int>> flips;
    for (size_t i = 0; i < 124; ++i)
        for (int bit = 0; bit < 8; ++bit) flips.emplace_back(i, bit);
    for (int i = 0; i < 300; ++i) flips.emplace_back(rng() % bytes.size(), int(rng() % 8));
    for (const auto& [pos, bit] : flips) {
        std::string flipped = bytes;
        flipped[pos] = char(flipped[pos] ^ (1 << bit));
        write_bytes(bad, flipped);
        ASSERT_NE(load_error(bad, scene), "") << "byte " << pos << " bit " << bit;
    }
}

/// A file whose checksum is right but whose nodes are not a tree (as a crafted file may be):
/// the structural checks refuse it.
TEST(KdTreeFile, CraftedTreesAreRefused) {
    const TempDir dir("kdfile_crafted");
    const Scene scene = test_scene();
    const KdTree built = build_kdtree(scene);
    const std::string path = dir.file("t");
    const auto expect_refused = [&](const KdTree& tree, const char* what) {
        save_kd_tree(path, tree, scene);
        const std::string e = load_error(path, scene);
        EXPECT_NE(e.find("corrupt"), std::string::npos) << what << ": " << e;
    };
    size_t leaf = 0, inner = 0;
    while (!built.nodes[leaf].is_leaf() || built.nodes[leaf].triangle_count() == 0) ++leaf;
    while (built.nodes[inner + 1].is_leaf()) ++inner;

    KdTree t = built;
    t.nodes[leaf].set_leaf(uint32_t(t.leaf_triangles.size()), 1);
    expect_refused(t, "leaf list past the end");
    t = built;
    t.leaf_triangles[0] = uint32_t(scene.triangle_count());
    expect_refused(t, "triangle index out of range");
    t = built;
    t.nodes[0].set_inner(0, 0.f, KdNode::max_index);
    expect_refused(t, "child out of range");
    t = built;
    t.nodes[0].set_inner(0, 0.f, 0);
    expect_refused(t, "cycle to the root");
    t = built;
    t.nodes[inner].set_inner(t.nodes[inner].axis(), std::nanf(""), t.nodes[inner].above_child());
    expect_refused(t, "NaN split");
    t = built;
    t.nodes.push_back(t.nodes[leaf]);
    expect_refused(t, "node after the tree");

    // A chain deeper than the traversal stacks.
    KdTree deep;
    for (int i = 0; i <= kd_max_depth; ++i) {
        KdNode n;
        n.set_inner(0, float(i), uint32_t(2 * (kd_max_depth + 1) - i));
        deep.nodes.push_back(n);
    }
    KdNode empty;
    empty.set_leaf(0, 0);
    deep.nodes.resize(2 * (kd_max_depth + 1) + 1, empty);
    deep.stats = built.stats;
    expect_refused(deep, "too deep");
}

}  // namespace
}  // namespace rtt
