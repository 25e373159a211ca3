#include "builtin_scenes/plant_models.h"

#include <cmath>
#include <vector>

namespace rtt::proc {

namespace {

const Vec3f up{0.f, 1.f, 0.f};

/// Unit vector at azimuth `az` (from +x towards +z) and elevation `el` above the xz plane.
Vec3f spherical(float az, float el) {
    return {std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az)};
}

Vec3f jitter(SceneRng& rng, float a) {
    return {rng.range(-a, a), rng.range(-a, a), rng.range(-a, a)};
}

Vec3f lerp(const Vec3f& a, const Vec3f& b, float t) {
    return a + (b - a) * t;
}

/// A random walk of n steps from `start`, bending by `droop` towards -y per step.
std::vector<Vec3f> grow(const Vec3f& start, Vec3f dir, float len, int n, float droop, float wiggle,
                        SceneRng& rng) {
    std::vector<Vec3f> path{start};
    Vec3f p = start;
    for (int k = 0; k < n; ++k) {
        dir = normalize(dir + jitter(rng, wiggle) - up * droop);
        p += dir * (len / float(n));
        path.push_back(p);
    }
    return path;
}

/// Pulls a point horizontally towards the plant axis so it stays within `r` of it.
Vec3f clamp_reach(const Vec3f& p, float r) {
    const float h = std::sqrt(p.x * p.x + p.z * p.z);
    return h <= r ? p : Vec3f{p.x * (r / h), p.y, p.z * (r / h)};
}

Mesh tapered_tube(std::span<const Vec3f> path, float r0, float r1, int sides) {
    std::vector<float> radii;
    for (size_t i = 0; i < path.size(); ++i)
        radii.push_back(r0 + (r1 - r0) * float(i) / float(path.size() - 1));
    return tube(path, radii, sides, false);
}

/// Places a leaf prototype of unit length at `base`, midrib along `dir`, blade facing `hint`
/// as far as it can, scaled to `size`.
void add_leaf(SceneBuilder& b, const PlantMaterials& m, const Mesh& proto, const Xform& at,
              const Vec3f& base, const Vec3f& dir, const Vec3f& hint, float size, SceneRng& rng) {
    const Vec3f y = normalize(dir);
    Vec3f z = hint - y * dot(hint, y);
    if (dot(z, z) < 1e-6f) z = Vec3f{1.f, 0.f, 0.f} - y * y.x;
    z = normalize(z);
    const Vec3f x = cross(y, z);
    const uint32_t mat = m.leaves[rng.below(uint32_t(m.leaves.size()))];
    b.add(mat, proto, at * Xform::basis(x * size, y * size, z * size, base));
}

}  // namespace

void flower_pot(SceneBuilder& b, const Xform& at, float r, float h, uint32_t pot, uint32_t soil) {
    const std::vector<Vec2f> p{{0.f, 0.f},
                               {0.72f * r, 0.f},
                               {0.72f * r, 0.f},
                               {0.95f * r, 0.86f * h},
                               {0.95f * r, 0.86f * h},
                               {1.05f * r, 0.88f * h},
                               {1.05f * r, h},
                               {1.05f * r, h},
                               {0.96f * r, h},
                               {0.96f * r, h},
                               {0.92f * r, 0.88f * h},
                               {0.92f * r, 0.88f * h},
                               {0.f, 0.88f * h}};
    b.add(pot, lathe(p, 40), at);
    // Soil: a slightly domed disc just below the inner rim.
    const std::vector<Vec2f> s{{0.93f * r, 0.879f * h}, {0.5f * r, 0.9f * h}, {0.f, 0.91f * h}};
    b.add(soil, lathe(s, 40), at);
}

