#include "photons/photon_tracer.h"

#include <omp.h>

#include <algorithm>

#include "core/rng.h"
#include "materials/surface_bsdf.h"
#include "scene/visibility.h"

namespace caustic {
namespace {

// Whether photons pass a surface of material m (unshaded: a textured one has a diffuse lobe or a
// roughness only its textures know, and is never passed) without being stored, as a mirror.
bool followedByPhotons(const Material& m, const PhotonTracingOptions& options) {
    return m.isSpecular() || m.lobeRoughness() < options.followedRoughness;
}

// Photon paths are traced in chunks whose results are joined in chunk order, so the photon list
// does not depend on the number of threads.
constexpr uint64_t kChunk = 4096;
// Random streams of photon paths, apart from camera samples (which use small sample indices).
constexpr uint64_t kPhotonStream = uint64_t(1) << 62;

struct Chunk {
    std::vector<Photon> photons;
    DVec3 emittedPower{0.0};
    uint64_t rays = 0;
    InterruptPoller interrupt;  // polled every bounce
    MaterialScratch scratch;    // textured materials at a photon's point
};

void tracePath(const Scene& scene, const Accelerator& accel, const PhotonTracingOptions& options,
               uint64_t index, Chunk& out) {
    Rng rng = Rng::forSample(options.seed, options.pass, index,
                             kPhotonStream + (options.causticOnly ? 1 : 0));
    std::optional<SampledLight> chosen = scene.lightSampler.sample(rng.uniform());
    Vec2 uPosition = rng.uniform2(), uDirection = rng.uniform2();
    if (!chosen) return;
    std::optional<LightLeSample> le = chosen->light->sampleLe(uPosition, uDirection);
    if (!le) return;
    // Each path carries its light's flux over the probability of its light and the path count.
    Color beta = le->power / (chosen->pmf * float(options.photons));
    out.emittedPower += DVec3(beta);
    Ray ray = le->ray;
    bool specularOnly = true;
    for (int bounces = 0; bounces < options.maxDepth; ++bounces) {
        if (out.interrupt.poll()) return;
        ++out.rays;
        std::optional<Hit> hit = intersectVisible(scene, accel, ray, kInfinity, out.rays);
        if (!hit) return;
        SurfaceInteraction si = scene.geometry.interaction(ray, *hit);
        const bool followed = followedByPhotons(*scene.materials[si.material], options);
        const Material& m = scene.shade(si, out.scratch);
        Vec3 wo = -ray.d;
        if (!followed) {
            PhotonPath path = bounces == 0   ? PhotonPath::Direct
                              : specularOnly ? PhotonPath::Caustic
                                             : PhotonPath::Indirect;
            const Photon photon{si.p, wo, beta, path, uint8_t(std::min(bounces, 255))};
            if (options.causticOnly) {
                if (path == PhotonPath::Caustic) out.photons.push_back(photon);
                return;
            }
            out.photons.push_back(photon);
        }
        float uc = rng.uniform();
        Vec2 u = rng.uniform2();
        std::optional<BsdfSample> bs =
            SurfaceBsdf(m, si).sample(wo, uc, u, TransportMode::Importance);
        if (!bs || isBlack(bs->weight)) return;
        // Russian roulette on the change of throughput, so a photon keeps its power while it can
        // (pbrt-v4 15.1, SPPM photon pass).
        Color next = beta * bs->weight;
        float q = std::min(1.0f, maxComponent(next) / maxComponent(beta));
        if (!(rng.uniform() < q)) return;
        beta = next / q;
        specularOnly = specularOnly && (followed || bs->specular);
        ray = Ray{rayOrigin(si, bs->wi), bs->wi};
    }
}

}  // namespace

PhotonTracing tracePhotons(const Scene& scene, const Accelerator& accel,
                           const PhotonTracingOptions& options) {
    PhotonTracing result;
    result.emitted = options.photons;
    if (scene.lightSampler.empty() || options.photons == 0) return result;
    // A caustic needs a followed bounce: without a followed material no path could store one, and
    // tracing them would only spend rays.
    if (options.causticOnly && std::none_of(scene.materials.begin(), scene.materials.end(),
                                            [&](const std::unique_ptr<Material>& m) {
                                                return followedByPhotons(*m, options);
                                            }))
        return result;
    const uint64_t chunks = (options.photons + kChunk - 1) / kChunk;
    std::vector<Chunk> done(chunks);
    for (Chunk& c : done) c.interrupt = InterruptPoller(options.interrupt);
    const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (uint64_t c = 0; c < chunks; ++c) {
        if (options.interrupt && options.interrupt->requested()) continue;
        uint64_t end = std::min(options.photons, (c + 1) * kChunk);
        for (uint64_t i = c * kChunk; i < end; ++i) {
            // Per path too: an interrupted path returns, and the chunk's next one must not start.
            if (options.interrupt && options.interrupt->requested()) break;
            tracePath(scene, accel, options, i, done[c]);
        }
    }
    result.interrupted = options.interrupt && options.interrupt->requested();
    size_t total = 0;
    for (const Chunk& c : done) total += c.photons.size();
    result.photons.reserve(total);
    for (Chunk& c : done) {
        result.photons.insert(result.photons.end(), c.photons.begin(), c.photons.end());
        result.emittedPower += c.emittedPower;
        result.rays += c.rays;
    }
    return result;
}

}  // namespace caustic
static_assert(sizeof(caustic::Photon) == 40, "Photon layout: see photon_tracer.h");
