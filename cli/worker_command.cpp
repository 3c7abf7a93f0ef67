#include "worker_command.h"

#include <iostream>
#include <thread>

#include <spdlog/spdlog.h>

#include <unistd.h>

#include "command_line.h"
#include "logging.h"
#include "service_options.h"
#if CAUSTIC_HAS_POSTGRES
#include "farm/task_workers.h"
#include "store/postgres/job_store.h"
#endif

namespace caustic {

CLI::App* addWorkerCommand(CLI::App& app, server::ServerConfig& c) {
    CLI::App* worker = app.add_subcommand(
        "worker",
        "Renders tasks of the jobs in a PostgreSQL store (the API runs elsewhere: caustic serve "
        "--store ...) until SIGINT or SIGTERM; renders in progress give their tasks back.");
    cli::addStoreOptions(*worker, c, true);
    cli::addWorkOptions(*worker, c, 1);
    c.assetsDir = CAUSTIC_DEFAULT_ASSETS_DIR;
    worker
        ->add_option_function<std::string>(
            "--assets", [&c](const std::string& dir) { c.assetsDir = dir; },
            "The folder mesh file names resolve in (uploaded meshes come from the store)")
        ->type_name("DIR")
        ->envname("CAUSTIC_ASSETS")
        ->default_str(c.assetsDir.string());
    cli::addLogLevelOption(*worker, c);
    return worker;
}

int runWorker(const server::ServerConfig& config) {
    cli::StopSignals stopSignals;  // before any thread starts
    try {
        server::setUpLogging(config.logLevel, "");
#if CAUSTIC_HAS_POSTGRES
        server::PostgresJobStore store(config.store, config.storeWaitSeconds,
                                       "caustic-worker-" + std::to_string(::getpid()));
        server::RenderCounters counters;
        server::TaskWorkers workers(config, store, counters);
        // Printed on stdout, not logged: scripts and tests wait for this line.
        std::cout << "caustic: worker rendering " << config.workers << " task(s) at a time from "
                  << cli::redactedStore(config.store) << " (Ctrl-C stops)" << std::endl;
        workers.start();
        spdlog::info("stopping (signal {})", stopSignals.wait());
        workers.stop();
#else
        throw std::runtime_error("this build has no PostgreSQL store (CAUSTIC_POSTGRES=OFF)");
#endif
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 1;
    }
    return 0;
}

}  // namespace caustic
