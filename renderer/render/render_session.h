// A render session: what one job needs, built once from a loaded scene and its resolved settings
// (the accelerator, the integrator and its light and photon budgets, the memory check), which
// renders any pass range [first, last) of the image into a film. The CLI, the server's workers
// and separate worker processes all render through it. Pass p depends only on (scene, settings,
// p): ranges rendered anywhere merge into the film of one render (film/film.h).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <vector>

#include "accel/accelerator.h"
#include "film/film.h"
#include "integrators/integrator.h"
#include "render/render_stats.h"
#include "render/seen_emission.h"
#include "render/settings.h"
#include "render/stopping.h"
#include "scene/scene.h"

namespace caustic {

/// Reported during the render, from one thread at a time, at most about every 100 ms and after
/// every pass.
struct RenderProgress {
    int passesDone = 0;
    int passesTotal = 0;
    double fraction = 0;  ///< Of the pass budget, in [0, 1].
    double elapsedSeconds = 0;
    double relativeError = 0;  ///< Of the passes done; NaN before two.
    /// Seconds until the render stops (render/forecast.h), and the rule it expects to stop it;
    /// -1 while unknown.
    double etaSeconds = -1;
    StopReason etaReason = StopReason::Spp;
};

struct RenderCallbacks {
    /// Progress; must be cheap and thread-safe (it is called from worker threads, one at a time).
    std::function<void(const RenderProgress&)> onProgress;
    /// After each pass is added to the film, from the calling thread (previews, checkpoints).
    std::function<void(const Film&)> onPass;
    /// Each finished pass's image and dropped samples, before it is added to the film (for a
    /// merge that must replay passes in order, see target_error_merge.h).
    /// Called from the rendering thread; the image is valid during the call only.
    std::function<void(int pass, const std::vector<Color>& image, uint64_t dropped)> onPassImage;
    /// Polled between tiles and inside paths; when it becomes true the render stops, discarding
    /// the partial pass.
    const std::atomic<bool>* cancel = nullptr;
    /// Earlier attempts' seconds, and whether the limit cuts a first pass too (stopping.h).
    TimeLimitOptions timeLimit;
};

/// What rendering a range did.
struct RangeResult {
    StopReason stopReason = StopReason::Spp;
    uint64_t rays = 0;
    double renderSeconds = 0;     ///< The passes, their setup included.
    double passSetupSeconds = 0;  ///< Of renderSeconds, preparing passes (photon tracing).
};

class RenderSession {
public:
    /// Builds the accelerator and the integrator and checks the memory limit (the photon
    /// integrators trace a pilot). Throws InputError naming the setting at fault, and
    /// RenderCancelled when `interrupt` (may be null) stopped the pilot. `scene` must outlive the
    /// session.
    RenderSession(const Scene& scene, const RenderSettings& settings,
                  const Interrupt* interrupt = nullptr);

    const Scene& scene() const { return scene_; }
    const RenderSettings& settings() const { return settings_; }
    int sppPerPass() const { return sppPerPass_; }
    /// Passes in the spp budget: ceil(spp / sppPerPass).
    int passesTotal() const { return passesTotal_; }
    int threads() const { return threads_; }
    double acceleratorSeconds() const { return acceleratorSeconds_; }
    double integratorSeconds() const { return integratorSeconds_; }

    /// An empty film of the camera's size.
    std::unique_ptr<Film> makeFilm() const;
    /// Renders passes [first, last), 0 <= first <= last <= passesTotal(), onto `film` (which
    /// must hold none of them; std::invalid_argument otherwise, before any work), stopping early
    /// by the settings' time limit (counted from this call, see RenderCallbacks::timeLimit), target
    /// error and `callbacks.cancel`. A pass cut short is left out. Uses `threads()` OpenMP
    /// threads; not reentrant (one range at a time per session).
    RangeResult renderRange(int first, int last, Film& film, const RenderCallbacks& callbacks);
    /// Bytes of each part, `film` included.
    MemoryStats memory(const Film& film) const;

private:
    /// Renders pass `pass` into passImage_ on every thread; false when `interrupt` cut it short.
    bool renderPass(int pass, const Interrupt& interrupt, uint64_t& rays, uint64_t& dropped,
                    const std::function<void(double)>& tileDone);
    void checkMemory() const;
    /// With adaptive sampling, the sample map of the passes after the pilot (render/sample_map.h):
    /// from `film` when it holds exactly the pilot, else from the pilot rendered again; false
    /// when `interrupt` cut that short.
    bool prepareSampleMap(const Film& film, const Interrupt& interrupt, uint64_t& rays);

    const Scene& scene_;
    RenderSettings settings_;
    int sppPerPass_, passesTotal_, threads_;
    std::unique_ptr<Accelerator> accel_;
    std::unique_ptr<Integrator> integrator_;
    std::unique_ptr<SeenEmission> seen_;  // null with emission_samples 0 or nothing emitting
    std::vector<Color> passImage_;
    std::vector<uint16_t> sampleMap_;  ///< Samples per pixel after the pilot; empty before.
    double acceleratorSeconds_ = 0, integratorSeconds_ = 0;
};

}  // namespace caustic
