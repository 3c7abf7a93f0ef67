#include "service.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <httplib.h>

#include <iostream>
#include <random>
#include <stdexcept>

#include "http/routes.h"
#include "store/sqlite_job_store.h"

namespace caustic::server {
namespace fs = std::filesystem;

RenderService::RenderService(ServerConfig config)
    : config_(std::move(config)), files_(config_.dataDir) {
    fs::create_directories(config_.dataDir);
    // One service per data folder: the embedded store and the job files are not shared.
    const fs::path lock = config_.dataDir / "caustic.lock";
    lockFd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lockFd_ < 0 || ::flock(lockFd_, LOCK_EX | LOCK_NB) != 0)
        throw std::runtime_error("the data folder " + config_.dataDir.string() +
                                 " is in use by another caustic serve");
    store_ = std::make_unique<SqliteJobStore>(config_.dataDir / "jobs.sqlite3");
    owner_ = "pid" + std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}());
    // The lock proves that whoever held the running jobs' leases is gone: requeue them now.
    int orphaned = store_->expireLeasesNotOwnedBy(owner_);
    if (orphaned > 0)
        std::cerr << "caustic serve: " << orphaned
                  << " job(s) were running when the last server stopped; they resume from their "
                     "last finished pass\n";
    workers_ = std::make_unique<WorkerPool>(config_, *store_, files_, events_, counters_, owner_);
    http_ = std::make_unique<httplib::Server>();
}

RenderService::~RenderService() {
    stop();
    if (lockFd_ >= 0) ::close(lockFd_);
}

int RenderService::bind() {
    if (config_.port == 0) {
        config_.port = http_->bind_to_any_port(config_.host);
        if (config_.port > 0) return config_.port;
    } else if (http_->bind_to_port(config_.host, config_.port)) {
        return config_.port;
    }
    throw std::runtime_error("cannot listen on " + config_.host + ":" +
                             std::to_string(config_.port));
}

void RenderService::serve() {
    // Request threads: event streams hold one each for as long as they are open.
    const size_t threads = size_t(config_.limits.maxEventStreams) + 16;
    http_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    http_->set_keep_alive_timeout(5);
    http_->set_read_timeout(10);
    http_->set_write_timeout(10);
    ApiContext api{config_,   *store_,   files_,        events_,
                   counters_, *workers_, eventStreams_, stopping_};
    registerRoutes(*http_, api);
    workers_->start();
    http_->listen_after_bind();
    workers_->stop();
}

void RenderService::stop() {
    stopping_ = true;
    events_.notify();
    if (http_) http_->stop();
}

}  // namespace caustic::server
