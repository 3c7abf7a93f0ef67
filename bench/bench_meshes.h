// The meshes of the accelerator benchmarks (bench_accel_rays, bench_kdtree_build): the Stanford
// bunny and the teapot from assets/meshes, each normalized to fit a unit box, and bunny-1m, the
// bunny subdivided twice (1,111,216 triangles, as watertight as the bunny).
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/bounds.h"
#include "scene/mesh_loader.h"

namespace caustic::bench {

inline const std::vector<std::string> kMeshNames = {"bunny", "teapot", "bunny-1m"};

// Scales and translates the mesh so that its bounds fit [-0.5, 0.5]^3, centred at the origin.
inline void normalize(TriangleMesh& mesh) {
    Bounds3 b;
    for (const Vec3& p : mesh.positions) b.extend(p);
    const Vec3 center = b.center();
    const float scale = 1.0f / maxComponent(b.diagonal());
    for (Vec3& p : mesh.positions) p = (p - center) * scale;
}

// 1-to-4 midpoint subdivision. Each edge's midpoint is made once (keyed by its sorted vertex
// pair), so triangles that shared an edge share its midpoint and the mesh stays watertight.
inline TriangleMesh subdivide(const TriangleMesh& in) {
    TriangleMesh out;
    out.positions = in.positions;
    out.triangles.reserve(4 * in.triangles.size());
    std::unordered_map<uint64_t, uint32_t> midpoints;
    midpoints.reserve(2 * in.triangles.size());
    auto midpoint = [&](uint32_t a, uint32_t b) {
        uint64_t key = uint64_t(std::min(a, b)) << 32 | std::max(a, b);
        auto [it, added] = midpoints.try_emplace(key, uint32_t(out.positions.size()));
        if (added) out.positions.push_back(0.5f * (in.positions[a] + in.positions[b]));
        return it->second;
    };
    for (const glm::uvec3& t : in.triangles) {
        uint32_t ab = midpoint(t.x, t.y), bc = midpoint(t.y, t.z), ca = midpoint(t.z, t.x);
        out.triangles.insert(out.triangles.end(),
                             {glm::uvec3(t.x, ab, ca), glm::uvec3(ab, t.y, bc),
                              glm::uvec3(ca, bc, t.z), glm::uvec3(ab, bc, ca)});
    }
    return out;
}

inline TriangleMesh loadMesh(const std::string& name) {
    const std::string file = name == "teapot" ? "teapot.obj" : "stanford-bunny.obj";
    TriangleMesh mesh = loadObj(std::string(CAUSTIC_DEFAULT_ASSETS_DIR) + "/" + file,
                                MeshTransform{}, "/meshes/" + name);
    normalize(mesh);
    if (name == "bunny-1m") mesh = subdivide(subdivide(mesh));
    return mesh;
}

}  // namespace caustic::bench
