#include "accel/bruteforce.h"

namespace caustic {

std::optional<Hit> BruteForceAccel::intersect(const Ray& ray, float tMax) const {
    const WatertightRay wr(ray);
    std::optional<PrimHit> best;
    uint32_t bestPrim = 0;
    for (uint32_t prim = 0; prim < geometry_.size(); ++prim) {
        if (auto h = geometry_.intersect(prim, wr, tMax)) {
            tMax = h->t;
            best = h;
            bestPrim = prim;
        }
    }
    std::optional<Hit> hit;  // one return of one object, written in place (Geometry::finish)
    if (best) geometry_.finish(bestPrim, ray, *best, hit.emplace());
    return hit;
}

bool BruteForceAccel::occluded(const Ray& ray, float tMax) const {
    const WatertightRay wr(ray);
    for (uint32_t prim = 0; prim < geometry_.size(); ++prim)
        if (geometry_.intersect(prim, wr, tMax)) return true;
    return false;
}

}  // namespace caustic
