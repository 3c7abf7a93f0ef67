#include "jobs/worker_pool.h"

#include <chrono>
#include <cmath>
#include <iostream>

#include "core/error.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace caustic::server {

double unixNow() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}

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
            std::cerr << "caustic serve: claiming a job: " << e.what() << "\n";
        }
        if (!job) {
            // Poll now and then as well: leases of other owners expire without a wake-up.
            std::unique_lock lock(mutex_);
            wake_.wait_for(lock, std::chrono::milliseconds(500));
            continue;
        }
        events_.notify();
        renderJob(std::move(*job));
        events_.notify();
    }
}

void WorkerPool::renderJob(Job job) {
    const std::string id = job.id;
    const int attempt = job.attempt;
    std::atomic<bool> cancel{false};
    std::atomic<bool> lost{false};
    std::atomic<bool> done{false};

    // Heartbeats: renew the lease a few times per lease period; learn of cancellation.
    std::thread heartbeat([&] {
        const auto period = std::chrono::duration<double>(std::min(1.0, config_.leaseSeconds / 4));
        auto last = std::chrono::steady_clock::now();
        while (!done) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            if (stopping_) cancel = true;
            if (std::chrono::steady_clock::now() - last < period) continue;
            last = std::chrono::steady_clock::now();
            LeaseStatus s = LeaseStatus::Held;
            try {
                s = store_.heartbeat(id, attempt, unixNow(), config_.leaseSeconds);
            } catch (const std::exception&) {
                continue;  // the store is busy: try again at the next beat
            }
            if (s == LeaseStatus::Lost) lost = true;
            if (s != LeaseStatus::Held) cancel = true;
        }
    });

    // Earlier attempts' time, so that the convergence log's seconds run on across restarts.
    double priorSeconds = 0;
    if (!job.convergence.empty() && job.convergence.back().contains("seconds"))
        priorSeconds = job.convergence.back()["seconds"].get<double>();

    JobState outcome = JobState::Failed;
    std::string error;
    Json stats;
    try {
        SceneOptions options;
        options.assetsDir = config_.assetsDir;
        std::unique_ptr<Scene> scene = loadScene(job.scene, options);
        RenderSettings settings = parseSettings(job.settings);
        std::unique_ptr<Film> checkpoint =
            files_.readCheckpoint(id, scene->camera.width(), scene->camera.height());
        const int sppPerPass = settings.resolvedSppPerPass();
        const int passesTotal = (settings.spp + sppPerPass - 1) / sppPerPass;
        // Clients see the passes in the store. A checkpoint is written before its pass is
        // recorded, so a kill between the two leaves the checkpoint ahead: record it first, so
        // that passes_done never goes back.
        auto record = [&](const Film& film, double seconds, double eta) {
            double passError = film.relativeError();
            Json point{
                {"pass", film.passes()},
                {"seconds", seconds},
                {"relative_error", std::isfinite(passError) ? Json(passError) : Json(nullptr)}};
            return store_.recordPass(id, attempt, double(film.passes()) / passesTotal,
                                     film.passes(), passesTotal, passError, eta, point);
        };
        if (checkpoint && checkpoint->passes() > job.passesDone &&
            !record(*checkpoint, priorSeconds, -1))
            lost = cancel = true;

        auto started = std::chrono::steady_clock::now();
        auto lastPreview = started - std::chrono::hours(1);
        auto seconds = [&] {
            return std::chrono::duration<double>(std::chrono::steady_clock::now() - started)
                .count();
        };
        RenderCallbacks callbacks;
        callbacks.cancel = &cancel;
        callbacks.resume = checkpoint.get();
        callbacks.onProgress = [&](const RenderProgress& p) {
            LiveProgress live{p.fraction, p.passesTotal, p.relativeError, -1};
            // The spp budget at the rate so far, or the time limit if that comes first (a target
            // error may stop it sooner still; that cannot be foreseen).
            if (p.fraction > 0 && p.elapsedSeconds > 0)
                live.etaSeconds = p.elapsedSeconds * (1 - p.fraction) / p.fraction;
            if (settings.timeLimit > 0) {
                double left = std::max(0.0, settings.timeLimit - p.elapsedSeconds);
                live.etaSeconds = live.etaSeconds < 0 ? left : std::min(live.etaSeconds, left);
            }
            events_.setLive(id, live);
        };
        callbacks.onPass = [&](const Film& film) {
            if (lost) return;
            files_.writeCheckpoint(id, film);
            // The preview at most twice a second (the final image is written anyway), and before
            // the pass is recorded: a client told of a pass finds its preview.
            if (std::chrono::steady_clock::now() - lastPreview > std::chrono::milliseconds(500)) {
                files_.writeImage(id, "preview.png", film, settings.exposure);
                lastPreview = std::chrono::steady_clock::now();
            }
            std::optional<LiveProgress> live = events_.live(id);
            if (!record(film, priorSeconds + seconds(), live ? live->etaSeconds : -1)) {
                lost = cancel = true;
                return;
            }
            counters_.passes++;
            events_.notify();
        };
        RenderResult result = render(*scene, settings, callbacks);
        counters_.rays += result.stats.rays;
        counters_.renderSeconds = counters_.renderSeconds + result.stats.renderSeconds;
        counters_.lastRaysPerSecond = result.stats.raysPerSecond;
        stats = result.stats.toJson();
        if (result.stats.stopReason == StopReason::Cancelled) {
            outcome = JobState::Cancelled;
            error = "cancelled";
        } else {
            files_.writeImage(id, "image.exr", *result.film, 0.0);
            files_.writeImage(id, "image.png", *result.film, settings.exposure);
            files_.writeImage(id, "preview.png", *result.film, settings.exposure);
            outcome = JobState::Succeeded;
        }
    } catch (const InputError& e) {
        error = e.what();
    } catch (const std::exception& e) {
        error = std::string("render failed: ") + e.what();
    }
    done = true;
    heartbeat.join();
    events_.clearLive(id);
    // A render stopped by the server's own shutdown or a lost lease is not the job's outcome: it
    // stays running until its lease expires, then goes back to the queue.
    if (lost || (stopping_ && outcome == JobState::Cancelled)) {
        // Deleted while it rendered: its last checkpoint or preview may have been written after
        // the files were removed.
        if (lost && !store_.get(id)) files_.remove(id);
        return;
    }
    try {
        if (store_.finish(id, attempt, outcome, stats, error, unixNow()) &&
            outcome == JobState::Succeeded)
            files_.removeCheckpoint(id);
    } catch (const std::exception& e) {
        std::cerr << "caustic serve: finishing job " << id << ": " << e.what() << "\n";
    }
}

}  // namespace caustic::server
