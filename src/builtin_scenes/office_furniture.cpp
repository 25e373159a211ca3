#include "builtin_scenes/office_furniture.h"

#include <cmath>
#include <vector>

#include "builtin_scenes/furniture.h"

namespace rtt::proc {

namespace {

Mesh bent_tube(std::initializer_list<Vec3f> corners, float corner_radius, float r, int sides) {
    const std::vector<Vec3f> c(corners);
    const std::vector<Vec3f> path = rounded_polyline(c, corner_radius, 6);
    return tube(path, std::vector<float>(path.size(), r), sides, true);
}

/// A key cap: a truncated pyramid w x d at the bottom (y = 0), inset by `inset` at the top
/// (y = h), centred on the origin; no bottom face (it sits on the keyboard).
Mesh key_cap(float w, float d, float h, float inset) {
    Mesh m;
    const float x0 = -0.5f * w, x1 = 0.5f * w, z0 = -0.5f * d, z1 = 0.5f * d;
    const uint32_t b0 = m.add_vertex({x0, 0.f, z0}), b1 = m.add_vertex({x1, 0.f, z0}),
                   b2 = m.add_vertex({x1, 0.f, z1}), b3 = m.add_vertex({x0, 0.f, z1});
    const uint32_t t0 = m.add_vertex({x0 + inset, h, z0 + inset}),
                   t1 = m.add_vertex({x1 - inset, h, z0 + inset}),
                   t2 = m.add_vertex({x1 - inset, h, z1 - inset}),
                   t3 = m.add_vertex({x0 + inset, h, z1 - inset});
    m.add_quad(t0, t3, t2, t1);  // top, facing +y
    m.add_quad(b0, t0, t1, b1);  // -z
    m.add_quad(b1, t1, t2, b2);  // +x
    m.add_quad(b2, t2, t3, b3);  // +z
    m.add_quad(b3, t3, t0, b0);  // -x
    return m;
}

}  // namespace

void desk(SceneBuilder& b, const Xform& at, const OfficeMaterials& m) {
    b.add(m.desk_top, rounded_box({0.8f, 0.015f, 0.4f}, 0.008f, 2),
          at * Xform::translate({0.f, desk_height - 0.015f, 0.f}));
    // Sled legs: a closed loop of rectangular path bent from one round tube on each side.
    for (float sx : {-1.f, 1.f}) {
        const float x = sx * 0.74f, top = desk_height - 0.03f;
        b.add(m.desk_frame,
              bent_tube({{x, top, -0.34f}, {x, 0.02f, -0.34f}, {x, 0.02f, 0.34f}, {x, top, 0.34f}},
                        0.07f, 0.02f, 12),
              at);
        b.add(m.desk_frame,
              rounded_block({x - 0.03f, top - 0.02f, -0.36f}, {x + 0.03f, top + 0.001f, 0.36f},
                            0.008f, 2),
              at);
    }
    b.add(m.desk_frame, bent_tube({{-0.74f, 0.55f, -0.3f}, {0.74f, 0.55f, -0.3f}}, 0.f, 0.015f, 12),
          at);
    b.add(m.partition,
          rounded_block({-0.7f, 0.3f, -0.39f}, {0.7f, desk_height - 0.035f, -0.37f}, 0.006f, 2),
          at);
    // Drawer pedestal under the right half.
    b.add(m.cabinet, rounded_block({0.24f, 0.03f, -0.3f}, {0.66f, 0.69f, 0.34f}, 0.01f, 2), at);
    for (int i = 0; i < 3; ++i) {
        const float y0 = 0.05f + 0.215f * float(i), y1 = y0 + 0.2f;
        b.add(m.cabinet, rounded_block({0.26f, y0, 0.34f}, {0.64f, y1, 0.355f}, 0.005f, 2), at);
        const float hy = y1 - 0.04f;
        b.add(m.handle,
              bent_tube({{0.38f, hy, 0.355f},
                         {0.38f, hy, 0.375f},
                         {0.52f, hy, 0.375f},
                         {0.52f, hy, 0.355f}},
                        0.012f, 0.005f, 8),
              at);
    }
}

void office_chair(SceneBuilder& b, const Xform& at, const OfficeMaterials& m) {
    // Five-star base: each arm an extruded side profile (radial distance, height).
    const Vec2f arm_profile[] = {{0.03f, 0.095f}, {0.29f, 0.07f}, {0.33f, 0.075f}, {0.335f, 0.095f},
                                 {0.3f, 0.1f},    {0.2f, 0.125f}, {0.1f, 0.15f},   {0.03f, 0.16f}};
    const Mesh arm = extrude(arm_profile, 0.045f);
    Mesh wheel;
    wheel.append(torus(0.024f, 0.009f, 16, 8),
                 Xform::translate({0.f, 0.f, -0.012f}) * Xform::rotate_x(0.5f * pi));
    wheel.append(torus(0.024f, 0.009f, 16, 8),
                 Xform::translate({0.f, 0.f, 0.012f}) * Xform::rotate_x(0.5f * pi));
    const Mesh housing = rounded_box({0.018f, 0.022f, 0.02f}, 0.008f, 1);
    const Mesh stem = cylinder(0.007f, 0.007f, 0.03f, 12);
    for (int i = 0; i < 5; ++i) {
        const Xform spoke = at * Xform::rotate_y(2.f * pi * float(i) / 5.f + 0.3f);
        b.add(m.chair_plastic, arm, spoke * Xform::translate({0.f, 0.f, -0.0225f}));
        b.add(m.chair_plastic, wheel, spoke * Xform::translate({0.31f, 0.033f, 0.f}));
        b.add(m.chair_plastic, housing, spoke * Xform::translate({0.29f, 0.045f, 0.f}));
        b.add(m.chrome, stem, spoke * Xform::translate({0.31f, 0.055f, 0.f}));
    }
    b.add(m.chair_plastic, cylinder(0.055f, 0.045f, 0.08f, 32),
          at * Xform::translate({0.f, 0.085f, 0.f}));
    b.add(m.chrome, cylinder(0.026f, 0.026f, 0.16f, 32), at * Xform::translate({0.f, 0.16f, 0.f}));
    b.add(m.chair_plastic, cylinder(0.036f, 0.032f, 0.12f, 32),
          at * Xform::translate({0.f, 0.3f, 0.f}));
    b.add(m.chair_plastic, rounded_box({0.13f, 0.025f, 0.14f}, 0.015f, 2),
          at * Xform::translate({0.f, 0.43f, 0.f}));
    // Seat: a rounded cushion built lying in xy, dished by bending, then turned face up.
    Mesh seat = rounded_box({0.255f, 0.245f, 0.045f}, 0.04f, 4, Shading::smooth, 0.1f);
    bend(seat, -0.5f);
    b.add(m.chair_fabric, seat,
          at * Xform::translate({0.f, 0.49f, 0.02f}) * Xform::rotate_x(-0.5f * pi));
    // Backrest curved around the sitter, on a bent spine.
    Mesh back = rounded_box({0.23f, 0.28f, 0.035f}, 0.03f, 4, Shading::smooth, 0.1f);
    bend(back, -0.7f);
    b.add(m.chair_fabric, back,
          at * Xform::translate({0.f, 0.86f, -0.27f}) * Xform::rotate_x(-0.12f));
    b.add(m.chair_plastic,
          bent_tube({{0.f, 0.44f, -0.08f}, {0.f, 0.44f, -0.31f}, {0.f, 0.75f, -0.33f}}, 0.08f,
                    0.022f, 16),
          at);
    // Armrests.
    for (float sx : {-1.f, 1.f}) {
        b.add(m.chair_plastic,
              bent_tube({{sx * 0.12f, 0.445f, -0.03f},
                         {sx * 0.29f, 0.445f, -0.03f},
                         {sx * 0.29f, 0.64f, -0.05f}},
                        0.06f, 0.016f, 12),
              at);
        b.add(m.chair_plastic, rounded_box({0.04f, 0.015f, 0.13f}, 0.012f, 2),
              at * Xform::translate({sx * 0.29f, 0.655f, 0.f}));
    }
}

void monitor(SceneBuilder& b, const Xform& at, const OfficeMaterials& m) {
    b.add(m.monitor, rounded_box({0.12f, 0.008f, 0.09f}, 0.007f, 2),
          at * Xform::translate({0.f, 0.008f, -0.03f}));
    b.add(m.monitor, rounded_box({0.03f, 0.17f, 0.012f}, 0.01f, 2),
          at * Xform::translate({0.f, 0.18f, -0.06f}));
    const Xform head = at * Xform::translate({0.f, 0.4f, -0.025f}) * Xform::rotate_x(-0.06f);
    b.add(m.monitor, rounded_box({0.3f, 0.18f, 0.018f}, 0.012f, 2), head);
    b.add(m.monitor, rounded_box({0.13f, 0.1f, 0.02f}, 0.015f, 2),
          head * Xform::translate({0.f, -0.01f, -0.025f}));
    b.add(m.screen,
          quad_grid({-0.285f, -0.16f, 0.0185f}, {0.57f, 0.f, 0.f}, {0.f, 0.33f, 0.f}, 1, 1), head);
}

void keyboard(SceneBuilder& b, const Xform& at, const OfficeMaterials& m) {
    b.add(m.keyboard, rounded_box({0.225f, 0.01f, 0.075f}, 0.008f, 2),
          at * Xform::translate({0.f, 0.01f, 0.f}));
    const float u = 0.019f;
    // Key widths (in key units) per row, back row first: a standard 15-unit main block;
    // negative entries are gaps.
    const std::vector<std::vector<float>> rows = {
        {1, -1, 1, 1, 1, 1, -0.5f, 1, 1, 1, 1, -0.5f, 1, 1, 1, 1},
        {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 2},
        {1.5f, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1.5f},
        {1.75f, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 2.25f},
        {2.25f, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 2.75f},
        {1.25f, 1.25f, 1.25f, 6.25f, 1.25f, 1.25f, 1.25f, 1.25f}};
    const float z_back = -0.06f;
    for (size_t r = 0; r < rows.size(); ++r) {
        float x = -0.21f;
        const float z = z_back + u * float(r) + (r > 0 ? 0.006f : 0.f);
        for (float w : rows[r]) {
            if (w < 0.f) {
                x -= w * u;
                continue;
            }
            const float kw = w * u;
            b.add(m.keys, key_cap(kw - 0.002f, u - 0.002f, 0.009f, 0.0025f),
                  at * Xform::translate({x + 0.5f * kw, 0.02f, z + 0.5f * u}));
            x += kw;
        }
    }
    for (int r = 0; r < 5; ++r)
        for (int c = 0; c < 4; ++c)
            b.add(m.keys, key_cap(u - 0.002f, u - 0.002f, 0.009f, 0.0025f),
                  at * Xform::translate({0.1f + u * (float(c) + 0.5f), 0.02f,
                                         z_back + 0.006f + u * (float(r) + 1.5f)}));
    // Mouse on the right.
    b.add(m.keyboard, sphere(1.f, 24, 12),
          at * Xform::translate({0.33f, 0.012f, 0.02f}) * Xform::scale({0.031f, 0.012f, 0.05f}));
}

void desk_lamp(SceneBuilder& b, const Xform& at, const OfficeMaterials& m) {
    b.add(m.lamp, cylinder(0.08f, 0.07f, 0.025f, 40), at);
    const Vec3f base{0.f, 0.035f, 0.f}, elbow{0.f, 0.38f, -0.1f}, head{0.f, 0.46f, 0.22f};
    const Mesh joint = sphere(0.016f, 20, 10);
    for (const Vec3f& p : {base, elbow, head}) b.add(m.chrome, joint, at * Xform::translate(p));
    const Vec3f arm0[2] = {base, elbow}, arm1[2] = {elbow, head};
    const float r[2] = {0.008f, 0.008f};
    b.add(m.lamp, tube(arm0, r, 12, false), at);
    b.add(m.lamp, tube(arm1, r, 12, false), at);
    const std::vector<Vec2f> shade{
        {0.085f, 0.f}, {0.06f, 0.05f}, {0.03f, 0.1f}, {0.018f, 0.125f}, {0.f, 0.13f}};
    b.add(
        m.lamp, lathe(shade, 40),
        at * Xform::translate(head) * Xform::rotate_x(0.5f) * Xform::translate({0.f, -0.12f, 0.f}));
}

void mug(SceneBuilder& b, const Xform& at, const OfficeMaterials& m) {
    const std::vector<Vec2f> p{
        {0.f, 0.f},       {0.04f, 0.f},     {0.04f, 0.f},     {0.041f, 0.05f}, {0.042f, 0.095f},
        {0.042f, 0.095f}, {0.037f, 0.095f}, {0.037f, 0.095f}, {0.036f, 0.01f}, {0.f, 0.01f}};
    b.add(m.mug, lathe(p, 32), at);
    b.add(m.mug, torus(0.024f, 0.006f, 16, 6),
          at * Xform::translate({0.046f, 0.05f, 0.f}) * Xform::rotate_x(0.5f * pi));
}

void papers(SceneBuilder& b, const Xform& at, const OfficeMaterials& m, SceneRng& rng) {
    const int sheets = 2 + int(rng.below(4));
    for (int i = 0; i < sheets; ++i)
        b.add(m.paper, box({-0.105f, 0.f, -0.1485f}, {0.105f, 0.0015f, 0.1485f}),
              at *
                  Xform::translate(
                      {rng.range(-0.01f, 0.01f), 0.0015f * float(i), rng.range(-0.01f, 0.01f)}) *
                  Xform::rotate_y(rng.range(-0.15f, 0.15f)));
    b.add(m.partition, rounded_box({0.115f, 0.008f, 0.155f}, 0.004f, 2),
          at * Xform::translate({0.26f, 0.008f, 0.f}) * Xform::rotate_y(rng.range(-0.3f, 0.3f)));
}

void filing_cabinet(SceneBuilder& b, const Xform& at, const OfficeMaterials& m) {
    b.add(m.cabinet, rounded_block({0.f, 0.f, 0.f}, {0.5f, 1.3f, 0.6f}, 0.012f, 2), at);
    for (int i = 0; i < 4; ++i) {
        const float y0 = 0.03f + 0.315f * float(i), y1 = y0 + 0.3f;
        b.add(m.cabinet, rounded_block({0.02f, y0, 0.6f}, {0.48f, y1, 0.618f}, 0.006f, 2), at);
        const float hy = y1 - 0.06f;
        b.add(
            m.handle,
            bent_tube(
                {{0.17f, hy, 0.618f}, {0.17f, hy, 0.64f}, {0.33f, hy, 0.64f}, {0.33f, hy, 0.618f}},
                0.012f, 0.006f, 8),
            at);
        b.add(m.handle, box({0.22f, hy + 0.03f, 0.618f}, {0.28f, hy + 0.06f, 0.622f}), at);
    }
}

void whiteboard(SceneBuilder& b, const Xform& at, float w, float y0, uint32_t board,
                const OfficeMaterials& m) {
    const float h = 1.2f;
    const Xform base = at * Xform::translate({0.f, y0, 0.f});
    frame(b, base, w, h, m.chrome);
    b.add(board,
          quad_grid({0.05f, 0.05f, 0.015f}, {w - 0.1f, 0.f, 0.f}, {0.f, h - 0.1f, 0.f}, 2, 1),
          base);
    b.add(m.chrome, rounded_block({0.3f, -0.02f, 0.f}, {w - 0.3f, 0.f, 0.08f}, 0.006f, 2), base);
    const Mesh marker = cylinder(0.009f, 0.009f, 0.13f, 16);
    for (int i = 0; i < 3; ++i)
        b.add(i == 0 ? m.keys : m.handle, marker,
              base * Xform::translate({0.5f + 0.2f * float(i), 0.009f, 0.05f}) *
                  Xform::rotate_z(0.5f * pi));
}

void waste_bin(SceneBuilder& b, const Xform& at, const OfficeMaterials& m) {
    const std::vector<Vec2f> p{{0.f, 0.f},      {0.12f, 0.f},     {0.12f, 0.f},
                               {0.15f, 0.35f},  {0.15f, 0.35f},   {0.145f, 0.35f},
                               {0.145f, 0.35f}, {0.115f, 0.012f}, {0.f, 0.012f}};
    b.add(m.chair_plastic, lathe(p, 48), at);
}

void ceiling_panel(SceneBuilder& b, const Vec3f& c, uint32_t frame_mat, uint32_t diffuser) {
    b.add(frame_mat,
          box({c.x - 0.31f, c.y - 0.025f, c.z - 0.31f}, {c.x + 0.31f, c.y, c.z + 0.31f}));
    b.add(diffuser, quad_grid({c.x - 0.28f, c.y - 0.026f, c.z - 0.28f}, {0.56f, 0.f, 0.f},
                              {0.f, 0.f, 0.56f}, 1, 1));
}

}  // namespace rtt::proc
