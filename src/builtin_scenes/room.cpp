// The `room` scene, an analogue of the paper's ROOM (Fig. 6a): a furnished living room of
// 6 x 3 x 5 m with one large planar mirror, lit by 7 spot lights under the ceiling.
#include <cmath>
#include <vector>

#include "builtin_scenes/furniture.h"
#include "builtin_scenes/makers.h"
#include "builtin_scenes/room_furniture.h"

namespace rtt {

using namespace proc;

namespace {

Light spot(Vec3f position, Vec3f target, float intensity) {
    Light l;
    l.kind = LightKind::spot;
    l.position = position;
    l.direction = target - position;
    l.inner_angle_deg = 25.f;
    l.outer_angle_deg = 40.f;
    l.color = {1.f, 0.93f, 0.82f};
    l.intensity = intensity;
    return l;
}

}  // namespace

Scene make_room_scene() {
    Scene scene;
    scene.name = "room";
    scene.background = {0.02f, 0.02f, 0.03f};
    SceneBuilder b(scene);
    const Vec3f size{6.f, 3.f, 5.f};

    const ShellMaterials shell{
        b.material(phong("floor_oak", {0.46f, 0.3f, 0.17f}, Vec3f{0.12f}, 40.f)),
        b.material(phong("wall_paint", {0.74f, 0.7f, 0.62f})),
        b.material(phong("ceiling", {0.85f, 0.85f, 0.83f})),
        b.material(phong("skirting", {0.9f, 0.9f, 0.88f}, Vec3f{0.1f}, 30.f))};
    const uint32_t walnut = b.material(phong("walnut", {0.3f, 0.17f, 0.09f}, Vec3f{0.25f}, 60.f));
    const uint32_t oak = b.material(phong("light_wood", {0.62f, 0.45f, 0.27f}, Vec3f{0.2f}, 50.f));
    const uint32_t seat =
        b.material(phong("seat_leather", {0.45f, 0.12f, 0.08f}, Vec3f{0.2f}, 30.f));
    const uint32_t fabric = b.material(phong("sofa_fabric", {0.2f, 0.3f, 0.42f}));
    const uint32_t cushion = b.material(phong("sofa_cushion", {0.24f, 0.36f, 0.5f}));
    const uint32_t pillow = b.material(phong("pillow", {0.85f, 0.62f, 0.2f}));
    const uint32_t metal =
        b.material(phong("brushed_metal", {0.5f, 0.5f, 0.52f}, Vec3f{0.6f}, 80.f));
    const uint32_t brass =
        b.material(phong("brass", {0.55f, 0.42f, 0.16f}, Vec3f{0.7f, 0.6f, 0.35f}, 90.f));
    const uint32_t shade = b.material(phong("lamp_shade", {0.92f, 0.86f, 0.72f}));
    const uint32_t rug = b.material(phong("rug", {0.55f, 0.22f, 0.18f}));
    const uint32_t ceramic =
        b.material(phong("ceramic_white", {0.85f, 0.85f, 0.82f}, Vec3f{0.5f}, 120.f));
    const uint32_t ceramic_blue =
        b.material(phong("ceramic_blue", {0.12f, 0.25f, 0.6f}, Vec3f{0.5f}, 120.f));
    const uint32_t ceramic_green =
        b.material(phong("ceramic_green", {0.2f, 0.45f, 0.3f}, Vec3f{0.4f}, 100.f));
    const uint32_t orange = b.material(phong("orange", {0.9f, 0.45f, 0.05f}, Vec3f{0.2f}, 40.f));
    const uint32_t apple = b.material(phong("apple", {0.6f, 0.08f, 0.06f}, Vec3f{0.3f}, 60.f));
    const uint32_t glass = b.material(phong("window_sky", {0.8f, 0.88f, 0.97f}));
    const uint32_t white_frame =
        b.material(phong("window_frame", {0.88f, 0.88f, 0.86f}, Vec3f{0.15f}, 40.f));
    const uint32_t curtain_mat = b.material(phong("curtain", {0.7f, 0.6f, 0.42f}));
    const uint32_t canvas_a = b.material(phong("painting_a", {0.2f, 0.4f, 0.55f}));
    const uint32_t canvas_b = b.material(phong("painting_b", {0.75f, 0.55f, 0.25f}));
    const uint32_t mirror = b.material(phong("mirror", Vec3f{0.03f}, Vec3f{0.3f}, 200.f, 0.85f));
    std::vector<uint32_t> books;
    const Vec3f book_colours[] = {{0.55f, 0.1f, 0.1f},  {0.1f, 0.25f, 0.5f},   {0.15f, 0.4f, 0.2f},
                                  {0.8f, 0.7f, 0.45f},  {0.12f, 0.12f, 0.12f}, {0.6f, 0.35f, 0.1f},
                                  {0.85f, 0.85f, 0.8f}, {0.35f, 0.15f, 0.4f}};
    for (const Vec3f& c : book_colours)
        books.push_back(b.material(phong("book", c, Vec3f{0.08f}, 20.f)));
    const uint32_t ornaments[] = {ceramic, ceramic_blue, ceramic_green, brass};

    room_shell(b, size, shell, 0.75f);

    // Back wall (z = 0): a bookshelf and two windows with curtains.
    SceneRng rng(20040607u);
    bookshelf(b, wall_frame(size, 0, 0.35f), 1.7f, 2.2f, 0.34f, 5, walnut, books, ornaments, rng);
    const WindowMaterials win{white_frame, glass, white_frame};
    for (float x : {2.6f, 4.4f})
        window(b, wall_frame(size, 0, x) * Xform::translate({0.f, 0.9f, 0.f}), 1.1f, 1.5f, win);
    for (float x : {2.22f, 3.92f, 5.62f})
        curtain(b, wall_frame(size, 0, x), 0.28f, 2.6f, 0.14f, curtain_mat);

    // Left wall (x = 0): the mirror above a sideboard. The mirror is one axis-aligned quad
    // (exactly planar), set 3 cm in front of the wall inside a frame.
    const float mz0 = 2.2f, mz1 = 4.2f, my0 = 1.0f, my1 = 2.45f;
    b.add(mirror, quad_grid({0.03f, my0, mz0}, {0.f, my1 - my0, 0.f}, {0.f, 0.f, mz1 - mz0}, 1, 1));
    frame(b, wall_frame(size, 1, size.z - mz1 - 0.06f) * Xform::translate({0.f, my0 - 0.06f, 0.f}),
          mz1 - mz0 + 0.12f, my1 - my0 + 0.12f, brass);
    sideboard(b, wall_frame(size, 1, size.z - 4.05f), walnut, brass);
    b.add(ceramic_blue, vase(0.42f, 2, 40), Xform::translate({0.22f, 0.8f, 2.75f}));
    b.add(ceramic, vase(0.26f, 0, 40), Xform::translate({0.25f, 0.8f, 3.6f}));
    b.add(brass, sphere(0.08f, 40, 20), Xform::translate({0.22f, 0.88f, 3.2f}));

    // Right wall (x = 6): the sofa, two pictures above it.
    sofa(b, Xform::translate({size.x - 0.47f, 0.f, 2.45f}) * Xform::rotate_y(-0.5f * pi), fabric,
         cushion, pillow, walnut);
    picture(b, wall_frame(size, 2, 1.45f) * Xform::translate({0.f, 1.35f, 0.f}), 0.9f, 0.7f, walnut,
            canvas_a);
    picture(b, wall_frame(size, 2, 2.6f) * Xform::translate({0.f, 1.45f, 0.f}), 0.6f, 0.5f, walnut,
            canvas_b);

    // Front wall (z = 5): the door and a small bookshelf.
    door(b, wall_frame(size, 3, 4.3f), oak, brass);
    bookshelf(b, wall_frame(size, 3, 2.2f), 1.0f, 1.2f, 0.3f, 3, oak, books, ornaments, rng);

    // Dining table with four chairs on a rug, fruit and a vase on the table.
    const Vec3f table{2.9f, 0.f, 2.55f};
    b.add(rug, box({1.5f, 0.f, 1.2f}, {4.3f, 0.012f, 3.9f}));
    round_table(b, Xform::translate(table), oak);
    for (int i = 0; i < 4; ++i) {
        const float a = 0.5f * pi * float(i) + 0.15f;
        const Vec3f offset{0.72f * std::sin(a), 0.012f, 0.72f * std::cos(a)};
        // Each chair faces the table centre.
        dining_chair(b, Xform::translate(table + offset) * Xform::rotate_y(a + pi), oak, seat);
    }
    fruit_bowl(b, Xform::translate(table + Vec3f{0.12f, 0.755f, 0.1f}), ceramic, orange, apple);
    b.add(ceramic_green, vase(0.3f, 3, 48),
          Xform::translate(table + Vec3f{-0.22f, 0.755f, -0.15f}));
    b.add(ceramic, sphere(0.05f, 32, 16), Xform::translate(table + Vec3f{-0.05f, 0.805f, -0.3f}));

    // Floor lamp by the windows, a tall floor vase, spheres on the floor in a corner.
    floor_lamp(b, Xform::translate({5.62f, 0.f, 0.45f}), brass, shade);
    b.add(ceramic_blue, vase(0.7f, 0, 48), Xform::translate({0.3f, 0.f, 1.9f}));
    for (int i = 0; i < 3; ++i)
        b.add(i == 1 ? brass : ceramic, sphere(0.09f + 0.03f * float(i), 40, 20),
              Xform::translate(
                  {0.35f + 0.3f * float(i), 0.09f + 0.03f * float(i), 4.6f - 0.05f * float(i)}));

    // Seven ceiling spots, each light 7 cm below its fitting.
    const float ceiling = size.y;
    const Vec3f spots[7][2] = {
        {{2.9f, 2.8f, 2.55f}, {2.9f, 0.75f, 2.55f}},  // table
        {{4.9f, 2.8f, 2.45f}, {5.6f, 0.5f, 2.45f}},   // sofa
        {{1.2f, 2.8f, 0.9f}, {1.2f, 1.0f, 0.2f}},     // bookshelf
        {{4.0f, 2.8f, 0.9f}, {4.0f, 0.6f, 0.3f}},     // windows
        {{1.0f, 2.8f, 3.2f}, {0.2f, 1.0f, 3.2f}},     // sideboard and mirror
        {{1.8f, 2.8f, 4.3f}, {1.3f, 0.f, 4.7f}},      // door corner
        {{4.6f, 2.8f, 4.2f}, {4.4f, 0.f, 3.6f}},      // near the viewer
    };
    for (const auto& s : spots) {
        ceiling_spot(b, s[0], ceiling, metal);
        scene.lights.push_back(spot(s[0], s[1], 6.f));
    }
    b.finish();

    Camera cam;
    cam.position = {5.45f, 1.6f, 4.7f};
    cam.target = {2.2f, 1.05f, 1.3f};
    cam.fovy_deg = 60.f;
    scene.camera = cam;
    return scene;
}

}  // namespace rtt
