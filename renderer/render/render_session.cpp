#include "render/render_session.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "core/error.h"
#include "render/forecast.h"
#include "render/integrator_factory.h"
#include "render/memory_estimate.h"
#include "render/sample_map.h"

namespace caustic {
namespace {

using Clock = Interrupt::Clock;

constexpr int kTileSize = 16;

// The share of a pixel's footprint a texture lookup filters over when the pixel takes `rays`
// camera rays: 1 / sqrt(rays) (pbrt-v4's scaling of ray differentials by the samples per pixel),
// no less than 1/8.
float footprintScale(double rays) {
    return float(std::clamp(1.0 / std::sqrt(std::max(rays, 1.0)), 0.125, 1.0));
}

// Estimates every pixel of one tile for one pass, into `out`.
struct TileRenderer {
    const Scene& scene;
    const Integrator& integrator;
    const RenderSettings& settings;
    const Interrupt& interrupt;
    int sppPerPass;
    uint32_t pass;
    const std::vector<uint16_t>* sampleMap;  ///< Samples per pixel; null for sppPerPass each.
    const SeenEmission* seen;                ///< Null: each sample's own ray sees emission.
    /// The pass: width x height pixels, then as many of their bias when the integrator estimates
    /// it (Film's bias layer).
    std::vector<Color>& out;

    // The emission seen directly through pixel (x, y), from the sample's own points.
    Color seenEmission(const Sampler& sampler, int x, int y, uint64_t& rays) const {
        const uint32_t k = uint32_t(settings.emissionSamples);
        // An emissive texture seen here is filtered over the share of the pixel each of the
        // pixel's spp x k rays covers, as a material's textures are over 1 / sqrt(spp).
        const float footprint = footprintScale(double(settings.spp) * k);
        Color sum(0.0f);
        for (uint32_t j = 0; j < k; ++j) {
            Vec2 p = sampler.pixelPoint(j, k);
            sum += seen->along(scene.camera.generateRay(float(x) + p.x, float(y) + p.y), rays,
                               footprint);
        }
        return sum / float(k);
    }

    // The pixel's samples in the passes before this one, which takes `samples`: the uniform
    // passes' (all of them, or the adaptive pilot's) and, after the pilot, its share of the map's.
    uint32_t samplesBefore(int samples) const {
        if (!sampleMap) return pass * uint32_t(sppPerPass);
        return uint32_t(kAdaptivePilotPasses * sppPerPass) +
               (pass - uint32_t(kAdaptivePilotPasses)) * uint32_t(samples);
    }

