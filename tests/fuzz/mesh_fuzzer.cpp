// libFuzzer target: a mesh file as an upload sends it, through parseMeshBytes as OBJ and as glTF
// binary, then what the loader promises (fuzz::checkMesh). Neither loader may open a file: an
// mtllib, or a buffer or image uri (/dev/zero would hang: a timeout is a finding).
//
// Mutated .glb bytes rarely keep the header's and chunks' lengths right, which stops them at the
// container check; so each input is also read as the text of a JSON chunk up to its first NUL
// byte, then the BIN chunk, wrapped in a correct header (the seeds "*.chunks" are written so).
#include <string>
#include <string_view>

#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "scene/mesh_file.h"
#include "support/glb_writer.h"

using namespace caustic;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::useOneThread();
    return 0;
}

namespace {

void loadAndCheck(std::string_view bytes, MeshFormat format) {
    TriangleMesh mesh;
    try {
        mesh = parseMeshBytes(bytes, format, MeshTransform{}, "fuzz", "/shapes/0/asset");
    } catch (const InputError&) {
        return;
    }
    fuzz::checkMesh(mesh);
    MeshBounds b = boundsOf(mesh);
    if (!isFinite(b.min) || !isFinite(b.max))
        fuzz::fail("the bounds of a loaded mesh are not finite");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string bytes = fuzz::text(data, size);
    loadAndCheck(bytes, MeshFormat::Obj);
    loadAndCheck(bytes, MeshFormat::Glb);
    const size_t nul = bytes.find('\0');
    if (nul != std::string::npos)
        loadAndCheck(testing::glbFromChunks(bytes.substr(0, nul), bytes.substr(nul + 1)),
                     MeshFormat::Glb);
    return 0;
}
