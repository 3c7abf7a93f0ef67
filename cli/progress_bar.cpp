#include "progress_bar.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace caustic {
namespace {

std::string clock(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "--:--";
    auto s = static_cast<long>(seconds + 0.5);
    char buf[32];
    if (s >= 3600)
        std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
    else
        std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
    return buf;
}

}  // namespace

void ProgressBar::update(const RenderProgress& p) {
    constexpr int kWidth = 30;
    int filled = static_cast<int>(p.fraction * kWidth);
    std::string bar(size_t(filled), '=');
    if (filled < kWidth) bar += '>' + std::string(size_t(kWidth - filled - 1), ' ');
    // The render's forecast: the spp budget, the time limit or the target error, whichever it
    // expects first (render/forecast.h); named when it is not the budget.
    const char* until = p.etaSeconds < 0                         ? ""
                        : p.etaReason == StopReason::TargetError ? " (target error)"
                        : p.etaReason == StopReason::TimeLimit   ? " (time limit)"
                                                                 : "";
    char err[32] = "";
    if (std::isfinite(p.relativeError))
        std::snprintf(err, sizeof err, "  error %.2f%%", 100.0 * p.relativeError);
    std::fprintf(stderr, "\r[%s] %3d%%  pass %d/%d  %s elapsed, ETA %s%s%s\033[K", bar.c_str(),
                 static_cast<int>(100.0 * p.fraction), p.passesDone, p.passesTotal,
                 clock(p.elapsedSeconds).c_str(), clock(p.etaSeconds).c_str(), until, err);
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressBar::finish() {
    if (drawn_) std::fprintf(stderr, "\r\033[K");
    drawn_ = false;
}

}  // namespace caustic
