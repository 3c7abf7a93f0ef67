#include "farm/task_workers.h"

#include <unistd.h>

#include <chrono>
#include <random>

#include <spdlog/spdlog.h>

#include "core/error.h"
#include "gltf/scene_document.h"
#include "jobs/asset_service.h"
#include "jobs/clock.h"
#include "jobs/lease_keeper.h"
#include "render/render_session.h"
#include "render/resolution.h"
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

struct TaskWorkers::Chain {
    /// The tasks held, shared with the lease keeper's heartbeats.
    struct Held {
        std::mutex mutex;
        std::vector<Task> tasks;
    };

    std::string jobId;
    std::vector<TaskDone> done;  ///< Rendered, in `film` (or `passImages`).
    std::unique_ptr<Film> film;  ///< A job without a target error.
    std::string passImages;      ///< A job with one: one task at a time.
    double renderSeconds = 0;    ///< Of `done`.
    double handInAfter = 0;      ///< Render seconds before the next hand-in.
    std::shared_ptr<Held> held = std::make_shared<Held>();
    std::unique_ptr<LeaseKeeper> lease;

    bool empty() const { return done.empty(); }
    /// Holds nothing more (the job's pace of hand-ins stays).
    void clear() {
        lease.reset();
        done.clear();
        film.reset();
        passImages.clear();
        renderSeconds = 0;
        std::lock_guard lock(held->mutex);
        held->tasks.clear();
    }
};

namespace {

// What a job's results may cost the store: about one a second, or 10 MB a second, whichever is
// less, however many workers render it.
constexpr double kJobBytesPerSecond = 10e6;

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

double TaskWorkers::handInAfter(int workersOnJob, const Scene& scene) const {
    // A result is a film of the image's size, stored in about a third of its bytes in memory.
    const double resultBytes =
        double(Film::bytesFor(scene.camera.width(), scene.camera.height())) / 3;
    return std::min(config_.handInSeconds,
                    workersOnJob * std::max(1.0, resultBytes / kJobBytesPerSecond));
}

FarmPolicy TaskWorkers::policy() const {
    return FarmPolicy{config_.leaseSeconds, config_.maxStalledLeases, config_.blockAfterFailures,
                      config_.failAfterWorkers};
}

void TaskWorkers::start() {
    consolidator_ = std::make_unique<Consolidator>(store_);
    for (int i = 0; i < config_.workers; ++i) threads_.emplace_back([this, i] { run(i); });
}

void TaskWorkers::stop() {
    stopping_ = true;
    wake_.notify_all();
    for (std::thread& t : threads_)
        if (t.joinable()) t.join();
    threads_.clear();
    consolidator_.reset();
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
    Chain chain;
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
            claimed = store_.claimTask(me.id, policy(), chain.jobId);
        } catch (const std::exception& e) {
            spdlog::error("worker {}: claiming a task: {}", me.id, e.what());
        }
        // The job has no task left for this worker, or another job comes first: what it holds
        // goes now.
        if (!chain.empty() && (!claimed || claimed->job.id != chain.jobId)) handIn(me.id, chain);
        if (!claimed) {
            cache = Cached{};  // an idle worker holds no scene
            chain.jobId.clear();
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
        renderTask(me.id, *claimed, cache, chain);
    }
    // Stopping: the tasks rendered whole are handed in (a render cut short gave its tasks back).
    if (!chain.empty()) handIn(me.id, chain);
    try {
        store_.workerGone(me.id);
    } catch (const std::exception&) {
        // Its row ages out of the list.
    }
}

void TaskWorkers::handIn(const std::string& worker, Chain& chain) {
    // A store that cannot take the result (PostgreSQL restarting, the network gone) is not the
    // render's failure: the tasks' leases expire and they are rendered again.
    try {
        if (!chain.lease || !chain.lease->lost) {
            const std::string result = chain.film ? chain.film->toBytes() : chain.passImages;
            if (store_.completeTasks(chain.done, result) == TaskCommit::Accepted && consolidator_)
                consolidator_->wake();
        }
    } catch (const std::exception& e) {
        spdlog::warn("worker {}: handing in {} task(s) of job {}: {}; they will be rendered again",
                     worker, chain.done.size(), chain.jobId, e.what());
    }
    chain.clear();
}

