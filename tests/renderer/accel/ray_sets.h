// Ray sets for checking accelerators against each other: random, axis-aligned, aimed exactly at
// vertices and edges, and starting on surfaces.
#pragma once

#include <vector>

#include "accel/accelerator.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "geometry/geometry.h"

namespace caustic::testing {

/// Random origins in the scene's bounds grown by half its size, uniform directions.
inline void addRandomRays(const Bounds3& b, size_t n, Rng& rng, std::vector<Ray>& rays) {
    Vec3 lo = b.lo - 0.5f * b.diagonal(), size = 2.0f * b.diagonal();
    for (size_t i = 0; i < n; ++i) {
        Vec3 o = lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * size;
        rays.push_back(Ray{o, sampleUniformSphere(rng.uniform2())});
    }
}

/// Directions with one or two zero components: parallel to split planes and box faces.
inline void addAxisAlignedRays(const Bounds3& b, size_t n, Rng& rng, std::vector<Ray>& rays) {
    Vec3 lo = b.lo - 0.1f * b.diagonal(), size = 1.2f * b.diagonal();
    for (size_t i = 0; i < n; ++i) {
        Vec3 o = lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * size;
        Vec3 d = sampleUniformSphere(rng.uniform2());
        int zeroes = 1 + int(rng.uniform() * 2.0f);  // one or two components zeroed
        int first = int(rng.uniform() * 3.0f) % 3;
        for (int k = 0; k < zeroes; ++k) d[(first + k) % 3] = 0.0f;
        if (glm::length(d) == 0.0f) d[first] = 1.0f;
        rays.push_back(Ray{o, glm::normalize(d)});
    }
}

/// Rays aimed exactly at triangle and quad corners and at points on their edges.
inline void addVertexAndEdgeRays(const Geometry& g, const Bounds3& b, size_t n, Rng& rng,
                                 std::vector<Ray>& rays) {
    std::vector<Vec3> targets;
    for (const Vec3& p : g.positions()) targets.push_back(p);
    for (const Quad& q : g.quads())
        for (const Vec3& v : q.v) targets.push_back(v);
    if (targets.empty()) return;
    Vec3 lo = b.lo - 0.5f * b.diagonal(), size = 2.0f * b.diagonal();
    for (size_t i = 0; i < n; ++i) {
        Vec3 a = targets[size_t(rng.uniform() * float(targets.size())) % targets.size()];
        Vec3 c = targets[size_t(rng.uniform() * float(targets.size())) % targets.size()];
        // Half the rays aim at a vertex, half at a point between two vertices (often an edge).
        Vec3 target = i % 2 == 0 ? a : a + 0.5f * (c - a);
        Vec3 o = lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * size;
        if (o == target) continue;
        rays.push_back(Ray{o, glm::normalize(target - o)});
    }
}

/// n rays leaving surface points that the rays already in `rays` hit (cycling through them, each
/// time in a new random direction), offset as the integrators offset them.
inline void addSurfaceRays(const Geometry& g, const Accelerator& accel, size_t n, Rng& rng,
                           std::vector<Ray>& rays) {
    std::vector<SurfaceInteraction> hits;
    for (const Ray& ray : rays)
        if (auto hit = accel.intersect(ray, kInfinity)) hits.push_back(g.interaction(ray, *hit));
    for (size_t i = 0; i < n && !hits.empty(); ++i) {
        const SurfaceInteraction& si = hits[i % hits.size()];
        Vec3 w = sampleUniformSphere(rng.uniform2());
        rays.push_back(Ray{offsetRayOrigin(si.p, si.pError, si.n, w), w});
    }
}

}  // namespace caustic::testing
