// The `office` scene, an analogue of the paper's OFFICE (Fig. 5a): an open-plan office of
// 12 x 3 x 9 m with four clusters of four desks, lit by 16 omni lights under the ceiling.
#include <cmath>
#include <vector>

#include "builtin_scenes/furniture.h"
#include "builtin_scenes/makers.h"
#include "builtin_scenes/office_furniture.h"

namespace rtt {

using namespace proc;

namespace {

Vec3f apply(const Xform& x, const Vec3f& p) {
    return x.point(p);
}

}  // namespace

OfficeLayout build_office(Scene& scene, SceneBuilder& b) {
    OfficeLayout layout;
    const Vec3f size{12.f, 3.f, 9.f};
    layout.size = size;

    const ShellMaterials shell{
        b.material(phong("carpet", {0.3f, 0.32f, 0.36f})),
        b.material(phong("wall_paint", {0.78f, 0.77f, 0.72f})),
        b.material(phong("ceiling", {0.86f, 0.86f, 0.85f})),
        b.material(phong("skirting", {0.35f, 0.35f, 0.37f}, Vec3f{0.1f}, 30.f))};
    OfficeMaterials m;
    m.desk_top = b.material(phong("desk_laminate", {0.72f, 0.6f, 0.45f}, Vec3f{0.2f}, 50.f));
    m.desk_frame = b.material(phong("desk_frame", {0.6f, 0.62f, 0.65f}, Vec3f{0.5f}, 70.f));
    m.chair_fabric = b.material(phong("chair_fabric", {0.12f, 0.16f, 0.3f}));
    m.chair_plastic = b.material(phong("black_plastic", {0.06f, 0.06f, 0.07f}, Vec3f{0.3f}, 60.f));
    m.chrome = b.material(phong("chrome", {0.4f, 0.4f, 0.42f}, Vec3f{0.8f}, 120.f));
    m.monitor = b.material(phong("monitor_housing", {0.1f, 0.1f, 0.11f}, Vec3f{0.25f}, 50.f));
    m.screen = b.material(phong("screen", {0.08f, 0.12f, 0.22f}, Vec3f{0.6f}, 150.f));
    m.keyboard = b.material(phong("keyboard", {0.75f, 0.75f, 0.73f}, Vec3f{0.2f}, 40.f));
    m.keys = b.material(phong("keys", {0.9f, 0.9f, 0.88f}, Vec3f{0.15f}, 40.f));
    m.paper = b.material(phong("paper", {0.92f, 0.92f, 0.9f}));
    m.mug = b.material(phong("mug", {0.7f, 0.15f, 0.1f}, Vec3f{0.5f}, 100.f));
    m.partition = b.material(phong("partition", {0.35f, 0.5f, 0.45f}));
    m.cabinet = b.material(phong("cabinet", {0.62f, 0.64f, 0.66f}, Vec3f{0.2f}, 40.f));
    m.handle = b.material(phong("handle", {0.25f, 0.25f, 0.27f}, Vec3f{0.6f}, 90.f));
    m.lamp = b.material(phong("lamp", {0.8f, 0.3f, 0.08f}, Vec3f{0.4f}, 60.f));
    const uint32_t board = b.material(phong("whiteboard", {0.9f, 0.9f, 0.9f}, Vec3f{0.4f}, 80.f));
    const uint32_t glass = b.material(phong("window_sky", {0.8f, 0.88f, 0.97f}));
    const uint32_t frame_mat =
        b.material(phong("window_frame", {0.55f, 0.56f, 0.58f}, Vec3f{0.2f}, 40.f));
    const uint32_t diffuser = b.material(phong("light_diffuser", {0.95f, 0.95f, 0.93f}));
    const uint32_t wood = b.material(phong("shelf_wood", {0.5f, 0.36f, 0.22f}, Vec3f{0.15f}, 40.f));
    const uint32_t screen_panel = b.material(phong("screen_panel", {0.45f, 0.48f, 0.52f}));
    std::vector<uint32_t> books;
    const Vec3f book_colours[] = {{0.55f, 0.1f, 0.1f}, {0.1f, 0.25f, 0.5f},   {0.15f, 0.4f, 0.2f},
                                  {0.85f, 0.8f, 0.6f}, {0.12f, 0.12f, 0.12f}, {0.9f, 0.6f, 0.1f}};
    for (const Vec3f& c : book_colours)
        books.push_back(b.material(phong("binder", c, Vec3f{0.1f}, 20.f)));
    const uint32_t ornaments[] = {m.mug, m.chrome};

    room_shell(b, size, shell, 1.f);
    SceneRng rng(1729u);

    // Back wall: four windows.
    const WindowMaterials win{frame_mat, glass, frame_mat};
    for (int i = 0; i < 4; ++i) {
        const float x = 1.0f + 2.9f * float(i);
        window(b, wall_frame(size, 0, x) * Xform::translate({0.f, 0.9f, 0.f}), 1.4f, 1.6f, win);
        // Sill spots 16 cm from the wall; plants there must keep 8 cm clear of the glass.
        layout.shelf_spots.push_back({{x + 0.35f, 0.9f - 0.08f, 0.16f}, 0.08f});
        layout.shelf_spots.push_back({{x + 1.05f, 0.9f - 0.08f, 0.16f}, 0.08f});
    }
    // Left wall: filing cabinets and a bookshelf of binders.
    for (int i = 0; i < 4; ++i) {
        const float along = 2.2f + 0.52f * float(i);
        filing_cabinet(b, wall_frame(size, 1, along), m);
        if (i % 2 == 0)
            layout.shelf_spots.push_back(
                {apply(wall_frame(size, 1, along), {0.25f, 1.3f, 0.3f}), 0.22f});
    }
    bookshelf(b, wall_frame(size, 1, 4.6f), 1.8f, 2.1f, 0.4f, 5, wood, books, ornaments, rng);
    // Right wall: whiteboard and door; front wall: cabinets and a shelf.
    whiteboard(b, wall_frame(size, 2, 3.0f), 2.4f, 0.9f, board, m);
    door(b, wall_frame(size, 2, 6.8f), wood, m.chrome);
    for (int i = 0; i < 3; ++i) {
        const float along = 5.5f + 0.52f * float(i);
        filing_cabinet(b, wall_frame(size, 3, along), m);
        layout.shelf_spots.push_back(
            {apply(wall_frame(size, 3, along), {0.25f, 1.3f, 0.3f}), 0.22f});
    }
    bookshelf(b, wall_frame(size, 3, 8.0f), 1.6f, 2.1f, 0.4f, 5, wood, books, ornaments, rng);

    // Four clusters of four desks, back to back in pairs with a screen between the rows.
    const Vec3f clusters[4] = {
        {3.4f, 0.f, 2.9f}, {8.4f, 0.f, 2.9f}, {3.4f, 0.f, 6.1f}, {8.4f, 0.f, 6.1f}};
    int desk_index = 0;
    for (const Vec3f& c : clusters) {
        b.add(screen_panel, rounded_box({1.62f, 0.22f, 0.02f}, 0.015f, 3),
              Xform::translate(c + Vec3f{0.f, desk_height + 0.22f, 0.f}));
        for (int row = 0; row < 2; ++row)
            for (int col = 0; col < 2; ++col, ++desk_index) {
                const float facing = row == 0 ? 0.f : pi;
                const Vec3f centre =
                    c + Vec3f{col == 0 ? -0.81f : 0.81f, 0.f, row == 0 ? 0.42f : -0.42f};
                const Xform at = Xform::translate(centre) * Xform::rotate_y(facing);
                desk(b, at, m);
                const Xform top = at * Xform::translate({0.f, desk_height, 0.f});
                monitor(b, top * Xform::translate({0.05f, 0.f, -0.17f}), m);
                keyboard(b, top * Xform::translate({0.f, 0.f, 0.15f}), m);
                if (desk_index % 3 == 0)
                    desk_lamp(b,
                              top * Xform::translate({-0.62f, 0.f, -0.22f}) * Xform::rotate_y(0.6f),
                              m);
                else
                    layout.desk_spots.push_back({apply(top, {-0.6f, 0.f, -0.22f}), 0.16f});
                if (desk_index % 2 == 0) mug(b, top * Xform::translate({0.48f, 0.f, 0.05f}), m);
                papers(b,
                       top * Xform::translate({-0.5f, 0.f, 0.12f}) *
                           Xform::rotate_y(rng.range(-0.2f, 0.2f)),
                       m, rng);
                layout.desk_spots.push_back({apply(top, {0.6f, 0.f, -0.25f}), 0.16f});
                // The chair, pulled out and swivelled a little.
                const float swivel = rng.range(-0.5f, 0.5f);
                office_chair(b,
                             at *
                                 Xform::translate({rng.range(-0.15f, 0.15f), 0.f,
                                                   0.62f + rng.range(0.f, 0.2f)}) *
                                 Xform::rotate_y(pi + swivel),
                             m);
            }
        waste_bin(b, Xform::translate(c + Vec3f{1.82f, 0.f, 0.3f}), m);
        // The outer end of each cluster is left free for a planter.
        layout.planter_spots.push_back(c + Vec3f{c.x < 0.5f * size.x ? -1.9f : 1.9f, 0.f, 0.f});
    }
    // Reaches keep 5 cm or more from walls, sills, cabinets, chairs and the planters.
    layout.floor_spots = {
        {{0.75f, 0.f, 0.75f}, 0.5f}, {{11.25f, 0.f, 0.75f}, 0.5f}, {{6.05f, 0.f, 0.75f}, 0.55f},
        {{6.0f, 0.f, 4.5f}, 0.8f},   {{11.35f, 0.f, 6.05f}, 0.6f}, {{11.35f, 0.f, 1.9f}, 0.6f},
        {{0.9f, 0.f, 7.8f}, 0.75f},  {{9.0f, 0.f, 8.45f}, 0.5f},   {{5.9f, 0.f, 7.6f}, 0.7f}};

    // 16 omni lights in a 4 x 4 grid, 0.55 m below ceiling panels.
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const Vec3f p{1.5f + 3.f * float(i), size.y - 0.55f, 1.125f + 2.25f * float(j)};
            ceiling_panel(b, {p.x, size.y, p.z}, frame_mat, diffuser);
            Light l;
            l.kind = LightKind::omni;
            l.position = p;
            l.color = {1.f, 0.97f, 0.92f};
            l.intensity = 1.6f;
            scene.lights.push_back(l);
        }

    Camera cam;
    cam.position = {11.4f, 1.75f, 8.55f};
    cam.target = {5.2f, 0.85f, 2.6f};
    cam.fovy_deg = 60.f;
    scene.camera = cam;
    scene.background = {0.02f, 0.02f, 0.03f};
    return layout;
}

Scene make_office_scene() {
    Scene scene;
    scene.name = "office";
    SceneBuilder b(scene);
    build_office(scene, b);
    b.finish();
    return scene;
}

}  // namespace rtt
