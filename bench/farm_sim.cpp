// A simulated render farm on a real PostgreSQL (server/store/task.h): N workers, each a thread
// with a store (a connection) of its own as a worker process has, claim the tasks of one job,
// "render" each by sleeping the render time measured for it on this machine, and hand in a real
// film of the job's size (cornell-box, the task's passes rendered once at the start). It reports
// the wall time, the speedup over one worker, the queue's share of the workers' time and the
// hand-ins' median and p99. bench/README.md, "Scale-out".
//
// Workers hand in as farm/task_workers.cpp's do (--hand-in-seconds). Speedup is measured in
// tasks a second on jobs of the same length per worker: N workers render a job of
// N x --tasks-per-worker tasks; S(N) = (tasks_N / wall_N) / (tasks_1 / wall_1). The wall time
// runs from the job's insert to its end (the last consolidation's commit).
//
// The server is a throwaway cluster (tests/support/postgres.sh: PostgreSQL 15 on 127.0.0.1,
// fsync off), or the one of --store: a database nobody else uses.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <iostream>
#include <memory>
#include <mutex>
#include <thread>

#include "bench_common.h"
#include "farm/consolidator.h"
#include "film/film.h"
#include "jobs/clock.h"
#include "jobs/lease_keeper.h"
#include "postgres_cluster.h"
#include "render/render_session.h"
#include "render/settings.h"
#include "scene/scene.h"
#include "store/postgres/job_store.h"