void TaskWorkers::giveBack(const std::string& worker, Chain& chain) {
    std::vector<Task> tasks;
    {
        std::lock_guard lock(chain.held->mutex);
        tasks = chain.held->tasks;
    }
    // A store out of reach leaves the tasks to their leases, which expire: they are rendered
    // again.
    if (!tasks.empty() && !(chain.lease && chain.lease->lost)) try {
            store_.releaseTasks(tasks);
        } catch (const std::exception& e) {
            spdlog::warn("worker {}: giving back {} task(s) of job {}: {}", worker, tasks.size(),
                         tasks.front().jobId, e.what());
        }
    chain.clear();
}

void TaskWorkers::renderTask(const std::string& worker, const ClaimedTask& claimed, Cached& cache,
                             Chain& chain) {
    const Task& task = claimed.task;
    const Job& job = claimed.job;
    chain.jobId = job.id;
    {
        std::lock_guard lock(chain.held->mutex);
        chain.held->tasks.push_back(task);
    }
    if (!chain.lease)
        chain.lease = std::make_unique<LeaseKeeper>(
            [&store = store_, held = chain.held, seconds = config_.leaseSeconds](double) {
                std::vector<Task> tasks;
                {
                    std::lock_guard lock(held->mutex);
                    tasks = held->tasks;
                }
                return store.heartbeatTasks(tasks, seconds);
            },
            config_.leaseSeconds, stopping_);
    LeaseKeeper& lease = *chain.lease;
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
        chain.handInAfter = handInAfter(claimed.workersOnJob, *cache.scene);
        const bool passImages = cache.settings.targetError > 0;
        // A target error's passes go one task at a time, as images the consolidation replays in
        // order; other tasks add to the held film.
        std::unique_ptr<Film> own;
        if (passImages) own = session.makeFilm();
        if (!passImages && !chain.film) chain.film = session.makeFilm();
        Film& film = passImages ? *own : *chain.film;
        const int before = film.passes();
        RenderCallbacks callbacks;
        callbacks.cancel = &lease.cancel;
        // The time limit counts from the job's start, whichever worker renders.
        callbacks.timeLimit = TimeLimitOptions{claimed.elapsedSeconds, true};
        if (passImages)
            callbacks.onPassImage = [&chain, &film](int pass, const std::vector<Color>& image,
                                                    uint64_t dropped) {
                appendPassImage(chain.passImages, film.width(), film.height(), pass, dropped,
                                image);
            };
        RangeResult range = session.renderRange(task.firstPass, task.lastPass, film, callbacks);
        counters_.rays += range.rays;
        counters_.passes += uint64_t(film.passes() - before);
        counters_.renderSeconds.fetch_add(range.renderSeconds);
        if (range.stopReason == StopReason::Cancelled) {
            // Some of this task's passes may be in the film: every task held goes back.
            giveBack(worker, chain);
            return;
        }
        const int passesDone = film.passes() - before;
        chain.done.push_back({task, passesDone, range.rays, range.renderSeconds});
        chain.renderSeconds += range.renderSeconds;
        if (passImages || passesDone < task.lastPass - task.firstPass ||
            chain.renderSeconds >= chain.handInAfter)
            handIn(worker, chain);
    } catch (const RenderCancelled&) {
        giveBack(worker, chain);
    } catch (const StoreUnavailable& e) {
        // Reading the job's assets: not the render's failure (no worker is blamed for
        // PostgreSQL's outage); the leases expire and the tasks are rendered again.
        spdlog::warn("worker {}: task {}-{} of job {}: {}; it will be rendered again", worker,
                     task.firstPass, task.lastPass, job.id, e.what());
        chain.clear();
    } catch (const InputError& e) {
        cache = Cached{};
        try {
            store_.failJob(task, e.what());
        } catch (const std::exception& again) {
            spdlog::error("worker {}: failing job {}: {}", worker, job.id, again.what());
        }
        chain.clear();  // the job failed: what it held is of no use
    } catch (const std::exception& e) {
        cache = Cached{};
        spdlog::warn("worker {}: task {}-{} of job {} failed: {}", worker, task.firstPass,
                     task.lastPass, job.id, e.what());
        {
            // The failed task is counted against this worker; the others it held go back.
            std::lock_guard lock(chain.held->mutex);
            chain.held->tasks.pop_back();
        }
        giveBack(worker, chain);
        try {
            store_.failTask(task, worker, e.what(), policy());
        } catch (const std::exception& again) {
            spdlog::error("worker {}: recording a failed task: {}", worker, again.what());
        }
    }
}

}  // namespace caustic::server
