// A glTF 2.0 file as a Caustic scene (docs/gltf.md): the default scene's nodes with their meshes,
// materials (glTF's metallic-roughness model and the extensions the renderer models), textures,
// cameras and KHR_lights_punctual lights, written as a scene document whose meshes and images
// are "embedded" (scene/embedded_data.h); a job's or the CLI's overrides then change the camera,
// the environment, materials by glTF name, and add lights or settings.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gltf/gltf_model.h"
#include "scene/embedded_data.h"
#include "scene/json_reader.h"

namespace caustic {

/// The extensions the importer reads; a file that requires another is refused.
const std::vector<std::string>& supportedGltfExtensions();

struct GltfScene {
    /// The scene document: camera (the file's first, else automatic), materials, "embedded" mesh
    /// shapes, lights, and the default environment when the file has no light.
    Json scene;
    std::shared_ptr<EmbeddedData> embedded = std::make_shared<EmbeddedData>();
    /// The file's perspective cameras as Caustic cameras, in glTF camera order of the nodes that
    /// use them: {"name", "camera": glTF index, "node", "scene": the camera object}.
    Json cameras = Json::array();
    /// The world-space bounds of every mesh (min, max), for the automatic camera.
    Vec3 boundsMin{0.0f}, boundsMax{0.0f};
    /// What the file holds: meshes, triangles, materials, textures with their sizes, cameras,
    /// lights, extensions, and the warnings (what was left out or approximated).
    Json summary;
    std::vector<std::string> warnings;
};

struct GltfImportOptions {
    /// The largest image a texture may have, in pixels: a larger one is refused naming the image.
    int64_t maxPixels = int64_t(16384) * 16384;
    /// The long side of the image when neither the file's camera nor an override gives a size.
    int width = 960;
    /// Count the meshes (EmbeddedData::Mesh::counts) without reading them, and take the bounds
    /// from the POSITION accessors' min and max: what admission needs, at a fraction of the cost.
    bool countOnly = false;
};

/// Imports a file read by loadGlbModel or loadGltfModel. Fails through `errors` naming the glTF
/// object at fault (InputError): a required extension not supported, a factor out of range, an
/// image over the pixel limit or that does not decode, a hierarchy or accessor error.
GltfScene importGltf(const GltfFile& file, const GltfImportOptions& options,
                     const MeshErrors& errors);

/// The scene to render: `imported.scene` with the overrides of `request` (a job's "scene" object
/// or the CLI's), read at JSON path `path`: "camera" ({"gltf": index or name}, {"auto": {...}}
/// or a Caustic camera, each with optional "width" and "height"), "environment" (null: none),
/// "background", "materials" (fields merged into the file's material of that name), "lights" (an
/// array added to the file's, or an object changing the file's by name, null leaving one out),
/// "settings". Records in the summary what was used ("camera",
/// "environment"). InputError at the override's path.
Json gltfSceneWithOverrides(GltfScene& imported, const Json& request, const std::string& path,
                            const GltfImportOptions& options);

/// The automatic camera for bounds: looking at their centre from `azimuth` degrees about +y from
/// +z (towards +x) and `elevation` degrees up, far enough for their bounding sphere to fit a
/// vertical field of `fov` degrees and the horizontal one of a width x height image.
Json autoCamera(const Vec3& boundsMin, const Vec3& boundsMax, double azimuth, double elevation,
                double fov, int width, int height);

}  // namespace caustic
