// This process's renderers, whichever kind its store has: the job workers of a SQLite store
// (jobs/worker_pool.h) or the task workers of a PostgreSQL one (farm/task_workers.h).
#pragma once

namespace caustic::server {

class Renderers {
public:
    virtual ~Renderers() = default;
    virtual void start() = 0;
    /// Stops claiming; renders under way stop; joins the threads.
    virtual void stop() = 0;
    /// Work was queued: wake an idle renderer.
    virtual void wake() = 0;
};

}  // namespace caustic::server
