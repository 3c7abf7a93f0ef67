// Merges passes rendered apart — pass ranges on other threads, processes or machines, arriving in
// any order — into the film of one render that stops at its target error. The error after pass p
// depends on every pass up to p, so passes are added in index order and the error is checked
// after each, as a single process does (render/stopping.h); the first pass that reaches the
// target ends the render and the passes after it are dropped. The film is then bit-identical to
// one process's, whatever the split. Without a target every pass is kept: merging range films
// (Film::merge) gives the same film with less memory.
#pragma once

#include <map>
#include <optional>
#include <vector>

#include "film/film.h"

namespace caustic {

class TargetErrorMerge {
public:
    /// `targetError`: relative RMS error to stop at (0 for none); `bias`: whether the passes carry
    /// their bias (Film's bias layer).
    TargetErrorMerge(int width, int height, double targetError, bool bias = false);

    /// Takes pass `index` (its image and dropped samples, from RenderCallbacks::onPassImage).
    /// Passes after the stop are dropped. Throws std::invalid_argument for a pass taken before.
    void addPass(int index, std::vector<Color> image, uint64_t dropped);

    /// Every pass from the first, up to the stop or the first one still missing.
    const Film& film() const { return film_; }
    /// The pass whose error reached the target, once one has.
    std::optional<int> stopPass() const { return stop_; }
    /// Passes held until those before them arrive (12 bytes a pixel each: whoever hands out the
    /// ranges should do so in order, within a window).
    size_t pending() const { return pending_.size(); }

private:
    struct Pass {
        std::vector<Color> image;
        uint64_t dropped;
    };

    Film film_;
    double targetError_;
    std::map<int, Pass> pending_;
    std::optional<int> stop_;
};

}  // namespace caustic
