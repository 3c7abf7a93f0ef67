#include "gltf/scene_document.h"

#include <algorithm>
#include <utility>

#include "core/error.h"
#include "gltf/gltf_model.h"
#include "gltf/gltf_zip.h"
#include "scene/mesh_file.h"
#include "scene/mesh_loader.h"

namespace caustic {

bool isModelDocument(const Json& doc) {
    return doc.is_object() && doc.contains("gltf");
}

std::unique_ptr<Scene> loadSceneDocument(const Json& doc, SceneOptions options, Json* summary) {
    if (!isModelDocument(doc)) return loadScene(doc, options);
    checkJsonDepth(doc, "");
    JsonObject source(doc.at("gltf"), "/gltf");
    const Json* asset = source.find("asset");
    const Json* file = source.find("file");
    (void)source.find("summary");  // what admission found, kept in a job's stored scene
    source.finish();
    if (!!asset == !!file)
        throw InputError("/gltf",
                         "names a model by \"asset\" (an uploaded .glb's id) or \"file\" "
                         "(a .glb or .gltf in the assets folder), one of them");
    const std::string at = asset ? "/gltf/asset" : "/gltf/file";
    const std::string name = source.string(asset ? "asset" : "file");
    std::string label = asset ? "asset " + name : name;
    const MeshErrors errors{label, at};
    GltfFile model;
    if (asset) {
        if (!options.resolveMeshAsset)
            throw InputError(at, "this renderer has no asset store; use \"file\"");
        const MeshAsset stored = options.resolveMeshAsset(name, at, true);
        if (!isGltfFormat(stored.format) || !stored.bytes)
            throw InputError(at, "asset " + name + " is " + nameOf(stored.format) +
                                     ", not a glTF model (.glb, or .zip of a .gltf)");
        model = loadGltfUpload(*stored.bytes, stored.format, errors);
    } else {
        if (!isGltfFileName(name)) throw InputError(at, "must name a .glb or .gltf file");
        model = loadGltfPath(resolveAsset(options.assetsDir, name, at), errors);
    }
    return loadModelScene(model, doc, std::move(options), errors, summary);
}

std::unique_ptr<Scene> loadModelScene(const GltfFile& model, const Json& request,
                                      SceneOptions options, const MeshErrors& errors,
                                      Json* summary) {
    GltfImportOptions importOptions;
    importOptions.maxPixels = options.maxPixels;
    importOptions.countOnly = options.countMeshesOnly;
    // A size the renderer takes: the render's settings may set another.
    importOptions.width = std::min(importOptions.width, options.maxResolution);
    GltfScene imported = importGltf(model, importOptions, errors);
    Json resolved = gltfSceneWithOverrides(imported, request, "", importOptions);
    options.embedded = imported.embedded;
    std::unique_ptr<Scene> scene = loadScene(resolved, options);
    if (summary) *summary = std::move(imported.summary);
    return scene;
}

}  // namespace caustic