namespace {

using namespace caustic;
using namespace caustic::server;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

/// An example scene (scenes/NAME.json) at size x size.
Json exampleScene(const std::string& name, int size) {
    Json scene = readJsonFile(std::string(CAUSTIC_DEFAULT_SCENES_DIR) + "/" + name + ".json");
    scene["camera"]["width"] = scene["camera"]["height"] = size;
    return scene;
}

/// One task's result as every worker hands it in: the film of passes [0, k) rendered here, and
/// the render seconds of one pass on one thread.
struct TaskTemplate {
    std::string scene;
    int size = 0, passes = 0;
    double passSeconds = 0;
    std::string film;  ///< Film::toBytes() of passes [0, passes).
};

TaskTemplate renderTemplate(const std::string& name, int size, int passes) {
    const Json doc = exampleScene(name, size);
    SceneOptions options;
    options.assetsDir = CAUSTIC_DEFAULT_ASSETS_DIR;
    std::unique_ptr<Scene> scene = loadScene(doc, options);
    RenderSettings settings;
    settings.spp = passes;
    settings.sppPerPass = 1;
    settings.threads = 1;
    TaskTemplate t{name, size, passes, 0, {}};
    std::unique_ptr<Film> film;
    {
        // The render time: the faster of two one-thread passes (the first warms the caches).
        RenderSession one(*scene, settings);
        film = one.makeFilm();
        double best = 1e30;
        for (int pass = 0; pass < std::min(2, passes); ++pass)
            best = std::min(best, one.renderRange(pass, pass + 1, *film, {}).renderSeconds);
        t.passSeconds = best;
    }
    settings.threads = 0;
    RenderSession all(*scene, settings);
    all.renderRange(film->passes(), passes, *film, {});
    t.film = film->toBytes();
    return t;
}

/// The template's film relabelled as the passes of `tasks`: a film's bytes start with a 40-byte
/// header (magic, size, counters, then the number of ranges as uint32 at byte 32) and the ranges
/// as int32 pairs, sorted and apart (renderer/film/film_bytes.cpp); the template has one range.
/// The sums stay those of its passes [0, k): every hand-in moves the bytes of a k-pass film.
std::string relabel(const std::string& film, std::vector<Task> tasks) {
    constexpr size_t kHeader = 40, kRangesAt = 32;
    std::sort(tasks.begin(), tasks.end(),
              [](const Task& a, const Task& b) { return a.firstPass < b.firstPass; });
    std::vector<int32_t> pairs;
    for (const Task& t : tasks)
        if (!pairs.empty() && pairs.back() == t.firstPass)
            pairs.back() = t.lastPass;  // adjacent ranges are one
        else
            pairs.insert(pairs.end(), {t.firstPass, t.lastPass});
    std::string out = film.substr(0, kHeader);
    const auto ranges = uint32_t(pairs.size() / 2);
    std::memcpy(out.data() + kRangesAt, &ranges, sizeof ranges);
    out.append(reinterpret_cast<const char*>(pairs.data()), pairs.size() * sizeof(int32_t));
    out.append(film, kHeader + 2 * sizeof(int32_t));
    return out;
}

struct WorkerTimes {
    double claims = 0, handIns = 0, rendering = 0;
    Clock::time_point lastHandIn{};  ///< When its last hand-in returned.
    std::vector<double> handIn;      ///< Each hand-in's seconds.
    int tasks = 0;
    int errors = 0;  ///< Store calls that threw (a worker logs them and goes on).
};

struct Run {
    int workers = 0, tasks = 0;
    double wall = 0;
    std::string state;  ///< How the job ended.
    double tail = 0;    ///< From the last hand-in to the job's end (its last consolidation).
    WorkerTimes sum;
};

constexpr FarmPolicy kPolicy{.leaseSeconds = 10};
// As farm/task_workers.cpp: a job's results cost the store about one a second or 10 MB a second.
constexpr double kJobBytesPerSecond = 10e6;

// A worker as farm/task_workers.cpp runs one: it goes on with its job's next task and hands in
// the tasks it holds as one film once it rendered W seconds since its last hand-in (W: the
// workers on the job times the larger of a second and a result's bytes over 10 MB/s, at most
// `handInSeconds`), or when the job has no task left for it.
void work(const std::string& url, const std::string& worker, const std::string& id,
          const TaskTemplate& t, double handInSeconds, Consolidator& consolidator,
          std::atomic<bool>& done, WorkerTimes& times) {
    PostgresJobStore store(url, 10, "farm_sim-worker");
    const double renderSeconds = t.passSeconds * t.passes;
    std::vector<TaskDone> held;
    double heldSeconds = 0, handInAfter = 0;
    // The held tasks' leases, renewed by a lease keeper's thread as a worker's are (also while it
    // hands them in); its heartbeats are not counted in the worker's queue time.
    auto leased = std::make_shared<std::pair<std::mutex, std::vector<Task>>>();
    std::unique_ptr<LeaseKeeper> lease;
    const std::atomic<bool> never{false};
    const auto handIn = [&] {
        std::vector<Task> tasks;
        for (const TaskDone& d : held) tasks.push_back(d.task);
        const std::string film = relabel(t.film, tasks);
        const auto start = Clock::now();
        if (store.completeTasks(held, film) == TaskCommit::Accepted) consolidator.wake();
        const double seconds = since(start);
        times.handIns += seconds;
        times.handIn.push_back(seconds);
        times.lastHandIn = Clock::now();
        times.tasks += int(held.size());
        held.clear();
        heldSeconds = 0;
        lease.reset();
        std::lock_guard lock(leased->first);
        leased->second.clear();
    };
    while (!done) try {
            auto start = Clock::now();
            std::optional<ClaimedTask> claimed = store.claimTask(worker, kPolicy, id);
            times.claims += since(start);
            if (!claimed) {
                if (!held.empty()) handIn();
                // An idle worker polls four times a second (farm/task_workers.cpp).
                std::this_thread::sleep_for(std::chrono::milliseconds(250));
                continue;
            }
            const Task& task = claimed->task;
            handInAfter = std::min(
                handInSeconds,
                claimed->workersOnJob * std::max(1.0, double(t.film.size()) / kJobBytesPerSecond));
            {
                std::lock_guard lock(leased->first);
                leased->second.push_back(task);
            }
            if (!lease)
                lease = std::make_unique<LeaseKeeper>(
                    [&store, leased](double) {
                        std::vector<Task> tasks;
                        {
                            std::lock_guard lock(leased->first);
                            tasks = leased->second;
                        }
                        return store.heartbeatTasks(tasks, kPolicy.leaseSeconds);
                    },
                    kPolicy.leaseSeconds, never);
            // The render: a sleep.
            std::this_thread::sleep_for(std::chrono::duration<double>(renderSeconds));
            times.rendering += renderSeconds;
            const int passes = task.lastPass - task.firstPass;
            held.push_back({task, passes, uint64_t(t.size) * uint64_t(t.size) * uint64_t(passes),
                            renderSeconds});
            heldSeconds += renderSeconds;
            if (heldSeconds >= handInAfter) handIn();
        } catch (const std::exception& e) {
            // As a worker does: the tasks' leases expire and they are rendered again.
            held.clear();
            lease.reset();
            std::lock_guard lock(leased->first);
            leased->second.clear();
            if (times.errors++ == 0) std::cerr << "farm_sim: a worker: " << e.what() << "\n";
        }
    if (!held.empty()) handIn();
}

Run runFarm(const std::string& url, PostgresJobStore& store, const TaskTemplate& t, int workers,
            int tasks, double handInSeconds) {
    static int count = 0;
    Job job;
    job.id = "sim-" + std::to_string(getpid()) + "-" + std::to_string(++count);
    job.scene = exampleScene(t.scene, t.size);
    job.sceneName = t.scene;
    RenderSettings settings;
    settings.spp = tasks * t.passes;
    settings.sppPerPass = 1;
    job.settings = settings.toJson();
    job.taskPasses = t.passes;
    job.passesTotal = tasks * t.passes;
    job.createdAt = unixNow();
    store.insert(job, {}, {});
    const auto start = Clock::now();
    std::atomic<bool> done{false};
    std::vector<WorkerTimes> times(static_cast<size_t>(workers));
    // The consolidator of the simulation's process (a real farm has one in each worker process;
    // one at a time works on a job).
    PostgresJobStore consolidatorStore(url, 10, "farm_sim-consolidator");
    Consolidator consolidator(consolidatorStore);
    std::vector<std::thread> threads;
    for (int i = 0; i < workers; ++i)
        threads.emplace_back([&, i] {
            work(url, "sim-worker-" + std::to_string(i), job.id, t, handInSeconds, consolidator,
                 done, times[size_t(i)]);
        });
    Run run{workers, tasks, 0, {}, 0, {}};
    while (true) {
        std::optional<Job> now = store.get(job.id);
        if (!now || (now->state != JobState::Queued && now->state != JobState::Running)) {
            run.wall = since(start);
            run.state = now ? toString(now->state) : "gone";
            if (now && now->state != JobState::Succeeded)
                std::cerr << "farm_sim: job " << job.id << " ended " << toString(now->state) << ": "
                          << now->error << "\n";
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    done = true;
    for (std::thread& thread : threads) thread.join();
    const auto end = start + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(run.wall));
    Clock::time_point lastHandIn = start;
    for (const WorkerTimes& w : times) {
        lastHandIn = std::max(lastHandIn, w.lastHandIn);
        run.sum.claims += w.claims;
        run.sum.handIns += w.handIns;
        run.sum.rendering += w.rendering;
        run.sum.tasks += w.tasks;
        run.sum.errors += w.errors;
        run.sum.handIn.insert(run.sum.handIn.end(), w.handIn.begin(), w.handIn.end());
    }
    run.tail = std::chrono::duration<double>(end - lastHandIn).count();
    store.remove(job.id);
    return run;
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app("A simulated render farm on PostgreSQL: speedup of one job over N workers.",
                 "farm_sim");
    std::string url;
    std::vector<int> sizes{512, 1024}, workerCounts{1, 4, 16, 64};
    int taskPasses = 8, tasksPerWorker = 16;
    double handInSeconds = 120;
    std::string sceneName = "cornell-box";
    std::vector<std::string> resultScenes;
    bool smoke = false;
    app.add_option("--store", url,
                   "A postgresql:// database nobody else uses (default: a throwaway cluster from "
                   "tests/support/postgres.sh)");
    app.add_option("--sizes", sizes, "Image sizes (square), default 512 1024");
    app.add_option("--workers", workerCounts, "Worker counts, default 1 4 16 64 (1 comes first)");
    app.add_option("--task-passes", taskPasses, "Passes of 1 spp a task (serve's default: 8)");
    app.add_option("--tasks-per-worker", tasksPerWorker,
                   "Tasks a worker renders: the job's length (default 16)");
    app.add_option("--hand-in-seconds", handInSeconds,
                   "As serve's and worker's --hand-in-seconds (default 120; 0: every task)");
    app.add_option("--scene", sceneName, "The job's example scene (default cornell-box)");
    app.add_option("--result-bytes", resultScenes,
                   "Instead of a farm: the bytes a pixel of one task's result on these example "
                   "scenes, at each size, in the stored format and the in-memory one");
    app.add_flag("--smoke", smoke, "64², 1 and 4 workers, 2 passes a task: checks that it runs");
    if (int exitCode = cli::parseCommandLine(app, argc, argv); exitCode >= 0) return exitCode;
    if (smoke) {
        sizes = {64};
        workerCounts = {1, 4};
        taskPasses = 2;
        tasksPerWorker = 4;
    }
    bench::printMachine(argc, argv);
    if (!resultScenes.empty()) {
        std::cout << "| scene | image | passes | stored bytes/px | in memory bytes/px | ratio |\n"
                     "|---|---|---:|---:|---:|---:|\n";
        for (const std::string& name : resultScenes)
            for (int size : sizes) {
                const TaskTemplate t = renderTemplate(name, size, taskPasses);
                const double pixels = double(size) * size;
                const double memory = double(Film::bytesFor(size, size)) / pixels;
                const double stored = double(t.film.size()) / pixels;
                std::cout << "| " << name << " | " << size << "² | " << taskPasses << " | "
                          << bench::fmt("%.1f", stored) << " | " << bench::fmt("%.1f", memory)
                          << " | " << bench::fmt("%.2f", memory / stored) << " |\n"
                          << std::flush;
            }
        return 0;
    }
    std::unique_ptr<bench::PostgresCluster> cluster;
    try {
        if (url.empty()) {
            if (!bench::haveServerBinaries()) {
                std::cerr << "farm_sim: no PostgreSQL 15 server binaries: skipped\n";
                return 77;
            }
            cluster = std::make_unique<bench::PostgresCluster>();
            url = cluster->url();
        }
        std::cout
            << "| image | workers | tasks | job | task render s | wall s | speedup | speedup / N "
               "| queue share | hand-in median ms | hand-in p99 ms | result bytes/px | "
               "last hand-in to end s | store errors |\n"
               "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (int size : sizes) {
            const TaskTemplate t = renderTemplate(sceneName, size, taskPasses);
            PostgresJobStore store(url);
            double oneRate = 0;
            for (int n : workerCounts) {
                const Run run = runFarm(url, store, t, n, n * tasksPerWorker, handInSeconds);
                const double rate = run.tasks / run.wall;
                if (n == 1) oneRate = rate;
                const double speedup = oneRate > 0 ? rate / oneRate : NAN;
                const double queue = run.sum.claims + run.sum.handIns;
                std::cout << "| " << size << "² | " << n << " | " << run.tasks << " | " << run.state
                          << " | " << bench::fmt("%.2f", t.passSeconds * t.passes) << " | "
                          << bench::fmt("%.2f", run.wall) << " | " << bench::fmt("%.2f", speedup)
                          << " | " << bench::fmt("%.2f", speedup / n) << " | "
                          << bench::fmt("%.1f%%", 100 * queue / (n * run.wall)) << " | "
                          << bench::fmt("%.1f", 1000 * bench::median(run.sum.handIn)) << " | "
                          << bench::fmt("%.1f", 1000 * percentile(run.sum.handIn, 0.99)) << " | "
                          << bench::fmt("%.1f", double(t.film.size()) / (double(size) * size))
                          << " | " << bench::fmt("%.2f", run.tail) << " | " << run.sum.errors
                          << " |\n"
                          << std::flush;
            }
        }
    } catch (const std::exception& e) {
        std::cerr << "farm_sim: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
