#include "jobs/worker_pool.h"

#include <chrono>
#include <cmath>

#include <spdlog/spdlog.h>

#include "core/error.h"
#include "gltf/scene_document.h"
#include "jobs/asset_service.h"
#include "jobs/pass_recorder.h"
#include "render/renderer.h"
#include "render/resolution.h"
#include "scene/scene.h"
#include "store/storage_full.h"

namespace caustic::server {

namespace {

std::string timeLimitError(const RenderSettings& settings) {
    return "/settings/time_limit: no pass finished within the time limit of " +
           Json(settings.timeLimit).dump() +
           " s; raise time_limit, or lower spp_per_pass or photons";
}

}  // namespace

WorkerPool::WorkerPool(const ServerConfig& config, JobStore& store, const JobFiles& files,
                       JobEvents& events, RenderCounters& counters, std::string owner)
    : config_(config),
      store_(store),
      files_(files),
      events_(events),
      counters_(counters),
      owner_(std::move(owner)) {}

WorkerPool::~WorkerPool() {
    stop();
}

void WorkerPool::start() {
    for (int i = 0; i < std::max(1, config_.workers); ++i) threads_.emplace_back([this] { run(); });
}

void WorkerPool::stop() {
    stopping_ = true;
    wake_.notify_all();
    for (std::thread& t : threads_)
        if (t.joinable()) t.join();
    threads_.clear();
}

void WorkerPool::wake() {
    wake_.notify_one();
}

void WorkerPool::run() {
    while (!stopping_) {
        std::optional<Job> job;
        try {
            job = store_.claim(owner_, unixNow(), config_.leaseSeconds, config_.maxStalledLeases,
                               config_.maxAttempts);
        } catch (const std::exception& e) {
            spdlog::error("claiming a job: {}", e.what());
        }
        if (!job) {
            // Poll now and then as well: leases of other owners expire without a wake-up.
            std::unique_lock lock(mutex_);
            wake_.wait_for(lock, std::chrono::milliseconds(500));
            continue;
        }
        events_.notify();
        renderJob(*job);
        events_.notify();
    }
}

void WorkerPool::renderJob(const Job& job) {
    Outcome outcome;
    bool lost = false;
    {
        LeaseKeeper lease(store_, config_, job.id, job.attempt, stopping_);
        outcome = renderLeased(job, lease);
        lost = lease.lost;
    }  // the lease is no longer renewed from here
    events_.clearLive(job.id);
    // A render stopped by the server's own shutdown or a lost lease is not the job's outcome: it
    // stays running until its lease expires, then goes back to the queue.
    if (lost || (stopping_ && outcome.state == JobState::Cancelled)) {
        // Deleted while it rendered: its last checkpoint or preview may have been written after
        // the files were removed.
        if (lost && !store_.get(job.id)) files_.remove(job.id);
        return;
    }
    try {
        if (store_.finish(job.id, job.attempt, outcome.state, outcome.stats, outcome.error,
                          unixNow()) &&
            outcome.state == JobState::Succeeded)
            files_.removeCheckpoint(job.id);
        spdlog::info("job {} {}{}{}", job.id, toString(outcome.state),
                     outcome.error.empty() ? "" : ": ", outcome.error);
    } catch (const std::exception& e) {
        spdlog::error("finishing job {}: {}", job.id, e.what());
    }
}

WorkerPool::Outcome WorkerPool::renderLeased(const Job& job, LeaseKeeper& lease) {
    Outcome outcome;
    RenderSettings settings;
    const auto started = Interrupt::Clock::now();
    try {
        // The scene, settings and session are made once per attempt.
        SceneOptions options;
        options.assetsDir = config_.assetsDir;
        options.resolveMeshAsset = storedAssets(store_);
        options.textures = textures_;
        std::unique_ptr<Scene> scene = loadSceneDocument(job.scene, options);
        settings = parseSettings(job.settings);
        applyResolution(*scene, settings, options);
        // The memory check's pilot stops at a cancel and at the time limit, as passes do.
        Interrupt setup(&lease.cancel);
        if (settings.timeLimit > 0)
            setup.setDeadline(fromNow(settings.timeLimit - secondsRendered(job)));
        RenderSession session(*scene, settings, &setup);
        std::unique_ptr<Film> film =
            files_.readCheckpoint(job.id, scene->camera.width(), scene->camera.height());
        if (!film) film = session.makeFilm();
        PassRecorder recorder(store_, files_, events_, lease, job, settings, session.passesTotal(),
                              counters_.passes);
        recorder.catchUp(*film);

        RenderStats stats = renderPasses(session, *film, recorder.callbacks());
        counters_.rays += stats.rays;
        counters_.renderSeconds.fetch_add(stats.renderSeconds);
        counters_.lastRaysPerSecond = stats.raysPerSecond;
        if (stats.stopReason == StopReason::TimeLimit && film->passes() == 0) {
            outcome.error = timeLimitError(settings);
        } else if (stats.stopReason == StopReason::Cancelled) {
            outcome.state = JobState::Cancelled;
            outcome.error = "cancelled";
        } else {
            files_.writeImage(job.id, job.attempt, "image.exr", *film, 0.0);
            files_.writeImage(job.id, job.attempt, "image.png", *film, settings.exposure);
            files_.writeImage(job.id, job.attempt, "preview.png", *film, settings.exposure);
            outcome.state = JobState::Succeeded;
        }
        // This attempt's wall time: loading, setup, the passes and the images.
        stats.totalSeconds = secondsSince(started);
        outcome.stats = stats.toJson();
    } catch (const RenderCancelled&) {
        // Before the first pass: cancelled, or out of time in the memory check's pilot.
        if (lease.cancel) {
            outcome.state = JobState::Cancelled;
            outcome.error = "cancelled";
        } else {
            outcome.error = timeLimitError(settings);
        }
    } catch (const InputError& e) {
        outcome.error = e.what();
    } catch (const StorageFull& e) {
        // A full disk fails the job rather than holding a worker for as long as it stays full
        // (docs/operations.md, "A full disk"). The write that failed left nothing behind (a
        // temporary file and a rename; a rolled-back transaction); the job's other files go too,
        // which frees their space for the store to record the failure. Not when the lease is lost:
        // the files are then another attempt's.
        if (!lease.lost) files_.remove(job.id);
        outcome.error = std::string(e.what()) + "; free space and submit the job again";
    } catch (const std::exception& e) {
        outcome.error = std::string("render failed: ") + e.what();
    }
    return outcome;
}

}  // namespace caustic::server
