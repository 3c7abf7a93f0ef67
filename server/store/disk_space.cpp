#include "store/disk_space.h"

#include <sys/stat.h>
#include <sys/statvfs.h>

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
