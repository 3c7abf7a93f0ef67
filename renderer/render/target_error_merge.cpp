#include "render/target_error_merge.h"

#include <stdexcept>
#include <string>

#include "render/stopping.h"

namespace caustic {

TargetErrorMerge::TargetErrorMerge(int width, int height, double targetError, bool bias)
    : film_(width, height, bias), targetError_(targetError) {}

void TargetErrorMerge::addPass(int index, std::vector<Color> image, uint64_t dropped) {
    if (index < 0 || index >= exact::kMaxPasses)
        throw std::invalid_argument("pass index " + std::to_string(index) + " out of range");
    if (film_.passSet().overlaps(index, index + 1) || pending_.count(index))
        throw std::invalid_argument("pass " + std::to_string(index) + " was merged already");
    if (stop_ && index > *stop_) return;
    pending_.emplace(index, Pass{std::move(image), dropped});
    // Add the passes that now follow the film's, checking the target after each.
    for (auto next = pending_.find(film_.passSet().end()); next != pending_.end() && !stop_;
         next = pending_.find(film_.passSet().end())) {
        film_.addPass(next->first, next->second.image, next->second.dropped);
        pending_.erase(next);
        if (reachedTargetError(film_, targetError_)) stop_ = film_.passSet().end() - 1;
    }
    if (stop_) pending_.clear();
}

}  // namespace caustic
