// Internal: the furniture of the `office` scene, each in a local frame standing on the floor
// (or on a desk top) at the origin; "front" is +z (where the user sits or stands).
#pragma once

#include "builtin_scenes/procedural.h"

namespace rtt::proc {

struct OfficeMaterials {
    uint32_t desk_top, desk_frame, chair_fabric, chair_plastic, chrome, monitor, screen, keyboard,
        keys, paper, mug, partition, cabinet, handle, lamp;
};

/// Desk 1.6 x 0.8 m, top surface at 0.74 m, drawer pedestal on the right; the user sits at +z.
inline constexpr float desk_height = 0.74f;
void desk(SceneBuilder& b, const Xform& at, const OfficeMaterials& m);

/// Swivel chair: five-star base on casters, gas lift, contoured seat and curved backrest
/// (towards -z), armrests.
void office_chair(SceneBuilder& b, const Xform& at, const OfficeMaterials& m);

/// Monitor on a stand (screen facing +z), standing on the origin.
void monitor(SceneBuilder& b, const Xform& at, const OfficeMaterials& m);

/// Keyboard with about a hundred individual keys and a mouse on its right, lying on the origin.
void keyboard(SceneBuilder& b, const Xform& at, const OfficeMaterials& m);

/// Desk lamp with a jointed arm, standing on the origin.
void desk_lamp(SceneBuilder& b, const Xform& at, const OfficeMaterials& m);

/// Coffee mug with handle, standing on the origin.
void mug(SceneBuilder& b, const Xform& at, const OfficeMaterials& m);

/// A stack of paper sheets and a closed folder, lying on the origin.
void papers(SceneBuilder& b, const Xform& at, const OfficeMaterials& m, SceneRng& rng);

/// Filing cabinet against a wall: x in [0, 0.5], back at z = 0, 1.3 m tall, four drawers.
void filing_cabinet(SceneBuilder& b, const Xform& at, const OfficeMaterials& m);

/// Whiteboard on a wall (local wall frame): x in [0, w], lower edge at y0, with marker tray.
void whiteboard(SceneBuilder& b, const Xform& at, float w, float y0, uint32_t board,
                const OfficeMaterials& m);

/// Waste bin (open lathe), standing on the origin.
void waste_bin(SceneBuilder& b, const Xform& at, const OfficeMaterials& m);

/// Ceiling light panel 0.6 x 0.6 m centred at (x, ceiling, z).
void ceiling_panel(SceneBuilder& b, const Vec3f& centre, uint32_t frame, uint32_t diffuser);

}  // namespace rtt::proc
