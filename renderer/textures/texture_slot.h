// One input of a material read from an image: which image, how it is filtered, and the texture
// transform (glTF's KHR_texture_transform) applied to the coordinates before the lookup.
#pragma once

#include <glm/mat2x2.hpp>

#include "geometry/geometry.h"
#include "textures/texture_store.h"

namespace caustic {

/// dst/dx and dst/dy at a point from how far it moves per pixel (dp/dx, dp/dy) and the texture
/// frame, by least squares on dp = dp/ds ds + dp/dt dt (pbrt-v4 10.1.1,
/// SurfaceInteraction::ComputeDifferentials).
TextureQuery footprintQuery(const TextureFrame& frame, const Vec3& dpdx, const Vec3& dpdy);

struct TextureSlot {
    const TextureStore::Image* image = nullptr;  ///< None: the input is its factor alone.
    /// Whether the scene names a texture here: also when only admitting it, which checks the
    /// image's size but loads no image.
    bool named = false;
    TextureFilter filter = TextureFilter::Anisotropic;
    /// st' = linear st + offset: scale, then rotation, then offset (KHR_texture_transform's
    /// T R S); identity by default.
    glm::mat2 linear{1.0f};
    Vec2 offset{0.0f};

    explicit operator bool() const { return image != nullptr; }
    /// Values of `count` channels from `first` at q, after the transform.
    void lookup(const TextureStore& store, const TextureQuery& q, int first, int count,
                float* out) const {
        TextureQuery t;
        t.st = linear * q.st + offset;
        t.dstdx = linear * q.dstdx;
        t.dstdy = linear * q.dstdy;
        store.lookup(*image, t, filter, first, count, out);
    }
};

}  // namespace caustic
