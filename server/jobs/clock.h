// Wall-clock time stamps of the job store (Unix seconds).
#pragma once

#include <chrono>

namespace caustic::server {

/// Seconds since the Unix epoch.
inline double unixNow() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}

}  // namespace caustic::server
