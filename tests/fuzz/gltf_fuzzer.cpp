// libFuzzer target: a glTF model as a scene (a .glb, or a .zip of a .gltf when the input starts as
// a zip does), the way admission and a worker take a job's model
// (gltf/scene_document.h): imported counting only, its overrides applied, the scene loaded for
// the memory estimate; and, for a file without images (decoding them would write prepared
// textures on every input), imported in full and loaded as a worker renders it, every embedded
// mesh then checked (fuzz::checkMesh). As mesh_fuzzer, each input is also read as the text of a
// JSON chunk up to its first NUL byte, then the BIN chunk, wrapped in a correct header.
#include <string>
#include <string_view>

#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "gltf/gltf_scene.h"
#include "gltf/gltf_zip.h"
#include "scene/scene.h"
#include "support/glb_writer.h"

using namespace caustic;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::useOneThread();
    return 0;
}

namespace {

void importAndLoad(std::string_view bytes, MeshFormat format, bool countOnly) {
    const std::string name = "fuzz.glb", path = "/gltf/asset";
    const MeshErrors errors{name, path};
    GltfImportOptions options;
    options.countOnly = countOnly;
    options.maxPixels = int64_t(4096) * 4096;
    GltfScene imported;
    Json doc;
    try {
        imported = importGltf(loadGltfUpload(bytes, format, errors), options, errors);
        if (!countOnly && !imported.embedded->images.empty()) return;
        doc = gltfSceneWithOverrides(imported, Json::object(), "", options);
    } catch (const InputError&) {
        return;
    }
    if (!countOnly)
        for (const EmbeddedData::Mesh& m : imported.embedded->meshes) fuzz::checkMesh(m.mesh);
    SceneOptions sceneOptions;
    sceneOptions.embedded = imported.embedded;
    sceneOptions.countMeshesOnly = countOnly;
    sceneOptions.maxResolution = 4096;
    sceneOptions.maxPixels = int64_t(4096) * 4096;
    try {
        (void)loadScene(doc, sceneOptions);
    } catch (const InputError&) {
        // A factor the importer passes and the scene format refuses is an error, not a crash.
    }
}

void check(std::string_view bytes) {
    const MeshFormat format = bytes.substr(0, 2) == "PK" ? MeshFormat::GltfZip : MeshFormat::Glb;
    importAndLoad(bytes, format, true);
    importAndLoad(bytes, format, false);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string bytes = fuzz::text(data, size);
    check(bytes);
    const size_t nul = bytes.find('\0');
    if (nul != std::string::npos)
        check(testing::glbFromChunks(bytes.substr(0, nul), bytes.substr(nul + 1)));
    return 0;
}
