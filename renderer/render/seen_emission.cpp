#include "render/seen_emission.h"

#include "scene/visibility.h"

namespace caustic {

SeenEmission::SeenEmission(const Scene& scene, const Accelerator& accel)
    : scene_(scene), accel_(accel) {
    const std::vector<uint32_t>& prims = scene.emitterPrims;
    if (prims.empty()) return;
    Bounds3 all;
    for (uint32_t prim : prims) {
        Bounds3 b = scene.geometry.bounds(prim);
        // Grown a little past the rounding of the box test, so that it never misses a hit the
        // accelerator finds (a lamp's box is flat).
        Vec3 pad(1e-4f * glm::length(b.diagonal()) + 1e-6f * maxComponent(glm::abs(b.hi)) + 1e-30f);
        b.lo -= pad;
        b.hi += pad;
        if (prims.size() <= kMaxBoxes) boxes_.push_back(b);
        all.extend(b);
    }
    if (boxes_.empty()) boxes_.push_back(all);
    for (const Bounds3& b : boxes_) outlines_.push_back(outline(b, scene.camera));
}

SeenEmission::Rect SeenEmission::outline(const Bounds3& box, const Camera& camera) {
    // A box wholly in front of the camera projects inside its corners' hull; one that is not
    // may be seen anywhere.
    Rect r{kInfinity, kInfinity, -kInfinity, -kInfinity};
    for (int c = 0; c < 8; ++c) {
        Vec3 p((c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y,
               (c & 4) ? box.hi.z : box.lo.z);
        float x, y;
        if (!camera.raster(p, x, y)) return Rect{-kInfinity, -kInfinity, kInfinity, kInfinity};
        r = Rect{std::min(r.x0, x), std::min(r.y0, y), std::max(r.x1, x), std::max(r.y1, y)};
    }
    return Rect{r.x0 - 1.0f, r.y0 - 1.0f, r.x1 + 1.0f, r.y1 + 1.0f};
}

bool SeenEmission::mayHitEmitter(const Ray& ray) const {
    const Vec3 invDir = 1.0f / ray.d;
    const uint32_t negative = directionSignBits(ray.d);
    for (const Bounds3& b : boxes_) {
        float t0 = 0.0f, t1 = kInfinity;
        if (clipToBox(b, ray.o, invDir, negative, t0, t1)) return true;
    }
    return false;
}

Color SeenEmission::along(const Ray& ray, uint64_t& rays, float footprintScale) const {
    if (!mayHitEmitter(ray)) return Color(0.0f);
    ++rays;
    std::optional<Hit> hit = intersectVisible(scene_, accel_, ray, kInfinity, rays);
    if (!hit) return Color(0.0f);
    const Material& m = scene_.material(hit->prim);
    if (!m.isEmissive()) return Color(0.0f);
    SurfaceInteraction si = scene_.geometry.interaction(ray, *hit);
    if (!m.isTextured()) return m.Le(-ray.d, si.n);
    MaterialScratch scratch;
    return scene_.shade(si, scratch, footprintScale).Le(-ray.d, si.n);
}

}  // namespace caustic
