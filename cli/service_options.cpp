#include "service_options.h"

#include <regex>

#include "command_line.h"
#include "logging.h"

namespace caustic::cli {

void addWorkOptions(CLI::App& app, server::ServerConfig& c, int minWorkers) {
    addNumber(app, "--workers", c.workers, minWorkers, 64,
              minWorkers == 0 ? "Jobs (with --store postgresql://, tasks) rendered at once by "
                                "this process; 0 with a PostgreSQL store leaves rendering to "
                                "`caustic worker` processes"
                              : "Tasks rendered at once by this process");
    addNumber(app, "--threads", c.renderThreads, 0, 1024, "Threads per render, 0 for every core");
    addNumber(app, "--lease-seconds", c.leaseSeconds, 0.5, 3600,
              "A worker's lease on its job (or task), seconds");
    addNumber(app, "--max-stalled-leases", c.maxStalledLeases, 1, 1000,
              "Leases in a row that may expire before a pass (a task) finishes before the job "
              "fails; with SQLite, a server killed or stopped from outside does not count, one "
              "that dies of a fault does");
    addNumber(app, "--max-attempts", c.maxAttempts, 1, 1e6,
              "Starts of one job, whatever stopped them, before it fails (guards against "
              "out-of-memory kills; SQLite)");
}

void addStoreOptions(CLI::App& app, server::ServerConfig& c, bool required) {
    app.add_option("--store", c.store,
                   std::string("The job store: a PostgreSQL connection string (postgresql://"
                               "user:password@host:port/database) shared by API and worker "
                               "processes on any machine") +
                       (required ? "" : " (default: SQLite in the data folder)"))
        ->type_name("URL")
        ->required(required)
        ->envname("CAUSTIC_STORE")
        ->check(CLI::Validator(
            [](const std::string& v) {
                return v.empty() || v.starts_with("postgresql://") || v.starts_with("postgres://")
                           ? std::string()
                           : "must be a postgresql:// connection string (SQLite needs no "
                             "--store), got \"" +
                                 redactedStore(v) + "\"";
            },
            ""));
    CLI::App& farm = *app.add_option_group("Scale-out (with --store postgresql://)");
    addNumber(farm, "--store-wait", c.storeWaitSeconds, 0, 3600,
              "Seconds a start waits for a PostgreSQL store that does not answer yet")
        ->envname("CAUSTIC_STORE_WAIT");
    addNumber(farm, "--task-passes", c.taskPasses, 1, 1 << 20,
              "Passes per task of a job that sets no task_passes: a job's passes are rendered "
              "in tasks this size, merged exactly");
    addNumber(farm, "--hand-in-seconds", c.handInSeconds, 0, 3600,
              "The most render seconds a worker goes on with one job's tasks before it hands "
              "them in as one film (it waits so that the job's results cost the store about one "
              "a second or 10 MB a second, however many workers render it): what a lost worker "
              "costs at most; 0 hands in every task");
    addNumber(farm, "--block-after-failures", c.blockAfterFailures, 1, 1000,
              "Failed tasks of a job after which a worker stops taking that job's tasks");
    addNumber(farm, "--fail-after-workers", c.failAfterWorkers, 1, 1000,
              "Distinct workers whose tasks of a job failed before the job fails");
    farm.add_flag("--fail-every-task", c.failEveryTask,
                  "For tests: this process's workers fail every task they take");
}

void addLogLevelOption(CLI::App& app, server::ServerConfig& c) {
    app.add_option("--log-level", c.logLevel, "Messages and access log at this level and above")
        ->check(CLI::IsMember(
            std::vector<std::string>(std::begin(server::kLogLevels), std::end(server::kLogLevels))))
        ->capture_default_str();
}

std::string redactedStore(const std::string& store) {
    // scheme://user:password@host... -> scheme://user:***@host...; a password=... parameter too.
    static const std::regex userinfo(R"(^([a-z]+://[^:/@]*):[^@/]*@)", std::regex::icase);
    static const std::regex parameter(R"((password=)[^&\s]*)", std::regex::icase);
    return std::regex_replace(std::regex_replace(store, userinfo, "$1:***@"), parameter, "$1***");
}

StopSignals::StopSignals() {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals_, nullptr);
    signal(SIGPIPE, SIG_IGN);
}

int StopSignals::wait() {
    int sig = 0;
    sigwait(&signals_, &sig);
    return sig;
}

}  // namespace caustic::cli
