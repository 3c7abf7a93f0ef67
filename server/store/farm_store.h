// What the HTTP API asks of a store that worker processes share (PostgreSQL, store/task.h):
// the workers, the tasks waiting for one, and re-queueing a split job with the passes it has.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/task.h"

namespace caustic::server {

class FarmStore {
public:
    virtual ~FarmStore() = default;
    /// Workers seen in the last `aliveSeconds` (by the database's clock), by id.
    virtual std::vector<WorkerInfo> listWorkers(double aliveSeconds) = 0;
    /// Tasks waiting for a worker: the queued tasks of queued or running jobs whose cancel was
    /// not asked, and the running ones whose lease has expired (the next claim puts them back in
    /// the queue). A worker blocked from a job may still not take them.
    virtual int64_t queuedTasks() = 0;
    /// Puts a failed or cancelled split job back in the queue; its finished tasks stay finished.
    /// Returns the job after the change; nothing for an unknown id.
    virtual std::optional<Job> requeue(const std::string& id) = 0;
};

}  // namespace caustic::server
