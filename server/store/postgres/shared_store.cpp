#include "store/shared_store.h"

#include <unistd.h>

#include "farm/task_workers.h"
#include "store/postgres/job_files.h"
#include "store/postgres/job_store.h"
#include "store/postgres/listener.h"

namespace caustic::server {

SharedStore openSharedStore(const ServerConfig& config, RenderCounters& counters,
                            std::function<void()> changed) {
    // Nothing here is shared through the data folder: leases expire by time (other processes'
    // are live), files live in the store, and a crash is a lease that expires.
    auto store = std::make_unique<PostgresJobStore>(config.store, config.storeWaitSeconds,
                                                    "caustic-serve-" + std::to_string(::getpid()));
    SharedStore shared;
    shared.files = std::make_unique<PostgresJobFiles>(*store);
    shared.farm = store.get();
    shared.renderers = std::make_unique<TaskWorkers>(config, *store, counters);
    shared.listener = std::make_shared<PostgresListener>(config.store, std::move(changed));
    shared.jobs = std::move(store);
    return shared;
}

}  // namespace caustic::server
