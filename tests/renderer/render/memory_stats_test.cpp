// Stats report memory by component, and a render builds only what its scene and integrator need
// (DESIGN.md, "Cost follows the scene"): no photon map for path tracing, no mesh arrays for a scene
// of spheres, no light tables for a scene that emits nothing.
#include <gtest/gtest.h>

#include "accel/accelerator.h"
#include "core/error.h"
#include "integrators/photon.h"
#include "photons/photon_kdtree.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::exampleScene;
using testing::sceneFromJson;
using testing::settingsFrom;

constexpr int kWidth = 24, kHeight = 16;

// Spheres only, lit by an emissive sphere.
json spheresOnly() {
    return json::parse(R"({
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 40, "width": 24, "height": 16},
      "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
                    "lamp": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [4, 4, 4]}},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"},
                 {"type": "sphere", "center": [0, 3, 0], "radius": 0.5, "material": "lamp"}]
    })");
}

MemoryStats renderMemory(const json& doc, const json& settings) {
    auto scene = sceneFromJson(doc);
    return render(*scene, settingsFrom(settings)).stats.memory;
}

TEST(MemoryStats, ComponentsAddUpAndFilmIsPerPixel) {
    MemoryStats m = renderMemory(spheresOnly(), {{"integrator", "path"}, {"spp", 2}});
    EXPECT_EQ(m.total(),
              m.geometry + m.meshes + m.accelerator + m.film + m.lightTables + m.photonMaps);
    // Per channel a 128-bit sum and a 192-bit sum of squares (film/exact_sum.h), plus the float
    // pass buffer.
    EXPECT_EQ(m.film, size_t(kWidth) * kHeight * (3 * (16 + 24) + 3 * sizeof(float)));
    EXPECT_GT(m.geometry, 0u);
    json j = m.toJson();
    for (const char* key :
         {"geometry", "meshes", "accelerator", "film", "light_tables", "photon_maps", "total"})
        EXPECT_TRUE(j.contains(key)) << key;
}

TEST(MemoryStats, PathTracingBuildsNoPhotonMap) {
    for (const char* integrator : {"raycast", "whitted", "path"})
        EXPECT_EQ(renderMemory(spheresOnly(), {{"integrator", integrator}, {"spp", 1}}).photonMaps,
                  0u)
            << integrator;
}

// The bytes of a photon map of n photons: 40 a photon, and its tree's 16 a photon, 8 a split
// of a complete tree of its depth and a leaf's padding (photons/photon_kdtree.h).
size_t photonMapBytes(size_t n) {
    if (n == 0) return 0;
    int levels = 0;
    for (size_t m = n; m > PhotonKdTree::kLeafSize; m -= m / 2) ++levels;
    return 56 * n + 8 * ((size_t(1) << levels) - 1) + 2 * (PhotonKdTree::kLeafSize - 1) * 4;
}

// Whether `bytes` are those of two photon maps (global and caustic) of some sizes.
bool areTwoPhotonMaps(size_t bytes) {
    for (size_t global = 0; photonMapBytes(global) <= bytes; ++global) {
        const size_t rest = bytes - photonMapBytes(global);
        // photonMapBytes(n) - 120 is 56 n to 58 n: start below the answer.
        size_t caustic = rest > 120 ? (rest - 120) / 58 : 0;
        while (photonMapBytes(caustic) < rest) ++caustic;
        if (photonMapBytes(caustic) == rest) return true;
    }
    return false;
}

TEST(MemoryStats, PhotonMappingReportsItsMaps) {
    // 40 bytes a stored photon and its tree's, for the global map and again for caustics (a
    // glass sphere under the lamp makes some).
    json doc = spheresOnly();
    doc["materials"]["glass"] = {{"type", "dielectric"}, {"ior", 1.5}};
    doc["shapes"].push_back(
        {{"type", "sphere"}, {"center", {0, 1.8, 0}}, {"radius", 0.3}, {"material", "glass"}});
    MemoryStats m = renderMemory(doc, {{"integrator", "photon"}, {"photons", 2000}, {"spp", 1}});
    EXPECT_GT(m.photonMaps, 0u);
    EXPECT_TRUE(areTwoPhotonMaps(m.photonMaps)) << m.photonMaps;
}

// The photon count a job asks for is checked against memory_limit before the first pass, and the
// error names the setting at fault.
std::string refusal(const json& settings) {
    auto scene = sceneFromJson(exampleScene("cornell-spheres", kWidth, kHeight));
    try {
        render(*scene, settingsFrom(settings));
    } catch (const InputError& e) {
        return e.path();
    }
    return "rendered";
}

