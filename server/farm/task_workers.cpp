#include "farm/task_workers.h"

#include <unistd.h>

#include <chrono>
#include <random>

#include <spdlog/spdlog.h>

#include "core/error.h"
#include "jobs/asset_service.h"
#include "jobs/clock.h"
#include "jobs/lease_keeper.h"
#include "render/render_session.h"
#include "render/resolution.h"
#include "gltf/scene_document.h"
#include "scene/scene.h"
#include "store/pass_images.h"
#include "store/store_unavailable.h"

namespace caustic::server {

struct TaskWorkers::Cached {
    std::string jobId;
    std::unique_ptr<Scene> scene;
    RenderSettings settings;
    std::unique_ptr<RenderSession> session;
};

namespace {

std::string hostName() {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return "unknown";
    return name;
}

}  // namespace

TaskWorkers::TaskWorkers(const ServerConfig& config, PostgresJobStore& store,
                         RenderCounters& counters)
    : config_(config),
      store_(store),
      counters_(counters),
      prefix_(hostName() + "-" + std::to_string(::getpid()) + "-" +
              std::to_string(std::random_device{}() % 10000)) {}

TaskWorkers::~TaskWorkers() {
    stop();
}

FarmPolicy TaskWorkers::policy() const {
    return FarmPolicy{config_.leaseSeconds, config_.maxStalledLeases, config_.blockAfterFailures,
                      config_.failAfterWorkers};
}

void TaskWorkers::start() {
    for (int i = 0; i < config_.workers; ++i) threads_.emplace_back([this, i] { run(i); });
}

void TaskWorkers::stop() {
    stopping_ = true;
    wake_.notify_all();
    for (std::thread& t : threads_)
        if (t.joinable()) t.join();
    threads_.clear();
}

void TaskWorkers::wake() {
    wake_.notify_one();
}

void TaskWorkers::run(int index) {
    WorkerInfo me;
    me.id = prefix_ + "-" + std::to_string(index);
    me.host = hostName();
    me.cores = int(std::thread::hardware_concurrency());
    me.threads = config_.renderThreads > 0 ? config_.renderThreads : me.cores;
    me.startedAt = unixNow();
    Cached cache;
    double lastSeen = 0;
    while (!stopping_) {
        std::optional<ClaimedTask> claimed;
        try {
            // Idle, the worker's row is renewed once a second (claims poll 4 times a second).
            me.lastSeen = unixNow();
            if (me.current || me.lastSeen - lastSeen >= 1.0) {
                me.current.reset();
                store_.workerSeen(me);
                lastSeen = me.lastSeen;
            }
            claimed = store_.claimTask(me.id, unixNow(), policy());
        } catch (const std::exception& e) {
            spdlog::error("worker {}: claiming a task: {}", me.id, e.what());
        }
        if (!claimed) {
            cache = Cached{};  // an idle worker holds no scene
            // Polled as well: leases expire and other processes queue jobs without a wake-up.
            std::unique_lock lock(mutex_);
            wake_.wait_for(lock, std::chrono::milliseconds(250));
            continue;
        }
        me.current = claimed->task;
        try {
            store_.workerSeen(me);
        } catch (const std::exception&) {
            // Only the workers list is late.
        }
        renderTask(me.id, *claimed, cache);
    }
    try {
        store_.workerGone(me.id);
    } catch (const std::exception&) {
        // Its row ages out of the list.
    }
}

void TaskWorkers::handIn(const std::string& worker, const Task& task, const TaskResult& result) {
    // A store that cannot take the result (PostgreSQL restarting, the network gone) is not the
    // render's failure: the task's lease expires and it is rendered again.
    try {
        store_.completeTask(task, result, unixNow());
    } catch (const std::exception& e) {
        spdlog::warn("worker {}: handing in task {}-{} of job {}: {}; it will be rendered again",
                     worker, task.firstPass, task.lastPass, task.jobId, e.what());
    }
}

void TaskWorkers::giveBack(const std::string& worker, const Task& task) {
    // A store out of reach leaves the task to its lease, which expires: it is rendered again.
    try {
        store_.releaseTask(task, unixNow());
    } catch (const std::exception& e) {
        spdlog::warn("worker {}: giving back task {}-{} of job {}: {}", worker, task.firstPass,
                     task.lastPass, task.jobId, e.what());
    }
}

void TaskWorkers::renderTask(const std::string& worker, const ClaimedTask& claimed, Cached& cache) {
    const Task& task = claimed.task;
    const Job& job = claimed.job;
    LeaseKeeper lease(
        [this, &task](double now) { return store_.heartbeatTask(task, now, config_.leaseSeconds); },
        config_.leaseSeconds, stopping_);
    try {
        if (config_.failEveryTask)
            throw std::runtime_error("this worker fails every task (--fail-every-task, for tests)");
        if (cache.jobId != job.id) {
            // The next task of the same job reuses the scene and the accelerator.
            cache = Cached{};
            SceneOptions options;
            options.assetsDir = config_.assetsDir;
            options.resolveMeshAsset = storedAssets(store_);
            options.textures = textures_;
            cache.scene = loadSceneDocument(job.scene, options);
            cache.settings = parseSettings(job.settings);
            applyResolution(*cache.scene, cache.settings, options);
            if (config_.renderThreads > 0) cache.settings.threads = config_.renderThreads;
            Interrupt setup(&lease.cancel);
            cache.session = std::make_unique<RenderSession>(*cache.scene, cache.settings, &setup);
            cache.jobId = job.id;
        }
        RenderSession& session = *cache.session;
        std::unique_ptr<Film> film = session.makeFilm();
        TaskResult result;
        result.width = film->width();
        result.height = film->height();
        RenderCallbacks callbacks;
        callbacks.cancel = &lease.cancel;
        // The time limit counts from the job's start, whichever worker renders.
        callbacks.timeLimit = TimeLimitOptions{std::max(0.0, unixNow() - job.startedAt), true};
        if (cache.settings.targetError > 0)
            callbacks.onPassImage = [&result](int pass, const std::vector<Color>& image,
                                              uint64_t dropped) {
                appendPassImage(result.passImages, pass, dropped, image);
            };
        RangeResult range = session.renderRange(task.firstPass, task.lastPass, *film, callbacks);
        counters_.rays += range.rays;
        counters_.passes += uint64_t(film->passes());
        counters_.renderSeconds.fetch_add(range.renderSeconds);
        if (range.stopReason == StopReason::Cancelled) {
            if (!lease.lost) giveBack(worker, task);
            return;
        }
        if (cache.settings.targetError <= 0) result.film = film->toBytes();
        result.passesDone = film->passes();
        result.rays = range.rays;
        result.renderSeconds = range.renderSeconds;
        handIn(worker, task, result);
    } catch (const RenderCancelled&) {
        if (!lease.lost) giveBack(worker, task);
    } catch (const StoreUnavailable& e) {
        // Reading the job's assets or giving the task back: not the render's failure (no worker
        // is blamed for PostgreSQL's outage); the lease expires and the task is rendered again.
        spdlog::warn("worker {}: task {}-{} of job {}: {}; it will be rendered again", worker,
                     task.firstPass, task.lastPass, job.id, e.what());
    } catch (const InputError& e) {
        cache = Cached{};
        try {
            store_.failJob(task, e.what(), unixNow());
        } catch (const std::exception& again) {
            spdlog::error("worker {}: failing job {}: {}", worker, job.id, again.what());
        }
    } catch (const std::exception& e) {
        cache = Cached{};
        spdlog::warn("worker {}: task {}-{} of job {} failed: {}", worker, task.firstPass,
                     task.lastPass, job.id, e.what());
        try {
            store_.failTask(task, worker, e.what(), unixNow(), policy());
        } catch (const std::exception& again) {
            spdlog::error("worker {}: recording a failed task: {}", worker, again.what());
        }
    }
}

}  // namespace caustic::server
