#include "service.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>

#include "http/routes.h"
#include "store/sqlite/job_store.h"
namespace caustic::server {
namespace fs = std::filesystem;

namespace {

constexpr int kKeepAliveSeconds = 5;

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

RenderService::RenderService(ServerConfig config) : config_(std::move(config)) {
    owner_ = "pid" + std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}());
    if (isPostgresStore(config_.store))
        openSharedStore();
    else
        openEmbeddedStore();
    if (!renderers_)
        renderers_ =
            std::make_unique<WorkerPool>(config_, *store_, *files_, events_, counters_, owner_);
    retention_ = std::make_unique<RetentionSweeper>(config_, *store_, *files_, events_, storage_);
    jobs_ = std::make_unique<JobService>(config_, *store_, *files_, events_, [this] { wake(); });
    assets_ = std::make_unique<AssetService>(config_, *store_);
    http_ = makeGatedServer(config_.tlsCert.string(), config_.tlsKey.string());
    // Request threads: event streams hold one each for as long as they are open.
    const int threads = config_.limits.maxEventStreams + 16;
    gate_ = std::make_unique<ConnectionGate>(*http_, config_.limits, threads, config_.tls(),
                                             kKeepAliveSeconds, connections_);
}

void RenderService::openEmbeddedStore() {
    fs::create_directories(config_.dataDir);
    // One service per data folder: the embedded store and the job files are not shared.
    const fs::path lock = config_.dataDir / "caustic.lock";
    lockFd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lockFd_ < 0 || ::flock(lockFd_, LOCK_EX | LOCK_NB) != 0)
        throw std::runtime_error("the data folder " + config_.dataDir.string() +
                                 " is in use by another caustic serve");
    store_ = std::make_unique<SqliteJobStore>(config_.dataDir / "jobs.sqlite3");
    auto files = std::make_unique<FolderJobFiles>(config_.dataDir);
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
        spdlog::warn("the last server {}{}", fault,
                     orphaned > 0 ? "; the jobs it was rendering count it as a stalled lease" : "");
    if (orphaned > 0)
        spdlog::warn(
            "{} job(s) were running when the last server stopped; they resume from their last "
            "finished pass",
            orphaned);
    files->removeTemporaryFiles();
    files_ = std::move(files);
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
}

void RenderService::openSharedStore() {
    SharedStore shared = server::openSharedStore(config_, counters_, [this] { events_.notify(); });
    store_ = std::move(shared.jobs);
    files_ = std::move(shared.files);
    farm_ = shared.farm;
    renderers_ = std::move(shared.renderers);
    listener_ = std::move(shared.listener);
}

RenderService::~RenderService() {
    stop();
    // Their threads use the events and counters.
    renderers_.reset();
    listener_.reset();
    if (faultFd_ >= 0) {
        int mine = faultFd_;
        faultFd.compare_exchange_strong(mine, -1);
        ::close(faultFd_);
    }
    if (lockFd_ >= 0) ::close(lockFd_);
}

int RenderService::bind() {
    config_.port = gate_->bind(config_.host, config_.port);
    return config_.port;
}

void RenderService::serve() {
    http_->set_keep_alive_timeout(kKeepAliveSeconds);
    http_->set_read_timeout(10);
    http_->set_write_timeout(10);
    ApiContext api{config_,  *jobs_,   counters_, eventStreams_, stopping_,
                   storage_, *assets_, farm_,     connections_};
    registerRoutes(*http_, api);
    startWorkers(true);
    retention_->start();
    gate_->run();
    retention_->stop();
    startWorkers(false);
}

void RenderService::startWorkers(bool start) {
    start ? renderers_->start() : renderers_->stop();
}

void RenderService::wake() {
    renderers_->wake();
}

void RenderService::stop() {
    stopping_ = true;
    events_.notify();
    if (gate_) gate_->stop();
}

}  // namespace caustic::server