TEST(MemoryStats, PhotonCountsAreCheckedAgainstTheLimit) {
    // About 3 stored photons a path in the Cornell box, 80 bytes each at the peak: 1e8 paths need
    // some 24 GB.
    EXPECT_EQ(refusal({{"integrator", "photon"}, {"photons", 100000000}, {"memory_limit", 1000}}),
              "/settings/photons");
    EXPECT_EQ(refusal({{"integrator", "ppm"},
                       {"photons", 1000},
                       {"caustic_photons", 1000000000},
                       {"memory_limit", 1000}}),
              "/settings/caustic_photons");
    EXPECT_EQ(refusal({{"integrator", "path"}, {"memory_limit", 0.001}}), "/settings/memory_limit");
    EXPECT_EQ(refusal({{"integrator", "photon"}, {"photons", 1000}, {"spp", 1}}), "rendered");
}

TEST(MemoryStats, PhotonEstimateBoundsWhatAPassHolds) {
    auto scene = sceneFromJson(exampleScene("cornell-spheres", kWidth, kHeight));
    auto accel = createAccelerator("embree", scene->geometry);
    for (uint64_t caustic : {uint64_t(0), uint64_t(50000)}) {
        PhotonIntegrator integrator(*scene, *accel, TraceSettings{},
                                    {.photons = 50000, .causticPhotons = caustic});
        const size_t estimate = integrator.estimatedPeakBytes();
        integrator.beginPass(0);
        // The maps held after the pass (56 bytes a photon) fit under the peak estimate (80 bytes
        // a photon at the peak, plus 10%), and the estimate is not wildly above them.
        EXPECT_GT(estimate, integrator.memoryBytes()) << caustic;
        EXPECT_LT(estimate, 2 * integrator.memoryBytes()) << caustic;
    }
}

TEST(MemoryStats, SpheresBuildNoMeshStructures) {
    for (const std::string& accel : acceleratorNames()) {
        MemoryStats spheres = renderMemory(spheresOnly(), {{"accelerator", accel}, {"spp", 1}});
        EXPECT_EQ(spheres.meshes, 0u) << accel;
    }
    auto scene = sceneFromJson(spheresOnly());
    EXPECT_FALSE(scene->geometry.hasTriangles());
    // The same accounting sees a mesh when there is one.
    MemoryStats bunny = renderMemory(exampleScene("bunny", kWidth, kHeight), {{"spp", 1}});
    EXPECT_GT(bunny.meshes, 1000000u);  // 69451 triangles: positions and indices
}

TEST(MemoryStats, NothingEmittingBuildsNoLightTables) {
    json dark = spheresOnly();
    dark["materials"]["lamp"].erase("emission");
    auto scene = sceneFromJson(dark);
    EXPECT_TRUE(scene->lights.empty());
    EXPECT_TRUE(scene->emitterPrims.empty());
    EXPECT_EQ(renderMemory(dark, {{"integrator", "path"}, {"spp", 1}}).lightTables, 0u);
    // One emitter: a table of one.
    EXPECT_GT(renderMemory(spheresOnly(), {{"integrator", "path"}, {"spp", 1}}).lightTables, 0u);
}

TEST(MemoryStats, ZeroPowerLightsAreNeverChosen) {
    json doc = spheresOnly();
    doc["lights"] =
        json::parse(R"([{"type": "point", "position": [0, 2, 0], "intensity": [0, 0, 0]}])");
    auto scene = sceneFromJson(doc);
    ASSERT_EQ(scene->lights.size(), 2u);  // the point light first, then the lamp's area light
    EXPECT_EQ(scene->lightSampler.pmf(0), 0.0f);
    EXPECT_EQ(scene->lightSampler.pmf(1), 1.0f);
    for (int i = 0; i < 1000; ++i)
        EXPECT_EQ(scene->lightSampler.sample(float(i) / 1000.0f)->light, scene->lights[1].get());
}

TEST(MemoryStats, EmbreeReportsItsBvh) {
    MemoryStats embree = renderMemory(exampleScene("bunny", kWidth, kHeight),
                                      {{"accelerator", "embree"}, {"spp", 1}});
    // At least its copy of the 69451 triangles' vertices and indices, and the BVH beyond them.
    EXPECT_GT(embree.accelerator, embree.meshes);
}

}  // namespace
}  // namespace caustic
