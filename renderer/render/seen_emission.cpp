#include "render/seen_emission.h"

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
    const Vec3 inv = 1.0f / ray.d;
    for (const Bounds3& b : boxes_) {
        // The slab test (Kay & Kajiya 1986). A zero direction component gives +-inf, or NaN when
        // the origin lies on the slab's plane: comparisons with NaN fail and leave the interval
        // as it was, which errs towards a traced ray.
        float tNear = 0.0f, tFar = kInfinity;
        for (int a = 0; a < 3; ++a) {
            float t0 = (b.lo[a] - ray.o[a]) * inv[a], t1 = (b.hi[a] - ray.o[a]) * inv[a];
            if (t0 > t1) std::swap(t0, t1);
            if (t0 > tNear) tNear = t0;
            if (t1 < tFar) tFar = t1;
        }
        if (tNear <= tFar) return true;
    }
    return false;
}

Color SeenEmission::along(const Ray& ray, uint64_t& rays) const {
    if (!mayHitEmitter(ray)) return Color(0.0f);
    ++rays;
    std::optional<Hit> hit = accel_.intersect(ray, kInfinity);
    if (!hit) return Color(0.0f);
    const Material& m = scene_.material(hit->prim);
    if (!m.isEmissive()) return Color(0.0f);
    SurfaceInteraction si = scene_.geometry.interaction(ray, *hit);
    return m.Le(-ray.d, si.n);
}

}  // namespace caustic
