#include "farm/consolidator.h"

#include <chrono>

#include <spdlog/spdlog.h>

namespace caustic::server {

Consolidator::Consolidator(PostgresJobStore& store, double intervalSeconds)
    : store_(store), intervalSeconds_(intervalSeconds), thread_([this] { run(); }) {}

Consolidator::~Consolidator() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void Consolidator::wake() {
    {
        std::lock_guard lock(mutex_);
        woken_ = true;
    }
    wake_.notify_all();
}

void Consolidator::round() {
    for (const std::string& id : store_.jobsToConsolidate(intervalSeconds_)) {
        // A batch that leaves results waiting (its budget spent) is followed by the next at
        // once: the job's last batch must not wait for the pace.
        Consolidation c = Consolidation::More;
        while (c == Consolidation::More && !stopping_) c = store_.consolidate(id);
    }
}

void Consolidator::run() {
    while (!stopping_) {
        try {
            round();
        } catch (const std::exception& e) {
            // The store out of reach: the results wait in their rows for the next round.
            spdlog::warn("consolidating results: {}", e.what());
        }
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, std::chrono::milliseconds(250),
                       [this] { return woken_ || stopping_; });
        woken_ = false;
    }
}

}  // namespace caustic::server
