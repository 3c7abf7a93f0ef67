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
    fuzz::checkMesh(mesh);
    return 0;
}
