#include "builtin_scenes/furniture.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rtt::proc {

namespace {

int cell_count(float length, float cell) {
    return std::max(1, int(std::ceil(length / cell - 1e-4f)));
}

}  // namespace

void room_shell(SceneBuilder& b, const Vec3f& size, const ShellMaterials& m, float cell) {
    const float X = size.x, Y = size.y, Z = size.z;
    const int nx = cell_count(X, cell), ny = cell_count(Y, cell), nz = cell_count(Z, cell);
    // Each face is a grid whose constant coordinate is exact and whose shared edges are
    // computed identically by both faces (length * i / n), so the shell has no cracks.
    b.add(m.floor, quad_grid({0.f, 0.f, 0.f}, {0.f, 0.f, Z}, {X, 0.f, 0.f}, nz, nx));
    b.add(m.ceiling, quad_grid({0.f, Y, 0.f}, {X, 0.f, 0.f}, {0.f, 0.f, Z}, nx, nz));
    b.add(m.walls, quad_grid({0.f, 0.f, 0.f}, {X, 0.f, 0.f}, {0.f, Y, 0.f}, nx, ny));
    b.add(m.walls, quad_grid({0.f, 0.f, Z}, {0.f, Y, 0.f}, {X, 0.f, 0.f}, ny, nx));
    b.add(m.walls, quad_grid({0.f, 0.f, 0.f}, {0.f, Y, 0.f}, {0.f, 0.f, Z}, ny, nz));
    b.add(m.walls, quad_grid({X, 0.f, 0.f}, {0.f, 0.f, Z}, {0.f, Y, 0.f}, nz, ny));
    const float h = 0.09f, d = 0.015f;
    b.add(m.skirting, box({0.f, 0.f, 0.f}, {X, h, d}));
    b.add(m.skirting, box({0.f, 0.f, Z - d}, {X, h, Z}));
    b.add(m.skirting, box({0.f, 0.f, d}, {d, h, Z - d}));
    b.add(m.skirting, box({X - d, 0.f, d}, {X, h, Z - d}));
}

Xform wall_frame(const Vec3f& size, int wall, float along) {
    const Vec3f up{0.f, 1.f, 0.f};
    switch (wall) {
        case 0:
            return Xform::basis({1.f, 0.f, 0.f}, up, {0.f, 0.f, 1.f}, {along, 0.f, 0.f});
        case 1:
            return Xform::basis({0.f, 0.f, -1.f}, up, {1.f, 0.f, 0.f}, {0.f, 0.f, size.z - along});
        case 2:
            return Xform::basis({0.f, 0.f, 1.f}, up, {-1.f, 0.f, 0.f}, {size.x, 0.f, along});
        default:
            return Xform::basis({-1.f, 0.f, 0.f}, up, {0.f, 0.f, -1.f},
                                {size.x - along, 0.f, size.z});
    }
}

void window(SceneBuilder& b, const Xform& at, float w, float h, const WindowMaterials& m) {
    const float fw = 0.08f, fd = 0.07f, r = 0.01f;
    b.add(m.frame, rounded_block({-fw, -fw, 0.f}, {0.f, h + fw, fd}, r, 2), at);
    b.add(m.frame, rounded_block({w, -fw, 0.f}, {w + fw, h + fw, fd}, r, 2), at);
    b.add(m.frame, rounded_block({0.f, h, 0.f}, {w, h + fw, fd}, r, 2), at);
    b.add(m.frame, rounded_block({0.f, -fw, 0.f}, {w, 0.f, fd}, r, 2), at);
    const float mw = 0.025f, md = 0.045f, split = h * 0.64f;
    b.add(m.frame, rounded_block({w * 0.5f - mw, 0.f, 0.005f}, {w * 0.5f + mw, h, md}, 0.008f, 2),
          at);
    b.add(m.frame, rounded_block({0.f, split - mw, 0.005f}, {w, split + mw, md}, 0.008f, 2), at);
    b.add(m.glass, quad_grid({0.f, 0.f, 0.01f}, {w, 0.f, 0.f}, {0.f, h, 0.f}, 2, 2), at);
    b.add(m.sill,
          rounded_block({-fw - 0.06f, -fw - 0.04f, 0.f}, {w + fw + 0.06f, -fw, 0.22f}, 0.012f, 3),
          at);
}

