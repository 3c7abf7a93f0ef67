#include "integrators/photon.h"

#include <algorithm>

#include "core/error.h"
#include "materials/surface_bsdf.h"

namespace caustic {

PhotonIntegrator::PhotonIntegrator(const Scene& scene, const Accelerator& accel,
                                   const TraceSettings& trace, const Settings& settings,
                                   bool progressive)
    : Integrator(scene, accel),
      trace_(trace),
      settings_(settings),
      progressive_(progressive),
      estimate_{settings.k, float(settings.radius), settings.kernel} {
    if (!progressive_) return;
    // ppm estimates at the visible point only, with a radius that shrinks per pass.
    settings_.finalGather = 0;
    estimate_.radius = firstProgressiveRadius(settings.radius, accel.bounds());
}

uint64_t PhotonIntegrator::beginPass(uint32_t pass) {
    passEstimate_ = estimate_;
    if (progressive_)
        passEstimate_.radius = progressiveRadius(estimate_.radius, float(settings_.alpha), pass);
    // Free the previous pass's maps first (peak memory: one pass's tracing and maps).
    global_.reset();
    caustic_.reset();
    PhotonTracing traced = tracePhotons(scene_, accel_, tracingOptions(pass, false));
    uint64_t rays = traced.rays;
    if (traced.interrupted) return rays;  // the caller abandons the pass
    std::vector<Photon> caustics;
    if (settings_.causticPhotons > 0) {
        PhotonTracing c = tracePhotons(scene_, accel_, tracingOptions(pass, true));
        rays += c.rays;
        if (c.interrupted) return rays;
        caustics = std::move(c.photons);
    } else {
        caustics.reserve(
            size_t(std::count_if(traced.photons.begin(), traced.photons.end(),
                                 [](const Photon& p) { return p.path == PhotonPath::Caustic; })));
        for (const Photon& p : traced.photons)
            if (p.path == PhotonPath::Caustic) caustics.push_back(p);
    }
    if (interrupt_ && interrupt_->requested()) return rays;  // before the maps' build
    global_ = std::make_unique<PhotonMap>(std::move(traced.photons), settings_.lookup);
    caustic_ = std::make_unique<PhotonMap>(std::move(caustics), settings_.lookup);
    return rays;
}

size_t PhotonIntegrator::estimatedPeakBytes() const {
    // Stored photons per path of a pilot tracing: all of them, and the caustic ones.
    auto storedPerPath = [&](bool causticOnly) {
        PhotonTracingOptions o = tracingOptions(0, causticOnly);
        o.photons = std::min<uint64_t>(o.photons, kPilotPhotonPaths);
        PhotonTracing pilot = tracePhotons(scene_, accel_, o);
        auto caustics =
            std::count_if(pilot.photons.begin(), pilot.photons.end(),
                          [](const Photon& p) { return p.path == PhotonPath::Caustic; });
        double paths = std::max(1.0, double(o.photons));
        return std::pair{double(pilot.photons.size()) / paths, double(caustics) / paths};
    };
    const auto [all, caustic] = storedPerPath(false);
    double stored = double(settings_.photons) * all;
    stored += settings_.causticPhotons > 0
                  ? double(settings_.causticPhotons) * storedPerPath(true).first
                  : double(settings_.photons) * caustic;
    return photonPassPeakBytes(stored);
}

void PhotonIntegrator::checkMemory(size_t budgetBytes) const {
    bool caustics = settings_.causticPhotons > settings_.photons;
    checkPhotonPeak(estimatedPeakBytes(), budgetBytes,
                    caustics ? "/settings/caustic_photons" : "/settings/photons");
}

size_t PhotonIntegrator::memoryBytes() const {
    return (global_ ? global_->memoryBytes() : 0) + (caustic_ ? caustic_->memoryBytes() : 0);
}

std::optional<SurfaceInteraction> PhotonIntegrator::firstDiffuseHit(Ray& ray, Color& beta,
                                                                    bool& escaped,
                                                                    SampleContext& ctx,
                                                                    int* bounces) const {
    escaped = false;
    for (int depth = 0; depth <= trace_.maxDepth; ++depth) {
        if (bounces) *bounces = depth;
        if (ctx.interrupted()) return std::nullopt;
        std::optional<Hit> hit = intersect(ray, ctx);
        if (!hit) {
            escaped = true;
            return std::nullopt;
        }
        SurfaceInteraction si = scene_.geometry.interaction(ray, *hit);
        // Returned unshaded: the caller shades it (a textured material is never followed).
        const Material& unshaded = *scene_.materials[si.material];
        if (!unshaded.isSpecular() &&
            !(unshaded.lobeRoughness() < float(settings_.followRoughness)))
            return si;
        const Material& m = shade(si, ctx);
        float uc = ctx.sampler.uniform();
        Vec2 u = ctx.sampler.uniform2();
        std::optional<BsdfSample> bs =
            SurfaceBsdf(m, si).sample(-ray.d, uc, u, TransportMode::Radiance);
        if (!bs || isBlack(bs->weight)) return std::nullopt;
        beta *= bs->weight;
        ray = spawnRay(si, bs->wi);
    }
    return std::nullopt;
}

Color PhotonIntegrator::gather(const SurfaceInteraction& x, const Vec3& wo, const Material& m,
                               SampleContext& ctx, std::vector<Neighbor>& scratch,
                               Color& bias) const {
    Color sum(0.0f);
    for (int g = 0; g < settings_.finalGather; ++g) {
        float uc = ctx.sampler.uniform();
        Vec2 u = ctx.sampler.uniform2();
        std::optional<BsdfSample> bs = SurfaceBsdf(m, x).sample(wo, uc, u, TransportMode::Radiance);
        if (!bs || isBlack(bs->weight)) continue;
        Color beta = bs->weight;
        bool escaped = false;
        Ray ray = spawnRay(x, bs->wi);
        std::optional<SurfaceInteraction> y = firstDiffuseHit(ray, beta, escaped, ctx);
        // Emitters seen by gather rays are direct light or caustics at x: counted already.
        if (!y) continue;
        const Material& my = shade(*y, ctx, 1);
        Color b(0.0f);
        sum += beta * global_->reflected(*y, -ray.d, my, passEstimate_, kAllPhotonPaths, scratch,
                                         ctx.trackBias ? &b : nullptr);
        bias += beta * b;
    }
    bias /= float(settings_.finalGather);
    return sum / float(settings_.finalGather);
}

Color PhotonIntegrator::Li(const Ray& ray, SampleContext& ctx) const {
    Color beta(1.0f);
    bool escaped = false;
    Ray in = ray;
    int bounces = 0;
    std::optional<SurfaceInteraction> x = firstDiffuseHit(in, beta, escaped, ctx, &bounces);
    if (!x) return escaped ? beta * scene_.escapedRadiance(in.d) : Color(0.0f);

    const Material& m = shade(*x, ctx);
    Vec3 wo = -in.d;
    thread_local std::vector<Neighbor> scratch;
    Color L = sampleDirectLight(*x, wo, m, ctx);
    if (bounces > 0 || ctx.cameraEmission) L += m.Le(wo, x->n);
    // The bias of both maps' estimates, when the render tracks it.
    Color* const track = ctx.trackBias ? &ctx.bias : nullptr;
    Color bias(0.0f), b(0.0f);
    L += caustic_->reflected(*x, wo, m, passEstimate_, kAllPhotonPaths, scratch,
                             track ? &b : nullptr);
    if (settings_.finalGather > 0)
        L += gather(*x, wo, m, ctx, scratch, bias);
    else
        L += global_->reflected(*x, wo, m, passEstimate_, maskOf(PhotonPath::Indirect), scratch,
                                track ? &bias : nullptr);
    if (track) *track += beta * (b + bias);
    return beta * L;
}

}  // namespace caustic
