// Internal: potted plants for the `plants` scene, grown procedurally from a SceneRng, each
// standing on the local origin. Their leaves are small (a few centimetres: a few pixels at
// 640x480 from across the office), which is what makes the scene hard for RTT.
#pragma once

#include <span>

#include "builtin_scenes/procedural.h"

namespace rtt::proc {

struct PlantMaterials {
    uint32_t pot, pot_alt, soil, stem;
    std::span<const uint32_t> leaves;  ///< Leaf greens, picked per leaf.
};

/// A weeping-fig bush about `height` tall in a pot: trunk, spiralling branches, twigs and
/// thousands of leaves of 4 triangles, all within `reach` of its axis.
void ficus(SceneBuilder& b, const Xform& at, float height, float reach, const PlantMaterials& m,
           SceneRng& rng);

/// The crown of a fig without a pot, its trunk rising from `base` (reach is measured from the
/// local y axis): for planters.
void fig_crown(SceneBuilder& b, const Xform& at, const Vec3f& base, float height, float reach,
               const PlantMaterials& m, SceneRng& rng);

/// A dracaena: a few bare canes of different heights, each crowned by arching strap leaves
/// that stay within `reach` of its axis.
void dracaena(SceneBuilder& b, const Xform& at, float height, float reach, const PlantMaterials& m,
              SceneRng& rng);

/// A small plant (pilea-like): round leaves on thin stalks in a small pot, within `reach` of
/// its axis.
void pilea(SceneBuilder& b, const Xform& at, float reach, const PlantMaterials& m, SceneRng& rng);

/// A small topiary: a clipped ball of tiny leaves on a short stem in a small pot, `height` tall.
void topiary(SceneBuilder& b, const Xform& at, float height, const PlantMaterials& m,
             SceneRng& rng);

/// Flower pot of rim radius r and height h with soil 12% below the rim.
void flower_pot(SceneBuilder& b, const Xform& at, float r, float h, uint32_t pot, uint32_t soil);

}  // namespace rtt::proc
