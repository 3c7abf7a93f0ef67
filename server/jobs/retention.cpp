#include "jobs/retention.h"

#include <chrono>
#include <string>

#include <spdlog/spdlog.h>

#include "jobs/clock.h"
#include "store/disk_space.h"

namespace caustic::server {

RetentionSweeper::RetentionSweeper(const ServerConfig& config, JobStore& store,
                                   const JobFiles& files, JobEvents& events,
                                   StorageCounters& counters)
    : config_(config), store_(store), files_(files), events_(events), counters_(counters) {}

RetentionSweeper::~RetentionSweeper() {
    stop();
}

void RetentionSweeper::start() {
    stopping_ = false;
    thread_ = std::thread([this] { run(); });
}

void RetentionSweeper::stop() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void RetentionSweeper::run() {
    const auto period = std::chrono::duration<double>(config_.storage.sweepSeconds);
    std::unique_lock lock(mutex_);
    while (!stopping_) {
        lock.unlock();
        sweep(unixNow());
        lock.lock();
        wake_.wait_for(lock, period, [this] { return stopping_; });
    }
}

int RetentionSweeper::sweep(double now) {
    int removed = 0;
    try {
        removed = removeExpiredJobs(now);
    } catch (const std::exception& e) {
        spdlog::error("retention: {}", e.what());
    }
    try {
        removed += removeUnusedAssets(now);
        if (removed > 0) store_.reclaimSpace();
    } catch (const std::exception& e) {
        spdlog::error("retention: {}", e.what());
    }
    counters_.dataBytes = diskUsage(config_.dataDir);
    ++counters_.sweeps;
    return removed;
}

int RetentionSweeper::removeUnusedAssets(double now) {
    // An asset is used while a job that names it exists (finished ones included, until retention
    // or a client deletes them): it goes --keep-days after its last use by an upload or a job.
    const double keepDays = config_.storage.keepDays;
    if (keepDays <= 0) return 0;
    const std::vector<std::string> ids = store_.removeUnusedAssets(now - keepDays * 86400);
    if (ids.empty()) return 0;
    counters_.assetsRemoved += ids.size();
    std::string list;
    for (const std::string& id : ids) list += (list.empty() ? "" : " ") + id;
    spdlog::info("retention removed {} asset(s) no job used for {} day(s) (--keep-days): {}",
                 ids.size(), keepDays, list);
    return int(ids.size());
}

int RetentionSweeper::removeExpiredJobs(double now) {
    const StoragePolicy& policy = config_.storage;
    // --keep-days 0 keeps jobs whatever their age; --max-stored-jobs 0 whatever their number.
    const double cutoff = policy.keepDays > 0 ? now - policy.keepDays * 86400 : -1;
    const int64_t keep = policy.maxStoredJobs > 0 ? policy.maxStoredJobs : -1;
    int tooOld = 0, overCount = 0;
    std::string ids;
    for (const ExpiredJob& job : store_.expiredJobs(cutoff, keep)) {
        // The record first: a job the API lists always has its files.
        if (!store_.remove(job.id)) continue;  // deleted by a client meanwhile
        files_.remove(job.id);
        ids += (ids.empty() ? "" : " ") + job.id;
        ++(job.tooOld ? tooOld : overCount);
        ++(job.tooOld ? counters_.jobsRemovedTooOld : counters_.jobsRemovedOverCount);
    }
    if (tooOld + overCount == 0) return 0;
    events_.notify();
    spdlog::info(
        "retention removed {} finished job(s) and their files: {} finished more than {} day(s) "
        "ago (--keep-days), {} beyond the newest {} (--max-stored-jobs): {}",
        tooOld + overCount, tooOld, policy.keepDays, overCount, policy.maxStoredJobs, ids);
    return tooOld + overCount;
}

}  // namespace caustic::server
