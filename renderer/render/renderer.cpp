#include "render/renderer.h"

#include <omp.h>

#include <chrono>
#include <mutex>

#include "accel/accelerator.h"
#include "core/error.h"
#include "integrators/integrator.h"

namespace caustic {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

constexpr int kTileSize = 16;

// Estimates every pixel of one tile for one pass; returns false when cancelled before it started.
struct PassRenderer {
    const Scene& scene;
    const Integrator& integrator;
    const RenderSettings& settings;
    int sppPerPass;
    uint32_t pass;
    std::vector<Color>& out;

    // Renders one tile; adds its rays and dropped samples to the counters.
    void tile(int tx, int ty, uint64_t& rays, uint64_t& dropped) const {
        const Camera& camera = scene.camera;
        int x1 = std::min(tx + kTileSize, camera.width());
        int y1 = std::min(ty + kTileSize, camera.height());
        SampleContext ctx;
        for (int y = ty; y < y1; ++y) {
            for (int x = tx; x < x1; ++x) {
                uint64_t pixel = uint64_t(y) * uint64_t(camera.width()) + uint64_t(x);
                DVec3 sum(0.0);  // double: many large finite samples must not overflow
                int valid = 0;
                for (int s = 0; s < sppPerPass; ++s) {
                    ctx.rng = Rng::forSample(settings.seed, pass, pixel, uint64_t(s));
                    Vec2 jitter = ctx.rng.uniform2();
                    Ray ray = camera.generateRay(float(x) + jitter.x, float(y) + jitter.y);
                    Color L = integrator.Li(ray, ctx);
                    // A non-finite sample is a bug or an overflow; keep it out of the image.
                    if (!isFinite(L)) {
                        ++dropped;
                        continue;
                    }
                    sum += DVec3(L);
                    ++valid;
                }
                out[pixel] = valid > 0 ? Color(sum / double(valid)) : Color(0.0f);
            }
        }
        rays += ctx.rays;
    }
};

// Refuses a render that would not fit in settings.memory_limit, before its first pass: what is
// built so far is measured, the film is known from its size, the integrator estimates its peak.
void checkMemory(const Scene& scene, const Accelerator& accel, const Integrator& integrator,
                 const RenderSettings& settings) {
    const size_t limit = settings.memoryLimitBytes();
    const size_t pixels = size_t(scene.camera.width()) * size_t(scene.camera.height());
    // The film's sums and sums of squares in double, and the pass buffer.
    const size_t film = pixels * (6 * sizeof(double) + sizeof(Color));
    const size_t built =
        scene.geometry.memoryBytes() + accel.memoryBytes() + film + scene.lightTableBytes();
    if (built > limit)
        throw InputError("/settings/memory_limit",
                         "the scene, its accelerator and the film already take " +
                             std::to_string(built >> 20) + " MiB, more than the limit of " +
                             std::to_string(limit >> 20) + " MiB");
    integrator.checkMemory(limit - built);
}

}  // namespace

std::string toString(StopReason r) {
    switch (r) {
        case StopReason::Spp:
            return "spp";
        case StopReason::TimeLimit:
            return "time_limit";
        case StopReason::TargetError:
            return "target_error";
        case StopReason::Cancelled:
            return "cancelled";
    }
    return "unknown";
}

nlohmann::json MemoryStats::toJson() const {
    return {{"geometry", geometry},
            {"meshes", meshes},
            {"accelerator", accelerator},
            {"film", film},
            {"light_tables", lightTables},
            {"photon_maps", photonMaps},
            {"total", total()}};
}

nlohmann::json RenderStats::toJson() const {
    auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
    return {{"setup_seconds", setupSeconds},
            {"accelerator_seconds", acceleratorSeconds},
            {"integrator_seconds", integratorSeconds},
            {"render_seconds", renderSeconds},
            {"pass_setup_seconds", passSetupSeconds},
            {"total_seconds", totalSeconds},
            {"rays", rays},
            {"samples", samples},
            {"rays_per_second", raysPerSecond},
            {"passes", passes},
            {"spp", sppReached},
            {"relative_error", number(relativeError)},
            {"dropped_samples", droppedSamples},
            {"threads", threads},
            {"stop_reason", toString(stopReason)},
            {"memory", memory.toJson()}};
}

void checkRenderMemory(const Scene& scene, const RenderSettings& settings) {
    std::unique_ptr<Accelerator> accel = createAccelerator(settings.accelerator, scene.geometry);
    checkMemory(scene, *accel, *createIntegrator(scene, *accel, settings), settings);
}

