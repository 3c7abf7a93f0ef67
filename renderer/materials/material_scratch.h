// Room for the material a textured material becomes at one surface point: one per sample and
// thread, filled by Material::atPoint and read until the next point.
#pragma once

#include <optional>

#include "geometry/geometry.h"
#include "materials/metallic_roughness.h"
#include "textures/texture_store.h"

namespace caustic {

/// What a textured material reads at a point besides the point itself: its texture coordinates
/// with their frame, and the footprint of a pixel there.
struct TexturePoint {
    TextureFrame frame;
    TextureQuery query;
    Vec3 n{0.0f};  ///< The geometric normal.
};

struct MaterialScratch {
    std::optional<MetallicRoughness> metallicRoughness;
};

}  // namespace caustic
