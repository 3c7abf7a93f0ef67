// A loaded scene: camera, primitives, materials, lights, background, and default settings. Built by
// the loader, then read-only: every render of it may run on many threads.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/built_parts.h"
#include "geometry/geometry.h"
#include "lights/environment_light.h"
#include "lights/light.h"
#include "lights/light_sampler.h"
#include "lights/local_light_sampler.h"
#include "materials/material.h"
#include "materials/material_scratch.h"
#include "scene/camera.h"
#include "scene/embedded_data.h"
#include "scene/mesh_counts.h"
#include "scene/mesh_file.h"
#include "textures/texture_store.h"

namespace caustic {

struct Scene {
    Camera camera;
    Geometry geometry;
    std::vector<std::unique_ptr<Material>> materials;
    std::vector<std::string> materialNames;
    /// Point lights and one area light per emissive primitive.
    std::vector<std::unique_ptr<Light>> lights;
    /// Chooses among `lights` by power (where photons start); empty (and free) when nothing emits.
    LightSampler lightSampler;
    /// Chooses the light a shading point samples, by its estimated contribution there.
    LocalLightSampler directLights;
    /// The emissive primitives in ascending order: lights[firstAreaLight + i] is emitterPrims[i]'s
    /// area light. Empty when nothing emits.
    std::vector<uint32_t> emitterPrims;
    size_t firstAreaLight = 0;
    Color background{0.0f};
    /// The environment light ("environment"), also in `lights` at environmentIndex; null when the
    /// scene has none.
    const EnvironmentLight* environment = nullptr;
    size_t environmentIndex = 0;
    /// Bytes of the environment's image and sampling density (from its size alone when the scene
    /// was loaded for admission).
    size_t environmentBytes = 0;
    /// The scene file's "settings" object: defaults a job's own settings override.
    nlohmann::json settings = nlohmann::json::object();
    /// With SceneOptions::countMeshesOnly, the meshes validated but not loaded: their counts and
    /// material. Their triangles are in neither `geometry` nor `lights`: such a scene is for
    /// estimating memory (render/memory_estimate.h), never for rendering.
    struct CountedMesh {
        MeshCounts counts;
        uint32_t material = 0;
    };
    std::vector<CountedMesh> countedMeshes;
    /// What the scene built because it uses it, and its cost (the render's stats list it).
    BuiltParts built;

    /// Radiance of a ray that leaves the scene along unit direction d: the background's and the
    /// environment's.
    Color escapedRadiance(const Vec3& d) const {
        return environment ? background + environment->Le(d) : background;
    }

    const Material& material(uint32_t prim) const { return *materials[geometry.material(prim)]; }
    /// The material at si as shading sees it: the scene's, or for a textured one the material its
    /// textures make at si (in `scratch`), filtered over a pixel's footprint there times
    /// `footprintScale`; a normal map turns si.ns.
    const Material& shade(SurfaceInteraction& si, MaterialScratch& scratch,
                          float footprintScale = 1.0f) const {
        const Material& m = *materials[si.material];
        return m.isTextured() ? shadeTextured(m, si, scratch, footprintScale) : m;
    }

    /// The images the materials read (null when none does), and the bytes they may hold in
    /// memory: the store's cache bound.
    std::shared_ptr<TextureStore> textures;
    size_t textureBytes = 0;
    /// Whether a material may cut parts of its surface out: rays then go through
    /// scene/visibility.h's queries, which pass through them.
    bool hasAlpha = false;
    /// The index in `lights` of an emissive primitive's area light; nullopt for a primitive that
    /// does not emit.
    std::optional<size_t> areaLightOf(uint32_t prim) const;
    /// Bytes of the light tables: the sampler, the primitive-to-light index and the environment.
    size_t lightTableBytes() const {
        return lightSampler.memoryBytes() + emitterPrims.capacity() * sizeof(uint32_t) +
               environmentBytes;
    }

private:
    const Material& shadeTextured(const Material& m, SurfaceInteraction& si,
                                  MaterialScratch& scratch, float footprintScale) const;
};

/// An uploaded mesh as the scene loader sees it: what the service stored at upload.
struct MeshAsset {
    MeshFormat format = MeshFormat::Obj;
    MeshCounts counts;                         ///< Stored at upload: admission estimates from them.
    std::shared_ptr<const std::string> bytes;  ///< The file; may be null when only counting.
};
/// Finds an asset by id (64 lowercase hex digits, checked by the loader first); throws InputError
/// at `path` ("no asset ..."). needBytes is false when SceneOptions::countMeshesOnly.
using MeshAssetResolver =
    std::function<MeshAsset(const std::string& id, const std::string& path, bool needBytes)>;

struct SceneOptions {
    /// Folder that mesh "file" names resolve in; no name may leave it.
    std::filesystem::path assetsDir;
    /// Largest resolution accepted, per side and in pixels.
    int maxResolution = 16384;
    int64_t maxPixels = int64_t(16384) * 16384;
    /// Validate every field and find every mesh file, but read only the meshes' counts (a line
    /// scan; Scene::countedMeshes) instead of loading them: for a service admitting a job.
    bool countMeshesOnly = false;
    /// With countMeshesOnly, where counts of files already scanned are kept (none: scan each).
    MeshCountCache* meshCounts = nullptr;
    /// Finds the uploaded meshes that "asset" shapes name; empty: an "asset" shape is an
    /// InputError at its path.
    MeshAssetResolver resolveMeshAsset = {};
    /// Where textures' images are prepared and cached: a worker's store, shared by its renders;
    /// null: a scene with textures makes a store of its own.
    std::shared_ptr<TextureStore> textures = nullptr;
    /// The meshes and images of a scene imported from a model file, which "embedded" shapes and
    /// textures name; null: "embedded" is an InputError at its path.
    std::shared_ptr<const EmbeddedData> embedded = nullptr;
};

/// Builds a scene from its JSON document (DESIGN.md, "Scene format"). Throws InputError naming the
/// JSON path of the first problem.
std::unique_ptr<Scene> loadScene(const nlohmann::json& doc, const SceneOptions& options);

/// Throws InputError at widthPath or heightPath unless each side is in [1, maxResolution] and
/// the image has at most maxPixels pixels (`options`' limits).
void checkResolution(int64_t width, int64_t height, const SceneOptions& options,
                     const std::string& widthPath, const std::string& heightPath);

/// Reads and parses a JSON file; InputError with the line and column of a syntax error.
nlohmann::json readJsonFile(const std::filesystem::path& file);
/// Parses JSON text; InputError with the line and column of a syntax error.
nlohmann::json parseJson(const std::string& text);

}  // namespace caustic