    // Renders one tile; adds its rays and dropped samples to the counters.
    void tile(int tx, int ty, uint64_t& rays, uint64_t& dropped) const {
        const Camera& camera = scene.camera;
        int x1 = std::min(tx + kTileSize, camera.width());
        int y1 = std::min(ty + kTileSize, camera.height());
        SampleContext ctx;
        ctx.interrupt = InterruptPoller(&interrupt);
        ctx.cameraEmission = seen == nullptr;
        ctx.footprintScale = footprintScale(double(settings.spp));
        ctx.trackBias = integrator.estimatesBias();
        const size_t pixels = size_t(camera.width()) * size_t(camera.height());
        for (int y = ty; y < y1; ++y) {
            for (int x = tx; x < x1; ++x) {
                uint64_t pixel = uint64_t(y) * uint64_t(camera.width()) + uint64_t(x);
                DVec3 sum(0.0), biasSum(0.0);  // double: large finite samples must not overflow
                int valid = 0;
                const int samples = sampleMap ? (*sampleMap)[pixel] : sppPerPass;
                const uint32_t before = samplesBefore(samples);
                const bool seenHere = seen && seen->mayBeSeenIn(x, y);
                for (int s = 0; s < samples; ++s) {
                    if (ctx.interrupted()) break;  // the pass is dropped
                    ctx.sampler = Sampler::forSample(settings.sampler, settings.seed, pass, pixel,
                                                     uint32_t(s), uint32_t(samples), before);
                    Vec2 jitter = ctx.sampler.uniform2();
                    Ray ray = camera.generateRay(float(x) + jitter.x, float(y) + jitter.y);
                    ctx.bias = Color(0.0f);
                    Color L = integrator.Li(ray, ctx);
                    if (seenHere) L += seenEmission(ctx.sampler, x, y, ctx.rays);
                    // A non-finite sample is a bug or an overflow; keep it out of the image.
                    if (!isFinite(L) || !isFinite(ctx.bias)) {
                        ++dropped;
                        continue;
                    }
                    sum += DVec3(L);
                    biasSum += DVec3(ctx.bias);
                    ++valid;
                }
                out[pixel] = valid > 0 ? Color(sum / double(valid)) : Color(0.0f);
                if (ctx.trackBias)
                    out[pixels + pixel] = valid > 0 ? Color(biasSum / double(valid)) : Color(0.0f);
            }
        }
        rays += ctx.rays;
    }
};

}  // namespace

RenderSession::RenderSession(const Scene& scene, const RenderSettings& settings,
                             const Interrupt* interrupt)
    : scene_(scene),
      settings_(settings),
      sppPerPass_(settings.resolvedSppPerPass()),
      passesTotal_(settings.passesTotal()),
      threads_(settings.threads > 0 ? settings.threads : omp_get_max_threads()) {
    // Build what this render needs.
    auto t0 = Clock::now();
    accel_ = createAccelerator(settings_.accelerator, scene_.geometry);
    acceleratorSeconds_ = secondsSince(t0);
    auto t1 = Clock::now();
    integrator_ = createIntegrator(scene_, *accel_, settings_);
    if (settings_.emissionSamples > 0 && !scene_.emitterPrims.empty())
        seen_ = std::make_unique<SeenEmission>(scene_, *accel_);
    integrator_->setInterrupt(interrupt);
    checkMemory();
    integrator_->setInterrupt(nullptr);
    if (interrupt && interrupt->requested()) throw RenderCancelled();
    // The image, then (with the bias layer) its bias.
    passImage_.resize(size_t(scene_.camera.width()) * size_t(scene_.camera.height()) *
                      (integrator_->estimatesBias() ? 2 : 1));
    integratorSeconds_ = secondsSince(t1);
}

std::unique_ptr<Film> RenderSession::makeFilm() const {
    return std::make_unique<Film>(scene_.camera.width(), scene_.camera.height(),
                                  integrator_->estimatesBias());
}

// Refuses a render that would not fit in settings.memory_limit, before its first pass: what is
// built so far is measured, the film is known from its size, the integrator estimates its peak.
void RenderSession::checkMemory() const {
    const size_t limit = settings_.memoryLimitBytes();
    const int width = scene_.camera.width(), height = scene_.camera.height();
    const size_t film = filmBytes(width, height, settings_.adaptive, integrator_->estimatesBias());
    const size_t built = scene_.geometry.memoryBytes() + accel_->memoryBytes() + film +
                         scene_.lightTableBytes() + scene_.textureBytes;
    if (built > limit)
        throw InputError("/settings/memory_limit",
                         "the scene, its accelerator and the film already take " +
                             std::to_string(built >> 20) + " MiB, more than the limit of " +
                             std::to_string(limit >> 20) + " MiB");
    integrator_->checkMemory(limit - built);
}

bool RenderSession::renderPass(int pass, const Interrupt& interrupt, uint64_t& rays,
                               uint64_t& dropped, const std::function<void(double)>& tileDone) {
    const int tilesX = (scene_.camera.width() + kTileSize - 1) / kTileSize;
    const int tilesY = (scene_.camera.height() + kTileSize - 1) / kTileSize;
    const int tileCount = tilesX * tilesY;
    const bool mapped = settings_.adaptive && pass >= kAdaptivePilotPasses && !sampleMap_.empty();
    TileRenderer renderer{scene_,
                          *integrator_,
                          settings_,
                          interrupt,
                          sppPerPass_,
                          uint32_t(pass),
                          mapped ? &sampleMap_ : nullptr,
                          seen_.get(),
                          passImage_};
    std::atomic<int> tilesDone{0};
    std::atomic<bool> abandon{false};
    uint64_t passRays = 0, passDropped = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_) \
    reduction(+ : passRays, passDropped)
    for (int t = 0; t < tileCount; ++t) {
        if (abandon.load(std::memory_order_relaxed)) continue;
        if (interrupt.requested()) {
            abandon = true;
            continue;
        }
        renderer.tile((t % tilesX) * kTileSize, (t / tilesX) * kTileSize, passRays, passDropped);
        int done = ++tilesDone;
        if (tileDone) tileDone(double(done) / tileCount);
    }
    rays += passRays;
    dropped = passDropped;
    // A tile's paths may have stopped early too: whatever asked, the pass is not whole.
    return !abandon && !interrupt.requested();
}

