#include "builtin_scenes/room_furniture.h"

#include <cmath>
#include <vector>

namespace rtt::proc {

namespace {

float bump(float t, float centre, float width) {
    const float d = (t - centre) / width;
    return std::exp(-d * d);
}

}  // namespace

Mesh turned_leg(float h, float r, int segments) {
    // Radius along the leg: a taper towards the foot plus Gaussian beads, sampled finely
    // enough (48 rings) to resolve each bead.
    const int n = 48;
    auto radius = [&](float t) {
        float f = 0.68f + 0.32f * t;
        f += 0.35f * bump(t, 0.05f, 0.03f) + 0.45f * bump(t, 0.42f, 0.035f) +
             0.25f * bump(t, 0.5f, 0.02f) + 0.3f * bump(t, 0.78f, 0.03f);
        if (t > 0.84f) f = std::max(f, 1.1f);
        return r * f;
    };
    std::vector<Vec2f> p;
    p.push_back({0.f, 0.f});
    p.push_back({radius(0.f), 0.f});
    for (int k = 0; k <= n; ++k)
        p.push_back({radius(float(k) / float(n)), h * float(k) / float(n)});
    p.push_back({radius(1.f), h});
    p.push_back({0.f, h});
    return lathe(p, segments);
}

void dining_chair(SceneBuilder& b, const Xform& at, uint32_t wood, uint32_t seat) {
    const float sh = 0.45f, lx = 0.19f, lz = 0.19f, leg_h = sh - 0.03f;
    const Mesh leg = turned_leg(leg_h, 0.02f, 20);
    for (float sx : {-1.f, 1.f})
        for (float sz : {-1.f, 1.f})
            b.add(wood, leg, at * Xform::translate({sx * lx, 0.f, sz * lz}));
    // Back posts rake backwards as they rise.
    const float top = 0.98f;
    auto post_z = [&](float y) {
        const float s = (y - leg_h) / (top - leg_h);
        return -lz - 0.06f * s * s;
    };
    for (float sx : {-1.f, 1.f}) {
        std::vector<Vec3f> path;
        std::vector<float> radii;
        for (int k = 0; k <= 8; ++k) {
            const float y = leg_h + (top - leg_h) * float(k) / 8.f;
            path.push_back({sx * lx, y, post_z(y)});
            radii.push_back(0.017f - 0.003f * float(k) / 8.f);
        }
        b.add(wood, tube(path, radii, 14, true), at);
    }
    b.add(seat, rounded_box({0.235f, 0.022f, 0.235f}, 0.015f, 3),
          at * Xform::translate({0.f, sh - 0.008f, 0.f}));
    // Apron under the seat and stretchers between the legs.
    b.add(wood,
          rounded_block({-lx, leg_h - 0.07f, lz - 0.012f}, {lx, leg_h, lz + 0.008f}, 0.005f, 1),
          at);
    for (float sx : {-1.f, 1.f})
        b.add(wood,
              rounded_block({sx * lx - 0.01f, leg_h - 0.07f, -lz}, {sx * lx + 0.01f, leg_h, lz},
                            0.005f, 1),
              at);
    for (float sx : {-1.f, 1.f}) {
        const Vec3f s[2] = {{sx * lx, 0.15f, -lz}, {sx * lx, 0.15f, lz}};
        const float sr[2] = {0.009f, 0.009f};
        b.add(wood, tube(s, sr, 10, false), at);
    }
    {
        const Vec3f s[2] = {{-lx, 0.2f, 0.f}, {lx, 0.2f, 0.f}};
        const float sr[2] = {0.009f, 0.009f};
        b.add(wood, tube(s, sr, 10, false), at);
    }
    // Bowed top and middle rails, spindles between them.
    auto rail = [&](float y, float arch, float r) {
        std::vector<Vec3f> path;
        std::vector<float> radii;
        for (int k = 0; k <= 12; ++k) {
            const float u = -1.f + 2.f * float(k) / 12.f;
            path.push_back({u * lx, y + arch * (1.f - u * u), post_z(y) - 0.03f * (1.f - u * u)});
            radii.push_back(r);
        }
        b.add(wood, tube(path, radii, 16, true), at);
    };
    rail(0.92f, 0.02f, 0.022f);
    rail(0.62f, 0.f, 0.013f);
    for (float x : {-0.105f, -0.035f, 0.035f, 0.105f}) {
        const float bow = 0.03f * (1.f - (x / lx) * (x / lx));
        const Vec3f s[3] = {{x, 0.62f, post_z(0.62f) - bow},
                            {x, 0.77f, post_z(0.77f) - bow},
                            {x, 0.92f, post_z(0.92f) - bow}};
        const float sr[3] = {0.008f, 0.012f, 0.008f};
        b.add(wood, tube(s, sr, 12, false), at);
    }
}

void round_table(SceneBuilder& b, const Xform& at, uint32_t wood) {
    std::vector<Vec2f> top{{0.f, 0.72f}, {0.575f, 0.72f}, {0.575f, 0.72f}};
    for (int k = 0; k <= 10; ++k) {
        const float a = -0.5f * pi + pi * float(k) / 10.f;
        top.push_back({0.575f + 0.0175f * std::cos(a), 0.7375f + 0.0175f * std::sin(a)});
    }
    top.push_back({0.575f, 0.755f});
    top.push_back({0.f, 0.755f});
    b.add(wood, lathe(top, 96), at);
    b.add(wood, turned_leg(0.62f, 0.055f, 40), at * Xform::translate({0.f, 0.1f, 0.f}));
    b.add(wood, cylinder(0.1f, 0.075f, 0.12f, 40), at * Xform::translate({0.f, 0.02f, 0.f}));
    b.add(wood, cylinder(0.1f, 0.1f, 0.03f, 40), at * Xform::translate({0.f, 0.68f, 0.f}));
    std::vector<Vec3f> foot;
    std::vector<float> radii;
    for (int k = 0; k <= 10; ++k) {
        const float s = float(k) / 10.f;
        foot.push_back({0.05f + 0.33f * s, 0.1f - 0.065f * std::sin(0.5f * pi * s), 0.f});
        radii.push_back(0.032f - 0.012f * s);
    }
    const Mesh foot_mesh = tube(foot, radii, 16, true);
    for (int i = 0; i < 4; ++i)
        b.add(wood, foot_mesh, at * Xform::rotate_y(pi * (0.25f + 0.5f * float(i))));
}

void sofa(SceneBuilder& b, const Xform& at, uint32_t fabric, uint32_t cushion, uint32_t pillow,
          uint32_t wood) {
    const float hw = 1.05f;
    b.add(fabric, rounded_block({-hw + 0.15f, 0.1f, -0.42f}, {hw - 0.15f, 0.4f, 0.42f}, 0.03f, 3),
          at);
    b.add(fabric,
          rounded_block({-hw + 0.15f, 0.35f, -0.45f}, {hw - 0.15f, 0.88f, -0.28f}, 0.05f, 4), at);
    for (float sx : {-1.f, 1.f}) {
        const float x0 = sx < 0.f ? -hw : hw - 0.2f;
        b.add(fabric, rounded_block({x0, 0.1f, -0.45f}, {x0 + 0.2f, 0.6f, 0.45f}, 0.07f, 4), at);
        for (float sz : {-1.f, 1.f}) {
            const Xform foot = at * Xform::translate({sx * (hw - 0.08f), 0.f, sz * 0.36f});
            b.add(wood, cylinder(0.018f, 0.026f, 0.1f, 20), foot);
        }
    }
    const float cw = (2.f * hw - 0.4f) / 3.f;
    for (int i = 0; i < 3; ++i) {
        const float x0 = -hw + 0.2f + cw * float(i);
        b.add(
            cushion,
            rounded_block({x0 + 0.005f, 0.4f, -0.27f}, {x0 + cw - 0.005f, 0.55f, 0.44f}, 0.05f, 4),
            at);
        const Xform back =
            at * Xform::translate({x0 + 0.5f * cw, 0.72f, -0.2f}) * Xform::rotate_x(-0.15f);
        b.add(cushion, rounded_box({0.5f * cw - 0.01f, 0.19f, 0.08f}, 0.06f, 4), back);
    }
    for (float sx : {-1.f, 1.f}) {
        const Xform p = at * Xform::translate({sx * (hw - 0.38f), 0.72f, -0.06f}) *
                        Xform::rotate_y(sx * 0.3f) * Xform::rotate_x(-0.35f) *
                        Xform::rotate_z(sx * 0.2f);
        b.add(pillow, rounded_box({0.2f, 0.2f, 0.06f}, 0.055f, 4), p);
    }
}

void floor_lamp(SceneBuilder& b, const Xform& at, uint32_t metal, uint32_t shade) {
    b.add(metal, cylinder(0.16f, 0.13f, 0.03f, 48), at);
    const Vec3f pole[2] = {{0.f, 0.03f, 0.f}, {0.f, 1.45f, 0.f}};
    const float pr[2] = {0.012f, 0.012f};
    b.add(metal, tube(pole, pr, 16, true), at);
    const std::vector<Vec2f> p{{0.2f, 1.35f},   {0.12f, 1.68f},  {0.12f, 1.68f},  {0.114f, 1.68f},
                               {0.114f, 1.68f}, {0.194f, 1.35f}, {0.194f, 1.35f}, {0.2f, 1.35f}};
    b.add(shade, lathe(p, 64), at);
}

void fruit_bowl(SceneBuilder& b, const Xform& at, uint32_t bowl, uint32_t fruit_a,
                uint32_t fruit_b) {
    const std::vector<Vec2f> p{{0.f, 0.f},      {0.05f, 0.f},     {0.05f, 0.f},     {0.1f, 0.025f},
                               {0.135f, 0.06f}, {0.15f, 0.08f},   {0.15f, 0.08f},   {0.142f, 0.08f},
                               {0.142f, 0.08f}, {0.128f, 0.062f}, {0.095f, 0.032f}, {0.f, 0.015f}};
    b.add(bowl, lathe(p, 48), at);
    const Mesh fruit = sphere(0.036f, 32, 16);
    for (int i = 0; i < 5; ++i) {
        const float a = 2.f * pi * float(i) / 5.f;
        b.add(i % 2 ? fruit_a : fruit_b, fruit,
              at * Xform::translate({0.072f * std::cos(a), 0.058f, 0.072f * std::sin(a)}));
    }
    b.add(fruit_a, fruit, at * Xform::translate({0.02f, 0.11f, 0.01f}));
    b.add(fruit_b, fruit, at * Xform::translate({-0.035f, 0.105f, -0.02f}));
}

void sideboard(SceneBuilder& b, const Xform& at, uint32_t wood, uint32_t metal) {
    const float w = 1.6f, d = 0.45f, h = 0.8f;
    b.add(wood, rounded_block({0.02f, 0.12f, 0.f}, {w - 0.02f, h - 0.03f, d - 0.02f}, 0.01f, 2),
          at);
    b.add(wood, rounded_block({0.f, h - 0.03f, 0.f}, {w, h, d}, 0.01f, 3), at);
    for (int i = 0; i < 4; ++i) {
        const float x0 = 0.03f + float(i) * (w - 0.06f) / 4.f, x1 = x0 + (w - 0.06f) / 4.f - 0.006f;
        b.add(wood, rounded_block({x0, 0.14f, d - 0.02f}, {x1, h - 0.05f, d}, 0.006f, 2), at);
        const float hx = i % 2 ? x0 + 0.05f : x1 - 0.05f;
        const Vec3f handle[4] = {
            {hx, 0.38f, d}, {hx, 0.40f, d + 0.025f}, {hx, 0.54f, d + 0.025f}, {hx, 0.56f, d}};
        const float hr[4] = {0.006f, 0.006f, 0.006f, 0.006f};
        b.add(metal, tube(handle, hr, 10, true), at);
    }
    for (float x : {0.08f, w - 0.08f})
        for (float z : {0.06f, d - 0.08f})
            b.add(wood, cylinder(0.018f, 0.025f, 0.12f, 20), at * Xform::translate({x, 0.f, z}));
}

void ceiling_spot(SceneBuilder& b, const Vec3f& at, float ceiling, uint32_t metal) {
    b.add(metal, cylinder(0.075f, 0.075f, 0.01f, 32),
          Xform::translate({at.x, ceiling - 0.01f, at.z}));
    b.add(metal, cylinder(0.06f, 0.06f, 0.12f, 32, true, false),
          Xform::translate({at.x, ceiling - 0.13f, at.z}));
    b.add(metal, torus(0.06f, 0.007f, 32, 8), Xform::translate({at.x, ceiling - 0.13f, at.z}));
}

}  // namespace rtt::proc
