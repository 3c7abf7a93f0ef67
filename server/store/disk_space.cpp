#include "store/disk_space.h"

#include <sys/stat.h>
#include <sys/statvfs.h>

#include <cstdio>

namespace caustic::server {
namespace fs = std::filesystem;

namespace {

// st_blocks counts 512-byte units whatever the file system's block size (POSIX <sys/stat.h>).
uint64_t allocatedBytes(const fs::path& file) {
    struct stat st {};
    return ::lstat(file.c_str(), &st) == 0 ? uint64_t(st.st_blocks) * 512 : 0;
}

}  // namespace

std::optional<DiskSpace> diskSpace(const fs::path& path) {
    struct statvfs s {};
    if (::statvfs(path.c_str(), &s) != 0) return std::nullopt;
    return DiskSpace{uint64_t(s.f_bavail) * s.f_frsize, uint64_t(s.f_blocks) * s.f_frsize};
}

std::optional<std::string> lowDiskSpace(const fs::path& dataDir, double minFreeMiB,
                                        uint64_t writing, const std::string& what) {
    if (minFreeMiB <= 0) return std::nullopt;  // 0: no check; a write finds a full disk itself
    std::optional<DiskSpace> space = diskSpace(dataDir);
    if (!space || double(space->freeBytes) >= minFreeMiB * 1048576 + double(writing))
        return std::nullopt;
    char minFree[32];
    std::snprintf(minFree, sizeof minFree, "%g", minFreeMiB);
    return "the data folder's disk is full: " + std::to_string(space->freeBytes >> 20) +
           " MiB free, under the " + minFree + " MiB that must stay free (--min-free-mib) after " +
           what + "; free space and retry";
}

uint64_t diskUsage(const fs::path& path) {
    uint64_t bytes = allocatedBytes(path);
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(path, ec))) return bytes;
    // Jobs come and go while the sweep walks: skip what disappears instead of stopping.
    for (auto it = fs::recursive_directory_iterator(
             path, fs::directory_options::skip_permission_denied, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
        bytes += allocatedBytes(it->path());
    return bytes;
}

}  // namespace caustic::server
