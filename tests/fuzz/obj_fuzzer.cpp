// libFuzzer target: OBJ text through the mesh loader (parseObj, what loadObj runs on a file's
// bytes), then the kd-tree over the mesh checked against brute force. The loader must never open
// another file (an `mtllib` naming /dev/zero would hang: a timeout is a finding).
#include <sstream>

#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "scene/mesh_loader.h"

using namespace caustic;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::useOneThread();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::istringstream in(fuzz::text(data, size));
    TriangleMesh mesh;
    try {
        mesh = parseObj(in, "fuzz.obj", MeshTransform{}, "/shapes/0/file");
    } catch (const InputError&) {
        return 0;
    }
    // What the loader promises the geometry.
    for (const glm::uvec3& t : mesh.triangles)
        if (std::max({t.x, t.y, t.z}) >= mesh.positions.size())
            fuzz::fail("a face index out of range passed the loader");
    for (const Vec3& p : mesh.positions)
        if (!isFinite(p)) fuzz::fail("a non-finite vertex passed the loader");

    Geometry g;
    g.addTriangles(mesh.positions, mesh.triangles, 0);
    Bounds3 b = g.bounds();
    // From outside the mesh's box, and from its center.
    std::vector<Ray> rays = fuzz::raysFrom(b.hi + 0.5f * b.diagonal(), g, 32);
    std::vector<Ray> inside = fuzz::raysFrom(b.center(), g, 32);
    rays.insert(rays.end(), inside.begin(), inside.end());
    fuzz::checkKdTree(g, rays);
    return 0;
}