RenderResult render(const Scene& scene, const RenderSettings& settings,
                    const RenderCallbacks& callbacks) {
    auto t0 = Clock::now();
    RenderResult result;
    RenderStats& stats = result.stats;
    const int width = scene.camera.width(), height = scene.camera.height();

    // Build what this render needs.
    std::unique_ptr<Accelerator> accel = createAccelerator(settings.accelerator, scene.geometry);
    stats.acceleratorSeconds = secondsSince(t0);
    auto tIntegrator = Clock::now();
    std::unique_ptr<Integrator> integrator = createIntegrator(scene, *accel, settings);
    result.film = std::make_unique<Film>(width, height);
    Film& film = *result.film;
    if (callbacks.resume) {
        if (callbacks.resume->width() != width || callbacks.resume->height() != height)
            throw InputError("/scene/camera", "the checkpoint to resume is " +
                                                  std::to_string(callbacks.resume->width()) + "x" +
                                                  std::to_string(callbacks.resume->height()) +
                                                  ", the camera " + std::to_string(width) + "x" +
                                                  std::to_string(height));
        film = *callbacks.resume;
    }
    checkMemory(scene, *accel, *integrator, settings);
    stats.integratorSeconds = secondsSince(tIntegrator);
    stats.setupSeconds = secondsSince(t0);

    const int threads = settings.threads > 0 ? settings.threads : omp_get_max_threads();
    const int sppPerPass = settings.resolvedSppPerPass();
    const int passesTotal = (settings.spp + sppPerPass - 1) / sppPerPass;
    const int tilesX = (width + kTileSize - 1) / kTileSize;
    const int tilesY = (height + kTileSize - 1) / kTileSize;
    const int tileCount = tilesX * tilesY;
    stats.threads = threads;

    auto tRender = Clock::now();
    std::vector<Color> passImage(size_t(width) * size_t(height));
    std::mutex progressMutex;
    auto lastProgress = Clock::now();
    auto cancelled = [&] { return callbacks.cancel && callbacks.cancel->load(); };
    auto overTime = [&] {
        return settings.timeLimit > 0 && film.passes() > 0 &&
               secondsSince(tRender) >= settings.timeLimit;
    };
    auto report = [&](double fraction) {
        if (!callbacks.onProgress) return;
        RenderProgress p;
        p.passesDone = film.passes();
        p.passesTotal = passesTotal;
        p.fraction = std::clamp(fraction, 0.0, 1.0);
        p.elapsedSeconds = secondsSince(tRender);
        p.relativeError = film.relativeError();
        callbacks.onProgress(p);
    };

    auto reachedTarget = [&] {
        return settings.targetError > 0 && film.passes() >= 2 &&
               film.relativeError() <= settings.targetError;
    };
    // A resumed render that had reached its target stops where it did.
    bool stopped = reachedTarget();
    if (stopped) stats.stopReason = StopReason::TargetError;
    for (int pass = film.passes(); pass < passesTotal && !stopped; ++pass) {
        auto tPass = Clock::now();
        stats.rays += integrator->beginPass(uint32_t(pass));
        stats.passSetupSeconds += secondsSince(tPass);
        PassRenderer renderer{scene, *integrator, settings, sppPerPass, uint32_t(pass), passImage};
        std::atomic<int> tilesDone{0};
        std::atomic<bool> abandon{false};
        uint64_t rays = 0, dropped = 0;

#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+ : rays, dropped)
        for (int t = 0; t < tileCount; ++t) {
            if (abandon.load(std::memory_order_relaxed)) continue;
            if (cancelled() || overTime()) {
                abandon = true;
                continue;
            }
            renderer.tile((t % tilesX) * kTileSize, (t / tilesX) * kTileSize, rays, dropped);
            int done = ++tilesDone;
            // Throttled progress from whichever thread gets the lock.
            std::unique_lock lock(progressMutex, std::try_to_lock);
            if (lock && secondsSince(lastProgress) > 0.1) {
                lastProgress = Clock::now();
                report((pass + double(done) / tileCount) / passesTotal);
            }
        }
        stats.rays += rays;
        if (abandon) {
            // A partial pass is not an estimate of the image: leave it out.
            stats.stopReason = cancelled() ? StopReason::Cancelled : StopReason::TimeLimit;
            break;
        }
        film.addPass(passImage);
        film.addDropped(dropped);
        report(double(pass + 1) / passesTotal);
        if (callbacks.onPass) callbacks.onPass(film);

        // Stopping rules, after whole passes.
        if (cancelled()) {
            stats.stopReason = StopReason::Cancelled;
            stopped = true;
        } else if (reachedTarget()) {
            stats.stopReason = StopReason::TargetError;
            stopped = true;
        } else if (settings.timeLimit > 0 && secondsSince(tRender) >= settings.timeLimit &&
                   pass + 1 < passesTotal) {
            stats.stopReason = StopReason::TimeLimit;
            stopped = true;
        }
    }

    stats.renderSeconds = secondsSince(tRender);
    stats.totalSeconds = secondsSince(t0);
    stats.passes = film.passes();
    stats.sppReached = film.passes() * sppPerPass;
    stats.samples = uint64_t(stats.sppReached) * uint64_t(width) * uint64_t(height);
    stats.raysPerSecond = stats.renderSeconds > 0 ? double(stats.rays) / stats.renderSeconds : 0;
    stats.relativeError = film.relativeError();
    stats.droppedSamples = film.droppedSamples();

    MemoryStats& memory = stats.memory;
    memory.meshes = scene.geometry.meshBytes();
    memory.geometry = scene.geometry.memoryBytes() - memory.meshes;
    memory.accelerator = accel->memoryBytes();
    memory.film = film.memoryBytes() + passImage.capacity() * sizeof(Color);
    memory.lightTables = scene.lightTableBytes();
    memory.photonMaps = integrator->memoryBytes();
    return result;
}

}  // namespace caustic
