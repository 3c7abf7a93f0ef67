// Helpers shared by renderer tests: build scenes from JSON text, render them small, and name a
// pixel value in a failure message.
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "integrators/integrator.h"
#include "render/integrator_factory.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace caustic::testing {

/// Options with the repository's assets folder.
inline SceneOptions repoSceneOptions() {
    SceneOptions o;
    o.assetsDir = CAUSTIC_SOURCE_DIR "/assets/meshes";
    return o;
}

inline std::unique_ptr<Scene> sceneFromJson(const nlohmann::json& doc) {
    return loadScene(doc, repoSceneOptions());
}

/// An example scene from scenes/, optionally resized.
inline nlohmann::json exampleScene(const std::string& name, int width = 0, int height = 0) {
    nlohmann::json doc = readJsonFile(CAUSTIC_SOURCE_DIR "/scenes/" + name + ".json");
    if (width > 0) doc["camera"]["width"] = width;
    if (height > 0) doc["camera"]["height"] = height;
    return doc;
}

/// Settings from JSON over the defaults, with the scene's own settings ignored.
inline RenderSettings settingsFrom(const nlohmann::json& j) {
    return parseSettings(j);
}

/// Root-mean-square difference of two images (flat arrays of one size).
inline double rmse(const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += double(a[i] - b[i]) * double(a[i] - b[i]);
    return std::sqrt(sum / double(a.size()));
}

/// Root-mean-square value of an image.
inline double rms(const std::vector<float>& a) {
    return rmse(a, std::vector<float>(a.size(), 0.0f));
}

/// Every integrator's name, and "path_photon_caustics": path with caustics from a photon map.
/// Tests that must hold for every estimator of the image loop over these.
inline std::vector<std::string> integratorVariants() {
    std::vector<std::string> names = integratorNames();
    names.push_back("path_photon_caustics");
    names.push_back("path_photon_maps");
    return names;
}

/// The settings that select an integratorVariants() entry.
inline nlohmann::json integratorVariant(const std::string& variant) {
    if (variant == "path_photon_caustics")
        return {{"integrator", "path"}, {"caustics", "photon_map"}};
    if (variant == "path_photon_maps")
        return {{"integrator", "path"}, {"caustics", "photon_map"}, {"indirect", "photon_map"}};
    return {{"integrator", variant}};
}

/// "pixel (x, y) channel c: mean +- se", for failure messages.
inline std::string pixelValueText(int x, int y, int c, float mean, float se) {
    return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
           std::to_string(c) + ": " + std::to_string(mean) + " +- " + std::to_string(se);
}

/// `base` with `patch` merged in (RFC 7386). Not named `patched`: the scene loader tests' patched
/// (renderer/scene/base_scene.h) takes a JSON pointer and a value, and a call with a string
/// literal would be ambiguous between the two.
inline nlohmann::json mergePatched(nlohmann::json base, const nlohmann::json& patch) {
    base.merge_patch(patch);
    return base;
}

/// The emission of emissiveWallScene's wall.
constexpr std::array<double, 3> kEmissiveWallLe = {0.9, 0.5, 0.2};

/// An emissive wall of albedo 0 filling the view of a `size` x `size` image, optionally with a
/// dielectric sphere of IOR 1 in front of it. Albedo 0 ends every path at the wall (the diffuse
/// sample has weight 0, and light samples there are 0), so each sample is exactly the wall's Le
/// (kEmissiveWallLe), with or without the sphere.
inline nlohmann::json emissiveWallScene(bool withIorOneSphere, int size) {
    nlohmann::json doc = nlohmann::json::parse(R"({
      "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 30},
      "materials": {
        "wall": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [0.9, 0.5, 0.2]},
        "air": {"type": "dielectric", "ior": 1.0}
      },
      "shapes": [{"type": "quad", "origin": [-10, -10, -2], "u": [20, 0, 0], "v": [0, 20, 0],
                  "material": "wall"}]
    })");
    doc["camera"]["width"] = size;
    doc["camera"]["height"] = size;
    if (withIorOneSphere)
        doc["shapes"].push_back({{"type", "sphere"},
                                 {"center", {0.1, -0.1, 0.5}},
                                 {"radius", 0.7},
                                 {"material", "air"}});
    return doc;
}

}  // namespace caustic::testing