void curtain(SceneBuilder& b, const Xform& at, float w, float top, float offset, uint32_t mat) {
    // A surface x = w s, y = top t, z = offset + a (1 - cos(2 pi k s)) / 2: k folds of depth a.
    const int nu = 48, nv = 10;
    const float a = 0.07f, folds = std::max(2.f, std::round(w / 0.14f));
    Mesh m;
    for (int i = 0; i <= nu; ++i) {
        const float s = float(i) / float(nu);
        const float phase = 2.f * pi * folds * s;
        const float z = offset + a * 0.5f * (1.f - std::cos(phase));
        const float slope = a * pi * folds * std::sin(phase);  // dz/ds
        const Vec3f n = normalize(Vec3f{-slope * top, 0.f, w * top});
        for (int j = 0; j <= nv; ++j) m.add_vertex({w * s, top * float(j) / float(nv), z}, n);
    }
    const auto stride = uint32_t(nv + 1);
    for (uint32_t i = 0; i < uint32_t(nu); ++i)
        for (uint32_t j = 0; j < uint32_t(nv); ++j) {
            const uint32_t c = i * stride + j;
            m.add_quad(c, c + stride, c + stride + 1, c + 1);
        }
    b.add(mat, m, at);
    // The rod it hangs from.
    const Vec3f rod[2] = {{-0.05f, top + 0.04f, offset + 0.04f},
                          {w + 0.05f, top + 0.04f, offset + 0.04f}};
    const float rr[2] = {0.012f, 0.012f};
    b.add(mat, tube(rod, rr, 12, true), at);
}

Mesh vase(float h, int style, int segments) {
    const int n = 18;
    auto shape = [style](float t) {
        switch (style) {
            case 0:
                return 0.45f + 0.55f * std::sin(pi * t * 1.1f) + 0.3f * std::pow(t, 8.f);
            case 1:
                return 0.75f + 0.25f * t + 0.05f * std::sin(pi * t * 3.f);
            case 2:
                return t < 0.55f
                           ? 1.f - 0.08f * t
                           : 0.3f + 0.656f * 0.5f *
                                        (1.f + std::cos(pi * std::min(1.f, (t - 0.55f) / 0.3f)));
            default:
                return 0.45f + 0.55f * std::sin(0.5f * pi * t);
        }
    };
    const float radius = h * (style == 3 ? 0.45f : 0.28f), wall = 0.06f * radius + 0.003f;
    std::vector<Vec2f> p;
    p.push_back({0.f, 0.f});
    p.push_back({shape(0.f) * radius * 0.9f, 0.f});
    p.push_back({shape(0.f) * radius * 0.9f, 0.f});
    for (int k = 0; k <= n; ++k) {
        const float t = float(k) / float(n);
        p.push_back({shape(t) * radius, h * t});
    }
    p.push_back({shape(1.f) * radius - wall, h});  // lip
    for (int k = n; k >= 2; --k) {
        const float t = float(k) / float(n);
        p.push_back({shape(t) * radius - wall, h * t});
    }
    p.push_back({0.f, h * 2.f / float(n)});
    return lathe(p, segments);
}

