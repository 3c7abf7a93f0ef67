// Extreme scenes: every integrator must give a finite value in every pixel and drop no sample
// (the render loop counts NaN and infinite samples in stats.droppedSamples and leaves them out, so
// the dropped count is what shows a NaN or Inf from the integrator). The scenes push the
// quantities that divide: albedo 1 (no absorption to end paths), IOR near 1 and very high,
// directions in or along a surface (zero cosines), lights at zero distance from surfaces, tiny and
// huge scales and far from the origin (offsets and tolerances), and sphere lights subtending a
// tiny cone (1 - cos(theta_max) below float precision) or nearly a hemisphere.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "support/scene_transform.h"
#include "support/test_scenes.h"

namespace caustic {
namespace {

using nlohmann::json;
using testing::exampleScene;
using testing::pixelValueText;
using testing::sceneFromJson;
using testing::settingsFrom;
using testing::transformedScene;

constexpr int kSize = 24;

json cornell() {
    return exampleScene("cornell-spheres", kSize, kSize);
}

// The shape in `doc` whose material is `material` (the first one).
json& shapeWithMaterial(json& doc, const std::string& material) {
    for (json& s : doc["shapes"])
        if (s["material"] == material) return s;
    throw std::runtime_error("no shape of material " + material);
}

// A kSize x kSize camera at `position` looking at `lookAt`.
json camera(const json& position, const json& lookAt) {
    return {{"position", position},
            {"look_at", lookAt},
            {"fov", 40},
            {"width", kSize},
            {"height", kSize}};
}

// A quad shape of `material`.
json quad(const json& origin, const json& u, const json& v, const char* material) {
    return {{"type", "quad"}, {"origin", origin}, {"u", u}, {"v", v}, {"material", material}};
}

// A diffuse "floor" and a diffuse "lamp" emitting Le.
json floorAndLamp(double Le) {
    return {
        {"floor", {{"type", "diffuse"}, {"albedo", {0.7, 0.6, 0.5}}}},
        {"lamp", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}, {"emission", {Le, Le, Le}}}}};
}

// A large diffuse floor y = 0 under a small lamp and a point light; a wall at z = -5 closes the
// view. For the grazing cameras.
json floorScene(const json& cameraPosition, const json& lookAt) {
    return {
        {"camera", camera(cameraPosition, lookAt)},
        {"materials", floorAndLamp(5)},
        {"shapes",
         {quad({-1e4, 0, -1e4}, {0, 0, 2e4}, {2e4, 0, 0}, "floor"),
          quad({-3, 0, -5}, {6, 0, 0}, {0, 3, 0}, "floor"),
          quad({-0.5, 2, -2}, {1, 0, 0}, {0, 0, 1}, "lamp")}},
        {"lights", {{{"type", "point"}, {"position", {1, 1, -1}}, {"intensity", {3, 3, 3}}}}},
    };
}

// A diffuse floor y = 0 lit by one emissive sphere.
json sphereLightScene(const json& center, double radius, double Le, const json& cameraPosition,
                      const json& lookAt) {
    return {
        {"camera", camera(cameraPosition, lookAt)},
        {"materials", floorAndLamp(Le)},
        {"shapes",
         {quad({-50, 0, -50}, {0, 0, 100}, {100, 0, 0}, "floor"),
          {{"type", "sphere"}, {"center", center}, {"radius", radius}, {"material", "lamp"}}}},
    };
}

struct ExtremeScene {
    const char* name;
    json (*make)();
};

