// Workers of a scale-out (store/task.h): threads that claim tasks from the PostgreSQL store, render
// their pass ranges through the render session, and hand in the results, and the process's
// consolidator (farm/consolidator.h), which merges the results of any process's workers.
//
// A worker goes on with the next task of the job it renders while the job has any, adding its
// passes to the same film, and hands in the tasks it holds as one film once it has rendered W
// seconds since its last hand-in, when the job has no task left for it, or when a time limit cut a
// task short. W is the number of workers holding the job's tasks times the larger of a second and
// a result's bytes over 10 MB/s, at most `handInSeconds`: so a job's results cost the store about
// one a second or 10 MB a second however many workers render it (its preview's pace). The leases
// of every task held are renewed together; a render stopped (a cancel, the lease lost, shutdown)
// gives back the tasks held, which are rendered again.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "farm/consolidator.h"
#include "jobs/worker_pool.h"
#include "server_config.h"
#include "store/postgres/job_store.h"

namespace caustic::server {

class TaskWorkers final : public Renderers {
public:
    /// `config.workers` threads; `name` prefixes their ids (host and process).
    TaskWorkers(const ServerConfig& config, PostgresJobStore& store, RenderCounters& counters);
    ~TaskWorkers() override;

    void start() override;
    /// Stops claiming; renders under way stop and give their tasks back; joins the threads.
    void stop() override;
    /// A task may be waiting: wake an idle worker.
    void wake() override;

private:
    struct Cached;  // a job's loaded scene and render session, reused by its next task
    struct Chain;   // the tasks of one job a worker rendered and holds, not yet handed in

    void run(int index);
    void renderTask(const std::string& worker, const ClaimedTask& claimed, Cached& cache,
                    Chain& chain);
    /// Hands in the tasks held (none is left held).
    void handIn(const std::string& worker, Chain& chain);
    /// Gives back the tasks held, unless their leases are lost (none is left held).
    void giveBack(const std::string& worker, Chain& chain);
    FarmPolicy policy() const;
    /// Render seconds a worker holds before it hands in, for a job on `workersOnJob` workers.
    double handInAfter(int workersOnJob, const Scene& scene) const;

    const ServerConfig& config_;
    PostgresJobStore& store_;
    RenderCounters& counters_;
    std::string prefix_;
    std::vector<std::thread> threads_;
    std::unique_ptr<Consolidator> consolidator_;
    std::atomic<bool> stopping_{false};
    std::mutex mutex_;
    std::condition_variable wake_;
    /// The image textures of every render here, through one bounded cache.
    std::shared_ptr<TextureStore> textures_ =
        std::make_shared<TextureStore>(TextureStore::Options{});
};

}  // namespace caustic::server
