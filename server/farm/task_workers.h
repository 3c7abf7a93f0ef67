// Workers of a scale-out (store/task.h): threads that claim tasks from the PostgreSQL store, render
// their pass ranges through the render session, and hand in the results, which the store merges.
// Run by `caustic worker` (no HTTP) and by `caustic serve --store postgresql://... --workers N`.
// Each thread is a worker of its own in the store's list (host, cores, current task), renewed
// every second while idle and with every heartbeat while rendering.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "jobs/worker_pool.h"
#include "server_config.h"
#include "store/postgres_job_store.h"

namespace caustic::server {

class TaskWorkers {
public:
    /// `config.workers` threads; `name` prefixes their ids (host and process).
    TaskWorkers(const ServerConfig& config, PostgresJobStore& store, RenderCounters& counters);
    ~TaskWorkers();

    void start();
    /// Stops claiming; renders under way stop and give their tasks back; joins the threads.
    void stop();
    /// A task may be waiting: wake an idle worker.
    void wake();

private:
    struct Cached;  // a job's loaded scene and render session, reused by its next task

    void run(int index);
    void renderTask(const std::string& worker, const ClaimedTask& claimed, Cached& cache);
    void handIn(const std::string& worker, const Task& task, const TaskResult& result);
    void giveBack(const std::string& worker, const Task& task);
    FarmPolicy policy() const;

    const ServerConfig& config_;
    PostgresJobStore& store_;
    RenderCounters& counters_;
    std::string prefix_;
    std::vector<std::thread> threads_;
    std::atomic<bool> stopping_{false};
    std::mutex mutex_;
    std::condition_variable wake_;
    /// The image textures of every render here, through one bounded cache.
    std::shared_ptr<TextureStore> textures_ =
        std::make_shared<TextureStore>(TextureStore::Options{});
};

}  // namespace caustic::server
