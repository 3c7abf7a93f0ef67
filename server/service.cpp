#include "service.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <httplib.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <random>
#include <stdexcept>

#include "http/routes.h"
#include "store/sqlite_job_store.h"

namespace caustic::server {
namespace fs = std::filesystem;

namespace {

// The fault record (see the constructor): a file in the data folder that a process dying of a
// fault writes one line to, from a signal handler, so only with async-signal-safe calls.
std::atomic<int> faultFd{-1};
char faultPrefix[160];
size_t faultPrefixLength = 0;
constexpr int kFaultSignals[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};

extern "C" void recordFault(int sig) {
    if (int fd = faultFd.load(); fd >= 0) {
        char line[16];
        size_t n = sizeof line;
        line[--n] = '\n';
        for (unsigned v = unsigned(sig); n > 0 && (v > 0 || n == sizeof line - 1); v /= 10)
            line[--n] = char('0' + v % 10);
        (void)!::write(fd, faultPrefix, faultPrefixLength);
        (void)!::write(fd, line + n, sizeof line - n);
    }
    // SA_RESETHAND made the action the default again: the process dies of `sig` once this
    // handler returns (a hardware fault recurs; a raised signal is delivered).
    ::raise(sig);
}

}  // namespace

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
    // The lock proves that whoever held the running jobs' leases is gone: requeue them now. Only
    // a process that died of a fault (its fault record says so) counts against the jobs it was
    // rendering, towards failing a job that crashes whoever renders it; one killed from outside
    // (SIGKILL, an operator, a shutdown, a power cut) or stopped says nothing about its jobs.
    const fs::path faultRecord = config_.dataDir / "fault.log";
    std::string fault;
    {
        std::ifstream in(faultRecord);
        std::getline(in, fault);
    }
    int orphaned = store_->expireLeasesNotOwnedBy(owner_, !fault.empty());
    if (!fault.empty())
        std::cerr << "caustic serve: the last server " << fault
                  << (orphaned > 0 ? "; the jobs it was rendering count it as a stalled lease" : "")
                  << "\n";
    if (orphaned > 0)
        std::cerr << "caustic serve: " << orphaned
                  << " job(s) were running when the last server stopped; they resume from their "
                     "last finished pass\n";
    files_.removeTemporaryFiles();
    // This process's fault record, empty unless it dies of a fault. Handlers are installed only
    // over the default action (a sanitizer's or debugger's stay).
    faultFd_ =
        ::open(faultRecord.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
    if (faultFd_ >= 0) {
        std::snprintf(faultPrefix, sizeof faultPrefix, "%s died of signal ", owner_.c_str());
        faultPrefixLength = std::strlen(faultPrefix);
        faultFd = faultFd_;
        for (int sig : kFaultSignals) {
            struct sigaction old {};
            if (::sigaction(sig, nullptr, &old) != 0 || old.sa_handler != SIG_DFL ||
                (old.sa_flags & SA_SIGINFO))
                continue;
            struct sigaction action {};
            action.sa_handler = recordFault;
            sigemptyset(&action.sa_mask);
            action.sa_flags = SA_RESETHAND | SA_ONSTACK;
            ::sigaction(sig, &action, nullptr);
        }
    }
    workers_ = std::make_unique<WorkerPool>(config_, *store_, files_, events_, counters_, owner_);
    jobs_ = std::make_unique<JobService>(config_, *store_, files_, events_,
                                         [this] { workers_->wake(); });
    assets_ = std::make_unique<AssetService>(config_, *store_);
    http_ = std::make_unique<httplib::Server>();
    // No Nagle delay: a response goes out in more than one write (headers, body), and on a
    // kept-alive connection the second waited for the client's delayed ACK, 40 ms a request.
    // Set before bind(): accepted sockets inherit it from the listening one.
    http_->set_tcp_nodelay(true);
}

RenderService::~RenderService() {
    stop();
    if (faultFd_ >= 0) {
        int mine = faultFd_;
        faultFd.compare_exchange_strong(mine, -1);
        ::close(faultFd_);
    }
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
    ApiContext api{config_, *jobs_, counters_, eventStreams_, stopping_, *assets_};
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