void fig_crown(SceneBuilder& b, const Xform& at, const Vec3f& base, float height, float reach,
               const PlantMaterials& m, SceneRng& rng) {
    // Twigs (up to 11 cm) and leaves (up to 7.5 cm) stick out of the branches: keep the
    // branches that much inside the reach.
    const float branch_reach = std::max(0.05f, reach - 0.19f);
    const float trunk_h = 0.45f * height;
    std::vector<Vec3f> trunk = grow(base, up, trunk_h, 6, 0.f, 0.08f, rng);
    for (Vec3f& p : trunk) p = clamp_reach(p, branch_reach);
    b.add(m.stem, tapered_tube(trunk, 0.01f + 0.008f * height, 0.006f, 7), at);
    const Mesh leaf_a = leaf(1.f, 0.45f, 0.25f, 0.3f, 2), leaf_b = leaf(1.f, 0.38f, 0.3f, 0.4f, 2);
    const int branches = 20 + int(rng.below(6));
    for (int i = 0; i < branches; ++i) {
        const float t = 0.25f + 0.75f * (float(i) + 0.5f) / float(branches);
        const float ft = t * float(trunk.size() - 1);
        const size_t seg = std::min(trunk.size() - 2, size_t(ft));
        const Vec3f start = lerp(trunk[seg], trunk[seg + 1], ft - float(seg));
        const float az = 2.39996f * float(i) + rng.range(-0.3f, 0.3f);
        const float len = height * (0.28f + 0.24f * (1.f - t)) * rng.range(0.8f, 1.2f);
        std::vector<Vec3f> branch =
            grow(start, spherical(az, rng.range(0.2f, 0.9f)), len, 6, 0.1f, 0.15f, rng);
        for (Vec3f& p : branch) p = clamp_reach(p, branch_reach);
        b.add(m.stem, tapered_tube(branch, 0.006f, 0.0025f, 5), at);
        // Twigs off each branch segment, each carrying alternate leaves.
        for (size_t k = 1; k < branch.size(); ++k) {
            const Vec3f seg_dir = normalize(branch[k] - branch[k - 1]);
            for (int j = 0; j < 3; ++j) {
                const Vec3f p = lerp(branch[k - 1], branch[k], (float(j) + 0.5f) / 3.f);
                const Vec3f tdir =
                    normalize(seg_dir + spherical(rng.range(0.f, 2.f * pi), 0.3f) * 0.9f);
                const float tl = rng.range(0.05f, 0.11f);
                const Vec3f twig[2] = {p, p + tdir * tl - up * (0.1f * tl)};
                const float tr[2] = {0.0018f, 0.0009f};
                b.add(m.stem, tube(twig, tr, 3, false), at);
                const Vec3f side = normalize(cross(tdir, up) + jitter(rng, 0.2f));
                const int leaves = 5 + int(rng.below(4));
                for (int l = 0; l < leaves; ++l) {
                    const float s = (float(l) + 1.f) / float(leaves);
                    const float sign = l % 2 ? 1.f : -1.f;
                    const Vec3f dir =
                        tdir * 0.6f + side * (0.8f * sign) - up * 0.25f + jitter(rng, 0.3f);
                    add_leaf(b, m, l % 3 ? leaf_a : leaf_b, at, lerp(twig[0], twig[1], s), dir,
                             up + jitter(rng, 0.5f), rng.range(0.045f, 0.075f), rng);
                }
            }
        }
    }
}

void ficus(SceneBuilder& b, const Xform& at, float height, float reach, const PlantMaterials& m,
           SceneRng& rng) {
    const float pot_r = std::min(0.1f + 0.08f * height, reach), pot_h = 1.1f * pot_r;
    flower_pot(b, at, pot_r, pot_h, rng.uniform() < 0.5f ? m.pot : m.pot_alt, m.soil);
    fig_crown(b, at, {0.f, 0.9f * pot_h, 0.f}, height - 0.9f * pot_h, reach, m, rng);
}