RangeResult RenderSession::renderRange(int first, int last, Film& film,
                                       const RenderCallbacks& callbacks) {
    if (first < 0 || first > last || last > passesTotal_ || film.passSet().overlaps(first, last))
        throw std::invalid_argument("cannot render passes " + std::to_string(first) + " to " +
                                    std::to_string(last) + " of " + std::to_string(passesTotal_) +
                                    " onto a film holding " + film.passSet().toString());
    auto t0 = Clock::now();
    RangeResult result;
    StopRules rules(settings_, callbacks.cancel, callbacks.timeLimit);
    rules.start(film);
    integrator_->setInterrupt(&rules.interrupt());
    // The rules live on this stack: the integrator must not keep them past this call.
    struct Detach {
        Integrator& integrator;
        ~Detach() { integrator.setInterrupt(nullptr); }
    } detach{*integrator_};
    std::mutex progressMutex;
    auto lastProgress = Clock::now();
    // The render so far, pass by pass, for the forecast of its end; from the film it starts with.
    std::vector<ProgressPoint> history{{film.passes(), rules.elapsed(), film.relativeError()}};
    std::optional<StopForecast> forecast;
    auto report = [&](double passFraction) {
        if (!callbacks.onProgress) return;
        RenderProgress p;
        p.passesDone = film.passes();
        p.passesTotal = passesTotal_;
        p.fraction = std::clamp((film.passes() + passFraction) / passesTotal_, 0.0, 1.0);
        p.elapsedSeconds = rules.elapsed();
        p.relativeError = film.relativeError();
        if (forecast) {
            // Counted down from the last pass's end.
            p.etaSeconds =
                std::max(0.0, forecast->secondsLeft - (p.elapsedSeconds - history.back().seconds));
            p.etaReason = forecast->reason;
        } else if (passFraction > 0) {
            // Within the first pass: the range at the pace of this pass so far.
            const double passes = last - film.passes() - passFraction;
            p.etaSeconds = (p.elapsedSeconds - history.back().seconds) / passFraction * passes;
            if (settings_.timeLimit > 0 && settings_.timeLimit - p.elapsedSeconds < p.etaSeconds) {
                p.etaSeconds = std::max(0.0, settings_.timeLimit - p.elapsedSeconds);
                p.etaReason = StopReason::TimeLimit;
            }
        }
        callbacks.onProgress(p);
    };
    // Throttled progress from whichever thread gets the lock.
    auto tileDone = [&](double passFraction) {
        std::unique_lock lock(progressMutex, std::try_to_lock);
        if (lock && secondsSince(lastProgress) > 0.1) {
            lastProgress = Clock::now();
            report(passFraction);
        }
    };

    // A resumed render that had reached its target stops where it did.
    std::optional<StopReason> stop;
    if (reachedTargetError(film, settings_.targetError)) stop = StopReason::TargetError;
    for (int pass = first; pass < last && !stop; ++pass) {
        if (settings_.adaptive && pass >= kAdaptivePilotPasses && sampleMap_.empty() &&
            !prepareSampleMap(film, rules.interrupt(), result.rays)) {
            stop = rules.interruptReason();
            break;
        }
        auto tPass = Clock::now();
        result.rays += integrator_->beginPass(uint32_t(pass));
        result.passSetupSeconds += secondsSince(tPass);
        uint64_t dropped = 0;
        if (rules.interrupt().requested() ||
            !renderPass(pass, rules.interrupt(), result.rays, dropped, tileDone)) {
            // A partial pass is not an estimate of the image: leave it out.
            stop = rules.interruptReason();
            break;
        }
        if (callbacks.onPassImage) callbacks.onPassImage(pass, passImage_, dropped);
        film.addPass(pass, passImage_, dropped, threads_);
        history.push_back({film.passes(), rules.elapsed(), film.relativeError()});
        forecast =
            forecastStop(history, last, film.passSet().isPrefix() ? settings_.targetError : 0.0,
                         settings_.timeLimit, minPassesForTarget(film));
        report(0.0);
        if (callbacks.onPass) callbacks.onPass(film);
        stop = rules.afterPass(film, pass + 1 < last);
    }
    result.stopReason = stop.value_or(StopReason::Spp);
    result.renderSeconds = secondsSince(t0);
    return result;
}

bool RenderSession::prepareSampleMap(const Film& film, const Interrupt& interrupt, uint64_t& rays) {
    if (film.passSet().isPrefix() && film.passes() == kAdaptivePilotPasses) {
        sampleMap_ = adaptiveSampleMap(film, sppPerPass_);
        return true;
    }
    // This range starts past the pilot (another worker's, or a resumed render's): render the pilot
    // again. Deterministic, so this map is the one every other range has.
    Film pilot(film.width(), film.height(), film.tracksBias());
    for (int p = 0; p < kAdaptivePilotPasses; ++p) {
        rays += integrator_->beginPass(uint32_t(p));
        uint64_t dropped = 0;
        if (interrupt.requested() || !renderPass(p, interrupt, rays, dropped, {})) return false;
        pilot.addPass(p, passImage_, dropped, threads_);
    }
    sampleMap_ = adaptiveSampleMap(pilot, sppPerPass_);
    return true;
}

MemoryStats RenderSession::memory(const Film& film) const {
    MemoryStats memory;
    memory.meshes = scene_.geometry.meshBytes();
    memory.geometry = scene_.geometry.memoryBytes() - memory.meshes;
    memory.accelerator = accel_->memoryBytes();
    memory.film = film.memoryBytes() + passImage_.capacity() * sizeof(Color) +
                  sampleMap_.capacity() * sizeof(uint16_t);
    memory.lightTables = scene_.lightTableBytes();
    memory.photonMaps = integrator_->memoryBytes();
    if (scene_.textures) memory.textures = size_t(scene_.textures->stats().memoryUsed);
    return memory;
}

}  // namespace caustic
