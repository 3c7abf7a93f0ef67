// How much space the data folder uses and how much its file system has left: for /metrics, for
// refusing submissions before the disk is full (--min-free-mib), and for telling a failed write
// that ran out of space from one that failed otherwise.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace caustic::server {

struct DiskSpace {
    uint64_t freeBytes = 0;   ///< Available to this (unprivileged) process: statvfs f_bavail.
    uint64_t totalBytes = 0;  ///< The file system's size: f_blocks.
};

/// The file system holding `path` (statvfs); nothing when it cannot be read. Cheap: one system
/// call, fine per request.
std::optional<DiskSpace> diskSpace(const std::filesystem::path& path);

/// Why a write of `writing` bytes to the data folder `dataDir` is refused before it starts: its
/// file system would have less than `minFreeMiB` (--min-free-mib) left. Nothing when there is room
/// (or the space cannot be read: the write itself then finds out). `what` names the write.
std::optional<std::string> lowDiskSpace(const std::filesystem::path& dataDir, double minFreeMiB,
                                        uint64_t writing, const std::string& what);

/// Bytes the files under `path` take on disk (allocated blocks, as `du` counts them), `path`
/// included; a file that vanishes during the walk counts 0, and a folder that does ends the walk
/// early (an undercount until the next one). Walks the whole tree:
/// call it now and then (the retention sweep), not per request.
uint64_t diskUsage(const std::filesystem::path& path);

}  // namespace caustic::server
