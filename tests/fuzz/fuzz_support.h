// What the fuzz targets share (tests/fuzz/README.md): one OpenMP thread, input bytes as text, a
// check that the kd-tree agrees with brute force, and a way to report a broken invariant.
#pragma once

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "accel/bruteforce.h"
#include "accel/kdtree/kdtree.h"
#include "scene/mesh_loader.h"
#include "support/accel_agreement.h"

namespace caustic::fuzz {

/// libFuzzer runs one input at a time; a parallel region per input would mostly start threads.
inline void useOneThread() {
    omp_set_num_threads(1);
}

inline std::string text(const uint8_t* data, size_t size) {
    return std::string(reinterpret_cast<const char*>(data), size);
}

/// Ends the run as a finding: libFuzzer saves the input that got here.
[[noreturn]] inline void fail(const std::string& what) {
    std::fprintf(stderr, "fuzz invariant broken: %s\n", what.c_str());
    std::abort();
}

/// Rays from `eye` along the six axis directions (zero direction components) and at the centers
/// of the first `limit` primitives; none with a non-finite origin or direction.
inline std::vector<Ray> raysFrom(const Vec3& eye, const Geometry& g, uint32_t limit) {
    std::vector<Ray> rays;
    if (!isFinite(eye)) return rays;
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {-1.0f, 1.0f}) {
            Vec3 d(0.0f);
            d[axis] = sign;
            rays.push_back(Ray{eye, d});
        }
    for (uint32_t prim = 0; prim < std::min(g.size(), limit); ++prim) {
        Vec3 d = g.bounds(prim).center() - eye;
        if (isFinite(d) && glm::dot(d, d) > 0.0f && isFinite(glm::normalize(d)))
            rays.push_back(Ray{eye, glm::normalize(d)});
    }
    return rays;
}

/// Coordinates up to this magnitude are compared. The README promises scenes of 1e-4 to 1e4 units
/// 1e5 from the origin; far beyond, the float primitive tests are no reference (a ray whose origin
/// is 1e38 away sees a small triangle collapse to a point and "hits" it), and the kd-tree, which
/// culls by box first, then rightly disagrees.
inline constexpr float kComparedMagnitude = 1e6f;

/// Builds the kd-tree over `g` and traces `rays`; fails unless it agrees with brute force where
/// the scene and the ray's origin lie within kComparedMagnitude.
inline void checkKdTree(const Geometry& g, const std::vector<Ray>& rays) {
    KdTreeAccel kdtree(g);
    BruteForceAccel brute(g);
    Bounds3 b = g.bounds();
    bool compared =
        b.empty() || maxComponent(glm::max(glm::abs(b.lo), glm::abs(b.hi))) <= kComparedMagnitude;
    std::vector<Ray> near;
    for (const Ray& ray : rays) {
        if (compared && maxComponent(glm::abs(ray.o)) <= kComparedMagnitude) {
            near.push_back(ray);
        } else {
            kdtree.intersect(ray, kInfinity);
            kdtree.occluded(ray, kInfinity);
        }
    }
    if (auto disagreement = testing::firstDisagreement(kdtree, brute, near))
        fail("kd-tree and brute force disagree: " + *disagreement);
}

/// What a mesh loader promises the geometry: indices in range and finite vertices; then the
/// kd-tree over the mesh against brute force, on rays from outside the mesh's box and from its
/// center.
inline void checkMesh(const TriangleMesh& mesh) {
    for (const glm::uvec3& t : mesh.triangles)
        if (std::max({t.x, t.y, t.z}) >= mesh.positions.size())
            fail("a face index out of range passed the loader");
    for (const Vec3& p : mesh.positions)
        if (!isFinite(p)) fail("a non-finite vertex passed the loader");

    Geometry g;
    g.addTriangles(mesh.positions, mesh.triangles, 0);
    Bounds3 b = g.bounds();
    std::vector<Ray> rays = raysFrom(b.hi + 0.5f * b.diagonal(), g, 32);
    std::vector<Ray> inside = raysFrom(b.center(), g, 32);
    rays.insert(rays.end(), inside.begin(), inside.end());
    checkKdTree(g, rays);
}

}  // namespace caustic::fuzz
