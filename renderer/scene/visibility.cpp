#include "scene/visibility.h"

#include <bit>

#include "core/rng.h"

namespace caustic {

namespace {

// A uniform number in [0, 1) fixed by the ray (pbrt-v4's HashFloat(ray.o, ray.d)).
float hashRay(const Ray& ray) {
    uint64_t h = 0;
    const float values[6] = {ray.o.x, ray.o.y, ray.o.z, ray.d.x, ray.d.y, ray.d.z};
    for (float v : values) h = hashCombine(h, std::bit_cast<uint32_t>(v));
    return float(mixBits(h) >> 40) * 0x1p-24f;
}

}  // namespace

std::optional<Hit> intersectSolid(const Scene& scene, const Accelerator& accel, const Ray& ray,
                                  float tMax, uint64_t& rays) {
    Ray r = ray;
    float travelled = 0.0f;  // along ray, in units of |d|, to r's origin
    const float dd = glm::dot(ray.d, ray.d);
    for (int layer = 0;; ++layer) {
        std::optional<Hit> hit = accel.intersect(r, tMax - travelled);
        if (!hit) return std::nullopt;
        const Material& m = *scene.materials[scene.geometry.material(hit->prim)];
        if (!m.hasAlpha() || layer == kMaxCutOutLayers) {
            hit->t += travelled;
            return hit;
        }
        const SurfaceInteraction si = scene.geometry.interaction(r, *hit);
        TexturePoint point;
        point.frame = scene.geometry.textureFrame(si);
        point.query.st = point.frame.st;
        point.n = si.n;
        if (!m.cutOut(point, hashRay(r))) {
            hit->t += travelled;
            return hit;
        }
        // On from just past the surface.
        r.o = offsetRayOrigin(si.p, si.pError, si.n, r.d);
        travelled = glm::dot(r.o - ray.o, ray.d) / dd;
        ++rays;
        if (!(travelled < tMax)) return std::nullopt;
    }
}

}  // namespace caustic
