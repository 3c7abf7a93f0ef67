// The render loop shared by every integrator: passes of whole-image estimates, rendered in tiles on
// OpenMP threads, accumulated in a Film, stopped by spp, time limit, target error or cancellation.
// Pixel samples are seeded from (seed, pass, pixel, sample), so the image is bit-identical for any
// thread count.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "film/film.h"
#include "render/settings.h"
#include "scene/scene.h"

namespace caustic {

/// Why a render stopped.
enum class StopReason { Spp, TimeLimit, TargetError, Cancelled };
std::string toString(StopReason r);

/// Bytes held by each part of a render, at its end. A part the scene and integrator do not need
/// is never built and shows zero.
struct MemoryStats {
    size_t geometry = 0;     ///< Primitive tables, spheres and quads.
    size_t meshes = 0;       ///< Triangle vertex and index arrays.
    size_t accelerator = 0;  ///< The intersection structure (Embree: the buffers we hand it).
    size_t film = 0;         ///< Pass accumulators and the pass buffer.
    size_t lightTables = 0;  ///< Light selection by power and the emitter index.
    size_t photonMaps = 0;   ///< Photon maps, for the photon-mapping integrators.
    size_t total() const {
        return geometry + meshes + accelerator + film + lightTables + photonMaps;
    }
    nlohmann::json toJson() const;
};

/// What a render cost and how accurate it is.
struct RenderStats {
    double setupSeconds = 0;        ///< acceleratorSeconds + integratorSeconds.
    double acceleratorSeconds = 0;  ///< Building the intersection structure.
    double integratorSeconds = 0;   ///< Preparing the integrator (photon tracing, for example).
    double renderSeconds = 0;       ///< The passes, pass setup included.
    double passSetupSeconds = 0;    ///< Of renderSeconds, preparing passes (photon tracing).
    double totalSeconds = 0;
    uint64_t rays = 0;         ///< Every ray traced: camera, bounce and shadow.
    uint64_t samples = 0;      ///< Camera samples taken (pixels x spp reached).
    double raysPerSecond = 0;  ///< rays / renderSeconds.
    int passes = 0;
    int sppReached = 0;
    double relativeError = 0;     ///< Film::relativeError(); NaN with fewer than 2 passes.
    uint64_t droppedSamples = 0;  ///< NaN or infinite samples left out.
    int threads = 0;
    StopReason stopReason = StopReason::Spp;
    MemoryStats memory;
    nlohmann::json toJson() const;
};

/// Reported during the render, from one thread at a time, at most about every 100 ms and after
/// every pass.
struct RenderProgress {
    int passesDone = 0;
    int passesTotal = 0;
    double fraction = 0;  ///< Of the spp budget, in [0, 1].
    double elapsedSeconds = 0;
    double relativeError = 0;  ///< Of the passes done; NaN before two.
};

struct RenderCallbacks {
    /// Progress; must be cheap and thread-safe (it is called from worker threads, one at a time).
    std::function<void(const RenderProgress&)> onProgress;
    /// After each pass is added to the film, from the calling thread (previews, checkpoints).
    std::function<void(const Film&)> onPass;
    /// Polled between tiles; when it becomes true the render stops, discarding the partial pass.
    const std::atomic<bool>* cancel = nullptr;
    /// Passes already rendered for this same scene and settings (a checkpoint): the render goes on
    /// from pass resume->passes(), and its image is bit-identical to an uninterrupted render's
    /// (passes depend only on their index). The time limit counts from this call.
    const Film* resume = nullptr;
};

struct RenderResult {
    std::unique_ptr<Film> film;
    RenderStats stats;
};

/// Throws InputError naming the setting at fault when the render would need more than
/// settings.memory_limit (what render() checks before its first pass). Builds the accelerator and
/// runs the integrator's pilot to know: for a service to refuse a job before queueing it.
void checkRenderMemory(const Scene& scene, const RenderSettings& settings);

/// Renders `scene` with `settings`. Throws InputError for settings the scene cannot use.
RenderResult render(const Scene& scene, const RenderSettings& settings,
                    const RenderCallbacks& callbacks = {});

}  // namespace caustic