void bookshelf(SceneBuilder& b, const Xform& at, float w, float h, float d, int shelves,
               uint32_t wood, std::span<const uint32_t> book_materials,
               std::span<const uint32_t> ornament_materials, SceneRng& rng) {
    const float t = 0.022f, plinth = 0.08f;
    b.add(wood, rounded_block({0.f, 0.f, 0.f}, {t, h, d}, 0.004f, 1), at);
    b.add(wood, rounded_block({w - t, 0.f, 0.f}, {w, h, d}, 0.004f, 1), at);
    b.add(wood, rounded_block({0.f, h - t, 0.f}, {w, h + 0.002f, d + 0.01f}, 0.004f, 1), at);
    b.add(wood, box({t, 0.f, 0.01f}, {w - t, plinth, d - 0.01f}), at);
    b.add(wood, box({t, plinth, 0.f}, {w - t, h - t, 0.008f}), at);
    const float spacing = (h - t - plinth) / float(shelves);
    for (int s = 0; s < shelves; ++s) {
        const float y = plinth + spacing * float(s);
        if (s > 0)
            b.add(wood, rounded_block({t, y - t, 0.008f}, {w - t, y, d - 0.004f}, 0.004f, 1), at);
        float x = t + 0.01f;
        const float end = w - t - 0.01f;
        while (x < end) {
            const float roll = rng.uniform();
            if (roll < 0.08f && !ornament_materials.empty() && end - x > 0.16f) {
                // An ornament: a small vase or a sphere on a stand.
                const uint32_t mat =
                    ornament_materials[rng.below(uint32_t(ornament_materials.size()))];
                const float oh = std::min(spacing - 0.06f, rng.range(0.12f, 0.22f));
                const Vec3f base{x + 0.08f, y, d * 0.5f};
                if (rng.uniform() < 0.6f) {
                    b.add(mat, vase(oh, int(rng.below(4)), 24), at * Xform::translate(base));
                } else {
                    const float r = std::min(0.06f, oh * 0.4f);
                    b.add(mat, sphere(r, 24, 12), at * Xform::translate(base + Vec3f{0.f, r, 0.f}));
                }
                x += 0.16f;
                continue;
            }
            if (roll < 0.12f) {  // leave a gap
                x += rng.range(0.03f, 0.1f);
                continue;
            }
            const float bw = rng.range(0.018f, 0.05f);
            if (x + bw > end) break;
            const float bh = std::min(spacing - 0.03f, rng.range(0.17f, 0.29f));
            const float bd = rng.range(0.14f, std::min(0.24f, d - 0.04f));
            const uint32_t mat = book_materials[rng.below(uint32_t(book_materials.size()))];
            b.add(mat,
                  rounded_block({x, y, d - 0.015f - bd}, {x + bw, y + bh, d - 0.015f}, 0.003f, 1),
                  at);
            x += bw + 0.001f;
        }
    }
}

void frame(SceneBuilder& b, const Xform& at, float w, float h, uint32_t mat) {
    const float fw = 0.05f, fd = 0.035f, r = 0.008f;
    b.add(mat, rounded_block({0.f, 0.f, 0.f}, {fw, h, fd}, r, 2), at);
    b.add(mat, rounded_block({w - fw, 0.f, 0.f}, {w, h, fd}, r, 2), at);
    b.add(mat, rounded_block({fw, 0.f, 0.f}, {w - fw, fw, fd}, r, 2), at);
    b.add(mat, rounded_block({fw, h - fw, 0.f}, {w - fw, h, fd}, r, 2), at);
}

void picture(SceneBuilder& b, const Xform& at, float w, float h, uint32_t frame_mat,
             uint32_t canvas) {
    const float fw = 0.05f;
    frame(b, at, w, h, frame_mat);
    b.add(canvas,
          quad_grid({fw, fw, 0.012f}, {w - 2.f * fw, 0.f, 0.f}, {0.f, h - 2.f * fw, 0.f}, 1, 1),
          at);
}

void door(SceneBuilder& b, const Xform& at, uint32_t wood, uint32_t metal) {
    const float w = 0.9f, h = 2.05f, fw = 0.07f;
    b.add(wood, rounded_block({-fw, 0.f, 0.f}, {0.f, h + fw, 0.03f}, 0.008f, 2), at);
    b.add(wood, rounded_block({w, 0.f, 0.f}, {w + fw, h + fw, 0.03f}, 0.008f, 2), at);
    b.add(wood, rounded_block({0.f, h, 0.f}, {w, h + fw, 0.03f}, 0.008f, 2), at);
    b.add(wood, box({0.f, 0.f, 0.f}, {w, h, 0.02f}, 0.5f), at);
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            const float x0 = 0.1f + float(i) * 0.38f, y0 = 0.15f + float(j) * 0.98f;
            b.add(wood, rounded_block({x0, y0, 0.015f}, {x0 + 0.32f, y0 + 0.8f, 0.032f}, 0.006f, 2),
                  at);
        }
    const Xform knob = at * Xform::translate({w - 0.09f, 1.02f, 0.02f}) * Xform::rotate_x(pi / 2.f);
    b.add(metal, cylinder(0.03f, 0.03f, 0.01f, 24), knob);
    b.add(metal, cylinder(0.01f, 0.01f, 0.06f, 16), knob);
    const Vec3f lever[4] = {
        {0.f, 0.06f, 0.f}, {-0.03f, 0.065f, 0.f}, {-0.08f, 0.065f, 0.f}, {-0.12f, 0.06f, 0.f}};
    const float lr[4] = {0.01f, 0.009f, 0.009f, 0.01f};
    b.add(metal, tube(lever, lr, 12, true), knob);
}

}  // namespace rtt::proc
