// What changes between store writes: a running job's live progress (updated about every 100 ms by
// its render), and a version number that wakes every event stream when any job changes.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "render/stopping.h"

namespace caustic::server {

struct LiveProgress {
    double fraction = 0;
    int passesTotal = 0;
    double relativeError = 0;
    double etaSeconds = -1;
    StopReason etaReason = StopReason::Spp;  ///< What the forecast expects to stop the render.
};

class JobEvents {
public:
    /// Something about some job changed: wake the waiters.
    void notify() {
        {
            std::lock_guard lock(mutex_);
            ++version_;
        }
        changed_.notify_all();
    }
    /// Waits until the version moves past `seen` (then updates it) or `timeout` passes; returns
    /// whether it moved.
    bool wait(uint64_t& seen, std::chrono::milliseconds timeout) {
        std::unique_lock lock(mutex_);
        bool moved = changed_.wait_for(lock, timeout, [&] { return version_ != seen; });
        seen = version_;
        return moved;
    }
    uint64_t version() {
        std::lock_guard lock(mutex_);
        return version_;
    }

    void setLive(const std::string& id, const LiveProgress& p) {
        {
            std::lock_guard lock(mutex_);
            live_[id] = p;
            ++version_;
        }
        changed_.notify_all();
    }
    void clearLive(const std::string& id) {
        std::lock_guard lock(mutex_);
        live_.erase(id);
    }
    std::optional<LiveProgress> live(const std::string& id) {
        std::lock_guard lock(mutex_);
        auto it = live_.find(id);
        if (it == live_.end()) return std::nullopt;
        return it->second;
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    uint64_t version_ = 0;
    std::map<std::string, LiveProgress> live_;
};

}  // namespace caustic::server
