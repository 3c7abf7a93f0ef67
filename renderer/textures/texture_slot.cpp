#include "textures/texture_slot.h"

#include <algorithm>

namespace caustic {

TextureQuery footprintQuery(const TextureFrame& frame, const Vec3& dpdx, const Vec3& dpdy) {
    TextureQuery q;
    q.st = frame.st;
    const float a00 = glm::dot(frame.dpds, frame.dpds), a01 = glm::dot(frame.dpds, frame.dpdt),
                a11 = glm::dot(frame.dpdt, frame.dpdt);
    float inverse = 1.0f / differenceOfProducts(a00, a11, a01, a01);
    if (!std::isfinite(inverse)) inverse = 0.0f;
    auto solve = [&](const Vec3& dp) {
        const float b0 = glm::dot(frame.dpds, dp), b1 = glm::dot(frame.dpdt, dp);
        const Vec2 d(differenceOfProducts(a11, b0, a01, b1) * inverse,
                     differenceOfProducts(a00, b1, a01, b0) * inverse);
        // Clamped as pbrt-v4 does: a grazing footprint must not ask for an infinite filter.
        return glm::clamp(d, Vec2(-1e8f), Vec2(1e8f));
    };
    q.dstdx = solve(dpdx);
    q.dstdy = solve(dpdy);
    return q;
}

}  // namespace caustic
