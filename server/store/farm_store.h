// What the HTTP API asks of a store that worker processes share (PostgreSQL, store/task.h):
// the workers, and re-queueing a split job with the passes it has.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "store/task.h"

namespace caustic::server {

class FarmStore {
public:
    virtual ~FarmStore() = default;
    /// Workers seen since `seenSince` (Unix seconds), by id.
    virtual std::vector<WorkerInfo> listWorkers(double seenSince) = 0;
    /// Puts a failed or cancelled split job back in the queue; its finished tasks stay finished.
    /// Returns the job after the change; nothing for an unknown id.
    virtual std::optional<Job> requeue(const std::string& id) = 0;
};

}  // namespace caustic::server