void dracaena(SceneBuilder& b, const Xform& at, float height, float reach, const PlantMaterials& m,
              SceneRng& rng) {
    const float pot_r = 0.2f, pot_h = 0.3f;
    // Old leaves arch out almost horizontally: their length bounds the crown's reach.
    const float leaf_len = std::min(0.5f, reach - 0.1f);
    flower_pot(b, at, pot_r, pot_h, rng.uniform() < 0.5f ? m.pot : m.pot_alt, m.soil);
    const Mesh strap = leaf(1.f, 0.09f, 0.3f, 0.45f, 5);
    const int canes = 3 + int(rng.below(2));
    for (int c = 0; c < canes; ++c) {
        const float az = 2.f * pi * float(c) / float(canes) + rng.range(-0.4f, 0.4f);
        const Vec3f foot{0.06f * std::cos(az), 0.9f * pot_h, 0.06f * std::sin(az)};
        const float cane_h = (height - 0.55f) * (0.45f + 0.55f * float(c) / float(canes - 1));
        std::vector<Vec3f> cane = grow(foot, spherical(az, 1.45f), cane_h, 5, 0.f, 0.04f, rng);
        for (Vec3f& p : cane) p = clamp_reach(p, 0.09f);
        b.add(m.stem, tapered_tube(cane, 0.025f, 0.018f, 10), at);
        // Crown: leaves from upright (young, inside) to arching down (old, outside).
        const Vec3f top = cane.back();
        const int leaves = 30 + int(rng.below(12));
        for (int l = 0; l < leaves; ++l) {
            const float age = float(l) / float(leaves);
            const float el = 1.35f - 1.2f * age + rng.range(-0.15f, 0.15f);
            const Vec3f dir = spherical(2.39996f * float(l) + rng.range(-0.2f, 0.2f), el);
            const Vec3f base = top - up * (0.08f * age);
            add_leaf(b, m, strap, at, base, dir, up, leaf_len * rng.range(0.6f, 1.f), rng);
        }
    }
}

void pilea(SceneBuilder& b, const Xform& at, float reach, const PlantMaterials& m, SceneRng& rng) {
    const float pot_r = 0.065f, pot_h = 0.1f;
    flower_pot(b, at, pot_r, pot_h, rng.uniform() < 0.5f ? m.pot : m.pot_alt, m.soil);
    const Mesh round_leaf = leaf(1.f, 0.9f, 0.12f, 0.1f, 3);
    const int stalks = 24 + int(rng.below(12));
    for (int s = 0; s < stalks; ++s) {
        const float az = 2.39996f * float(s);
        const float el = rng.range(0.6f, 1.4f);
        std::vector<Vec3f> stalk = grow({0.f, 0.9f * pot_h, 0.f}, spherical(az, el),
                                        rng.range(0.06f, 0.18f), 3, 0.1f, 0.1f, rng);
        // Leaves are up to 5 cm across: keep the stalk ends that much inside the reach.
        for (Vec3f& p : stalk) p = clamp_reach(p, std::max(0.02f, reach - 0.05f));
        b.add(m.stem, tapered_tube(stalk, 0.0018f, 0.0012f, 3), at);
        const Vec3f outward = spherical(az, 0.1f);
        add_leaf(b, m, round_leaf, at, stalk.back(), outward + jitter(rng, 0.3f),
                 up + outward * 0.5f, rng.range(0.035f, 0.05f), rng);
    }
}

void topiary(SceneBuilder& b, const Xform& at, float height, const PlantMaterials& m,
             SceneRng& rng) {
    const float pot_r = 0.07f, pot_h = 0.1f, ball_r = 0.32f * height;
    flower_pot(b, at, pot_r, pot_h, rng.uniform() < 0.5f ? m.pot : m.pot_alt, m.soil);
    const Vec3f centre{0.f, height - ball_r, 0.f};
    const Vec3f stem[2] = {{0.f, 0.9f * pot_h, 0.f}, centre};
    const float sr[2] = {0.006f, 0.005f};
    b.add(m.stem, tube(stem, sr, 6, false), at);
    // Leaves on a Fibonacci sphere (even coverage), pointing outward and lying along the
    // surface, with jitter so the ball looks clipped, not regular.
    const Mesh tiny = leaf(1.f, 0.5f, 0.2f, 0.2f, 2);
    const int leaves = int(4.f * pi * ball_r * ball_r / (0.011f * 0.011f) * 0.35f);
    for (int l = 0; l < leaves; ++l) {
        const float yy = 1.f - 2.f * (float(l) + 0.5f) / float(leaves);
        const float rr = std::sqrt(std::max(0.f, 1.f - yy * yy));
        const float az = 2.39996f * float(l);
        const Vec3f n{rr * std::cos(az), yy, rr * std::sin(az)};
        const Vec3f base = centre + n * (ball_r * rng.range(0.82f, 0.97f));
        const Vec3f dir = normalize(n * 0.5f + normalize(cross(n, up) + jitter(rng, 0.6f)));
        add_leaf(b, m, tiny, at, base, dir, n + jitter(rng, 0.4f), rng.range(0.016f, 0.026f), rng);
    }
}

}  // namespace rtt::proc