const ExtremeScene kScenes[] = {
    // Albedo 1 everywhere: nothing is absorbed, Russian roulette (continuation probability
    // max(beta) = 1) never ends a path, only escaping through the open front or max_depth does.
    {"AlbedoOne",
     [] {
         json doc = cornell();
         for (auto& [name, m] : doc["materials"].items())
             if (m["type"] == "diffuse") m["albedo"] = {1, 1, 1};
         return doc;
     }},
    // Dielectrics barely refracting (R ~ 1e-9 at normal incidence, T / eta^2 ~ 1) and very dense
    // (R = 0.67 at normal incidence, total internal reflection beyond 5.7 degrees inside).
    {"GlassIor1_0001",
     [] {
         json doc = cornell();
         doc["materials"]["glass"]["ior"] = 1.0001;
         return doc;
     }},
    {"GlassIor10",
     [] {
         json doc = cornell();
         doc["materials"]["glass"]["ior"] = 10.0;
         return doc;
     }},
    // The camera exactly in the plane of the floor quad, and on it: half the rays run along the
    // plane (zero determinant in the triangle test) or leave it at t = 0.
    {"CameraInFloorPlane",
     [] {
         return floorScene({0.25, 0, 0.5}, {0.25, 0, -5});
     }},
    // Looking along a floor from 1e-3 above it: rays meet it at angles down to 1e-6 rad, and the
    // shading points' normals are perpendicular to the view.
    {"CameraGrazingFloor",
     [] {
         return floorScene({0, 1e-3, 0.5}, {0, 0, -1000});
     }},
    // Point lights exactly on the floor, on the back wall, and on the mirror sphere (up to the
    // rounding of its surface): shading points at distance 0 to ~1e-7 from a light, with
    // cos(theta) = 0 for the surface's own points.
    {"PointLightsOnSurfaces",
     [] {
         json doc = cornell();
         doc["lights"] = {
             {{"type", "point"}, {"position", {0.2, -1, 0.1}}, {"intensity", {1, 1, 1}}},
             {{"type", "point"}, {"position", {0.3, 0.2, -1}}, {"intensity", {1, 1, 1}}},
             {{"type", "point"}, {"position", {-0.45, -0.2, -0.35}}, {"intensity", {1, 1, 1}}}};
         return doc;
     }},
    // The lamp in the plane of the ceiling (overlapping it: which is hit is up to rounding), and a
    // second emitter in the plane of the right wall: light samples land on surfaces that are the
    // receivers' own planes, with cos = 0 at both ends.
    {"AreaLightsCoplanarWithWalls",
     [] {
         json doc = cornell();
         shapeWithMaterial(doc, "lamp")["origin"] = {-0.23, 1, -0.18};
         doc["shapes"].push_back(quad({1, -0.5, -0.5}, {0, 0, 0.5}, {0, 0.5, 0}, "lamp"));
         return doc;
     }},
    // The lamp in the back left corner, touching both walls along its edges: shading points on the
    // walls arbitrarily close to the emitter.
    {"AreaLightTouchingWalls",
     [] {
         json doc = cornell();
         shapeWithMaterial(doc, "lamp")["origin"] = {-1, 0.99, -1};
         return doc;
     }},
    // The Cornell box at 1e-4 and 1e4 times its size, and moved 1e5 from the origin
    // (scale_test.cpp compares their images with raycast and whitted).
    {"Tiny", [] { return transformedScene(cornell(), 1e-4, 0); }},
    {"Huge", [] { return transformedScene(cornell(), 1e4, 0); }},
    {"Far", [] { return transformedScene(cornell(), 1, 1e5); }},
    // A sphere light of radius 1e-3 seen from 1e5 away: sin^2(theta_max) = 1e-16, below float
    // precision against 1, so 1 - cos(theta_max) needs its Taylor form (else the cone pdf is
    // infinite). Le = 1e14 makes its irradiance on the floor pi Le sin^2 = 0.03.
    {"SphereLightFar",
     [] {
         return sphereLightScene({0, 1e5, 0}, 1e-3, 1e14, {0, 2, 3}, {0, 0, 0});
     }},
    // A sphere light resting on the floor (touching it at one point) with a diffuse sphere
    // touching it and another 1e-6 from it: shading points at distance 0 to 1e-6 from its
    // surface, where it fills nearly a hemisphere (sin(theta_max) -> 1).
    {"SphereLightTouching",
     [] {
         json doc = sphereLightScene({0, 1, 0}, 1.0, 2.0, {2, 1.5, 4}, {0.5, 0.5, 0});
         doc["shapes"].push_back(
             {{"type", "sphere"}, {"center", {2, 1, 0}}, {"radius", 1.0}, {"material", "floor"}});
         doc["shapes"].push_back({{"type", "sphere"},
                                  {"center", {0, 1, 2.000001}},
                                  {"radius", 1.0},
                                  {"material", "floor"}});
         return doc;
     }},
};

// The integrators, with their settings: the path tracer in its three ways of finding emitters,
// with a max_depth far beyond the default (long paths are where weights drift), and Whitted and
// ray casting.
struct IntegratorConfig {
    const char* name;
    json settings;
};

const IntegratorConfig kIntegrators[] = {
    {"PathMis", {{"integrator", "path"}, {"max_depth", 1000}}},
    {"PathLightSampling", {{"integrator", "path"}, {"max_depth", 1000}, {"mis", false}}},
    {"PathBsdfOnly", {{"integrator", "path"}, {"max_depth", 1000}, {"light_sampling", false}}},
    {"Whitted", {{"integrator", "whitted"}, {"max_depth", 64}}},
    {"Raycast", {{"integrator", "raycast"}}},
};

class Extremes : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(Extremes, EveryPixelFiniteAndNoSampleDropped) {
    const auto [sceneIndex, integratorIndex] = GetParam();
    json settings = kIntegrators[integratorIndex].settings;
    settings.update({{"spp", 16}, {"spp_per_pass", 8}, {"seed", 21}});
    auto scene = sceneFromJson(kScenes[sceneIndex].make());
    RenderResult r = render(*scene, settingsFrom(settings));
    ASSERT_EQ(r.film->passes(), 2);
    EXPECT_EQ(r.stats.droppedSamples, 0u) << "of " << r.stats.samples << " samples";
    int nonFinite = 0;
    std::string first;
    for (int y = 0; y < r.film->height(); ++y) {
        for (int x = 0; x < r.film->width(); ++x) {
            Color m = r.film->mean(x, y), se = r.film->standardError(x, y);
            for (int c = 0; c < 3; ++c) {
                if (std::isfinite(m[c]) && std::isfinite(se[c])) continue;
                if (nonFinite++ == 0) first = pixelValueText(x, y, c, m[c], se[c]);
            }
        }
    }
    EXPECT_EQ(nonFinite, 0) << "first: " << first;
    // Not vacuous: camera rays met the scene and traced further rays (shadow or bounce).
    EXPECT_GT(r.stats.rays, r.stats.samples);
}

INSTANTIATE_TEST_SUITE_P(ScenesAndIntegrators, Extremes,
                         ::testing::Combine(::testing::Range(0, int(std::size(kScenes))),
                                            ::testing::Range(0, int(std::size(kIntegrators)))),
                         [](const auto& p) {
                             return std::string(kScenes[std::get<0>(p.param)].name) + "_" +
                                    kIntegrators[std::get<1>(p.param)].name;
                         });

}  // namespace
}  // namespace caustic
