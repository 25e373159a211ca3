// The `plants` scene, an analogue of the paper's PLANTS (Fig. 6b): the office scene filled
// with potted plants whose many small leaves break up image-space coherence. Same lights and
// camera as the office.
#include <vector>

#include "builtin_scenes/makers.h"
#include "builtin_scenes/plant_models.h"

namespace rtt {

using namespace proc;

Scene make_plants_scene() {
    Scene scene;
    scene.name = "plants";
    SceneBuilder b(scene);
    const OfficeLayout layout = build_office(scene, b);

    const uint32_t leaves[] = {
        b.material(phong("leaf_dark", {0.07f, 0.22f, 0.05f}, Vec3f{0.15f}, 40.f)),
        b.material(phong("leaf_mid", {0.13f, 0.33f, 0.07f}, Vec3f{0.15f}, 40.f)),
        b.material(phong("leaf_light", {0.25f, 0.45f, 0.1f}, Vec3f{0.1f}, 30.f))};
    PlantMaterials m;
    m.pot = b.material(phong("terracotta", {0.62f, 0.3f, 0.17f}));
    m.pot_alt = b.material(phong("glazed_pot", {0.85f, 0.84f, 0.8f}, Vec3f{0.4f}, 90.f));
    m.soil = b.material(phong("soil", {0.16f, 0.11f, 0.07f}));
    m.stem = b.material(phong("stem", {0.3f, 0.22f, 0.12f}));
    m.leaves = leaves;

    // One generator per plant, seeded by its index, so each plant is fixed regardless of the
    // others. Floor: figs and dracaenas; planters: rows of fig bushes; desks: topiaries; sills
    // and cabinets: pileas.
    uint32_t seed = 4242u;
    for (size_t i = 0; i < layout.floor_spots.size(); ++i) {
        const PlantSpot& s = layout.floor_spots[i];
        SceneRng rng(seed++);
        const Xform at = Xform::translate(s.position) * Xform::rotate_y(rng.range(0.f, 2.f * pi));
        if (i % 3 == 2)
            dracaena(b, at, rng.range(1.5f, 1.9f), s.reach, m, rng);
        else
            ficus(b, at, rng.range(1.4f, 1.9f), s.reach, m, rng);
    }
    const uint32_t planter = b.material(phong("planter", {0.3f, 0.3f, 0.32f}, Vec3f{0.2f}, 40.f));
    for (const Vec3f& p : layout.planter_spots) {
        const float h = 0.45f;
        b.add(planter, rounded_box({0.2f, 0.5f * h, 0.75f}, 0.02f, 2),
              Xform::translate(p + Vec3f{0.f, 0.5f * h, 0.f}));
        b.add(m.soil, quad_grid(p + Vec3f{-0.18f, h + 0.001f, -0.73f}, {0.f, 0.f, 1.46f},
                                {0.36f, 0.f, 0.f}, 4, 1));
        for (int k = 0; k < 3; ++k) {
            SceneRng rng(seed++);
            const Xform at = Xform::translate(p + Vec3f{0.f, 0.f, 0.5f * float(k - 1)}) *
                             Xform::rotate_y(rng.range(0.f, 2.f * pi));
            fig_crown(b, at, {0.f, h, 0.f}, rng.range(0.8f, 1.0f), 0.4f, m, rng);
        }
    }
    for (const PlantSpot& s : layout.desk_spots) {
        SceneRng rng(seed++);
        topiary(b, Xform::translate(s.position) * Xform::rotate_y(rng.range(0.f, 2.f * pi)),
                rng.range(0.3f, 0.42f), m, rng);
    }
    for (const PlantSpot& s : layout.shelf_spots) {
        SceneRng rng(seed++);
        pilea(b, Xform::translate(s.position) * Xform::rotate_y(rng.range(0.f, 2.f * pi)), s.reach,
              m, rng);
    }
    b.finish();
    return scene;
}

}  // namespace rtt
