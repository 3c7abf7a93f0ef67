#include "render/memory_estimate.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "film/film.h"
#include "integrators/photon.h"
#include "lights/light.h"
#include "render/integrator_factory.h"

namespace caustic {
namespace {

// Accelerator bytes: a fixed part plus a part per primitive. Not a bound: a kd-tree's size depends
// on how many primitives straddle its splits, which no count tells. Measured (memoryBytes() after
// a build): Embree 83-93 bytes a primitive on the bunny, teapot, spot and a 1M-triangle grid,
// 3.9 KB for the 8 primitives of cornell-spheres. Our kd-tree (its leaves holding their triangles'
// vertices, 40 bytes a reference, costed in tests of eight): 68 bytes a primitive on the bunny
// (1.66 references a triangle), 76 on the teapot (1.86), 68 on the 1M-triangle bunny of
// bench_accel_rays (1.66). The figures below hold them with a margin
// (tests/renderer/render/memory_estimate_test.cpp); render() checks what it built.
constexpr size_t kAccelFixedBytes = size_t(16) << 10;
constexpr size_t kEmbreeBytesPerPrim = 128;
constexpr size_t kKdTreeBytesPerPrim = 160;

size_t mib(size_t bytes) {
    return (bytes + (size_t(1) << 20) - 1) >> 20;
}

// The settings the photon budget depends on.
struct PhotonBudget {
    uint64_t photons = 0;         // paths a pass of a map that keeps every photon they store
    uint64_t causticPhotons = 0;  // paths a pass whose caustic photons a caustic map keeps
    int maxDepth = 0;
    const char* setting = "";  // what a refusal names
};

// Zero paths when the integrator keeps no photon map.
PhotonBudget photonBudget(const RenderSettings& s) {
    const IntegratorTraits* traits = findIntegrator(s.integrator);
    if (!traits) return {};
    if (traits->photonMapsBySetting) {
        // Its caustic map (`photons` caustic-only paths) and its indirect map (a global map of
        // `indirect_photons` paths, less their direct photons: bounded by all of them).
        const bool caustics = s.path.caustics == PathSource::PhotonMap;
        const bool indirect = s.path.indirect == PathSource::PhotonMap;
        return {indirect ? s.path.indirectPhotons : 0, caustics ? s.photon.photons : 0, s.maxDepth,
                indirect ? "/settings/indirect_photons" : "/settings/photons"};
    }
    if (!traits->ownsPhotonMaps) return {};
    const bool caustics = s.photon.causticPhotons > s.photon.photons;
    // Without caustic_photons, the caustic map copies those of the `photons` paths.
    return {s.photon.photons,
            s.photon.causticPhotons > 0 ? s.photon.causticPhotons : s.photon.photons, s.maxDepth,
            caustics ? "/settings/caustic_photons" : "/settings/photons"};
}

struct Counts {
    uint64_t prims = 0, vertices = 0, triangles = 0;
    uint64_t lights = 0, emitters = 0;  // emitters: emissive primitives, each an area light
    bool emits = false;                 // a light of nonzero power exists
    uint64_t normals = 0;               // vertex normals
    uint64_t texcoords = 0;             // vertices with texture coordinates
    uint64_t tangents = 0;              // vertices with tangents
};

Counts countScene(const Scene& scene) {
    const Geometry& g = scene.geometry;
    Counts c{g.size(),
             g.positions().size(),
             g.triangles().size(),
             scene.lights.size(),
             scene.emitterPrims.size(),
             !scene.lightSampler.empty()};
    c.normals = g.hasVertexNormals() ? g.positions().size() : 0;
    c.texcoords = g.hasTexcoords() ? g.positions().size() : 0;
    c.tangents = g.hasTangents() ? g.positions().size() : 0;
    for (const Scene::CountedMesh& mesh : scene.countedMeshes) {
        const Material& m = *scene.materials[mesh.material];
        // A textured material splits vertices by texture coordinates too: one a corner at most.
        const uint64_t vertices = m.isTextured() && mesh.counts.texcoords
                                      ? std::max(mesh.counts.vertices, 3 * mesh.counts.triangles)
                                      : mesh.counts.vertices;
        c.prims += mesh.counts.triangles;
        c.vertices += vertices;
        if (mesh.counts.normals) c.normals += vertices;
        if (m.isTextured()) c.texcoords += vertices;
        if (m.needsTangents()) c.tangents += vertices;
        c.triangles += mesh.counts.triangles;
        if (scene.materials[mesh.material]->isEmissive()) {
            c.lights += mesh.counts.triangles;
            c.emitters += mesh.counts.triangles;
            c.emits = true;
        }
    }
    return c;
}

size_t geometryBytes(const Scene& scene, const Counts& c) {
    // The loader shrinks every array to its size (Geometry::shrinkToFit).
    return c.prims * sizeof(Geometry::PrimRecord) +
           scene.geometry.spheres().size() * sizeof(Sphere) +
           scene.geometry.quads().size() * sizeof(Quad) + (c.vertices + c.normals) * sizeof(Vec3) +
           c.texcoords * sizeof(Vec2) + c.tangents * sizeof(glm::vec4) +
           c.triangles * sizeof(glm::uvec3);
}

size_t acceleratorBytes(const std::string& name, const Counts& c) {
    if (name == "bruteforce" || c.prims == 0) return 0;
    return kAccelFixedBytes +
           c.prims * (name == "embree" ? kEmbreeBytesPerPrim : kKdTreeBytesPerPrim);
}

size_t lightTableBytes(const Counts& c) {
    if (!c.emits) return 0;
    // LightSampler: two arrays grown by push_back (capacity under twice the size), the cdf and the
    // pmf by light; then the emitter index, grown by push_back.
    return c.lights * 2 * (sizeof(const Light*) + sizeof(size_t)) +
           (2 * c.lights + 1) * sizeof(float) + c.emitters * 2 * sizeof(uint32_t);
}

bool hasSpecular(const Scene& scene) {
    return std::any_of(scene.materials.begin(), scene.materials.end(),
                       [](const auto& m) { return m->isSpecular(); });
}

size_t photonPeakBytes(const Scene& scene, const RenderSettings& settings, const Counts& c) {
    const PhotonBudget budget = photonBudget(settings);
    if ((budget.photons == 0 && budget.causticPhotons == 0) || !c.emits) return 0;
    const double perPath = storedPhotonsPerPathBound(scene, budget.maxDepth);
    // A path stores at most one caustic photon: the first non-specular hit after specular ones
    // only (photons/photon_tracer.cpp). Without specular materials there is none.
    const double caustic = hasSpecular(scene) && perPath > 0 ? 1.0 : 0.0;
    const double stored =
        double(budget.photons) * perPath + double(budget.causticPhotons) * caustic;
    return photonPassPeakBytes(stored);
}

}  // namespace

size_t filmBytes(int width, int height, bool adaptive, bool bias) {
    const size_t pixels = size_t(width) * size_t(height);
    const size_t film =
        Film::bytesFor(width, height, bias) + pixels * sizeof(Color) * (bias ? 2 : 1);
    return adaptive ? film + Film::bytesFor(width, height, bias) + pixels * sizeof(uint16_t) : film;
}

// Photon tracing stores a photon at each non-specular hit, at most one per bounce: at most
// max_depth a path. Russian roulette bounds the expectation better (photons/photon_tracer.cpp,
// after pbrt-v4 15.1): after a stored photon the path goes on with probability
// q = min(1, max(beta * w) / max(beta)) <= max(w) <= rho, where w is the sample weight, at most
// rho for every non-specular material (Material::maxScatterWeight). So a path stores another
// photon with probability at most rho each time, and E[stored] <= sum_k rho^k = 1 / (1 - rho).
double storedPhotonsPerPathBound(const Scene& scene, int maxDepth) {
    double rho = -1;  // no non-specular material: no photon is ever stored
    for (const auto& m : scene.materials)
        if (!m->isSpecular()) rho = std::max(rho, double(m->maxScatterWeight()));
    if (rho < 0) return 0;
    return rho < 1 ? std::min(double(maxDepth), 1.0 / (1.0 - rho)) : double(maxDepth);
}

MemoryEstimate estimateMemory(const Scene& scene, const RenderSettings& settings) {
    const Counts c = countScene(scene);
    MemoryEstimate e;
    e.geometry = geometryBytes(scene, c);
    e.accelerator = acceleratorBytes(settings.accelerator, c);
    e.film = filmBytes(scene.camera.width(), scene.camera.height(), settings.adaptive,
                       estimatesBias(settings.integrator, settings.path.photonMapped()));
    e.lightTables = lightTableBytes(c) + scene.environmentBytes;
    e.photonMaps = photonPeakBytes(scene, settings, c);
    e.textures = scene.textureBytes;
    return e;
}

void checkMemoryEstimate(const Scene& scene, const RenderSettings& settings) {
    const size_t limit = settings.memoryLimitBytes();
    const MemoryEstimate e = estimateMemory(scene, settings);
    if (e.beforePasses() > limit)
        throw InputError("/settings/memory_limit",
                         "the scene, its accelerator and the film would take about " +
                             std::to_string(mib(e.beforePasses())) +
                             " MiB (estimated from counts), more than the limit of " +
                             std::to_string(limit >> 20) + " MiB");
    const size_t left = limit - e.beforePasses();
    if (e.photonMaps <= left) return;
    const PhotonBudget budget = photonBudget(settings);
    char perPath[32];
    std::snprintf(perPath, sizeof perPath, "%.1f",
                  storedPhotonsPerPathBound(scene, budget.maxDepth));
    // Without a global map (path's caustic map) a path stores one caustic photon at most.
    const std::string stored =
        budget.photons > 0 ? "up to " + std::string(perPath) +
                                 " photons stored a path, and one caustic photon with a specular "
                                 "material"
                           : "one caustic photon a path with a specular material";
    throw InputError(budget.setting,
                     "the photon maps of a pass could need about " +
                         std::to_string(mib(e.photonMaps)) + " MiB (estimated from counts: " +
                         stored + "), more than the " + std::to_string(mib(left)) +
                         " MiB the memory limit leaves; lower it, lower max_depth or raise "
                         "memory_limit");
}

}  // namespace caustic
