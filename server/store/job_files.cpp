#include "store/job_files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>

#include "film/image_io.h"
#include "store/disk_space.h"
#include "store/storage_full.h"

namespace caustic::server {
namespace fs = std::filesystem;

namespace {

std::string fullDiskMessage(const fs::path& file) {
    return "the data folder's disk is full while writing " + file.filename().string();
}

// Writes all of `bytes` to a new file; returns 0 or the errno of the first failure (the file may
// then exist, partly written). POSIX calls rather than a stream: a stream's failure carries no
// errno, and a full disk must be told from other failures.
int writeNewFile(const fs::path& file, const std::string& bytes) {
    int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return errno;
    int error = 0;
    for (size_t done = 0; done < bytes.size() && error == 0;) {
        ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n > 0)
            done += size_t(n);
        else if (n == 0 || errno != EINTR)
            error = n == 0 ? ENOSPC : errno;  // write(2) returns 0 only when nothing fits
    }
    // close(2) can report a deferred write error (NFS, quotas).
    if (::close(fd) != 0 && error == 0) error = errno;
    return error;
}

// True when `e` is a file system error of a full disk (creating a folder, renaming).
bool isNoSpace(const std::exception& e) {
    auto* fsError = dynamic_cast<const fs::filesystem_error*>(&e);
    return fsError && isNoSpaceError(fsError->code().value());
}

}  // namespace

void writeFileAtomically(const fs::path& file, const std::string& bytes) {
    fs::path tmp = file;
    tmp += ".tmp" + std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}());
    int error = 0;
    try {
        fs::create_directories(file.parent_path());
        error = writeNewFile(tmp, bytes);
        if (error == 0) fs::rename(tmp, file);
    } catch (const fs::filesystem_error& e) {
        error = e.code().value();
    }
    if (error == 0) return;
    std::error_code ignored;
    fs::remove(tmp, ignored);
    if (isNoSpaceError(error)) throw StorageFull(fullDiskMessage(file));
    throw std::runtime_error("cannot write " + file.string() + ": " + std::strerror(error));
}

void JobFiles::writeCheckpoint(const std::string& id, const Film& film) const {
    writeFileAtomically(dir(id) / "checkpoint.bin", film.toBytes());
}

std::unique_ptr<Film> JobFiles::readCheckpoint(const std::string& id, int width, int height) const {
    std::ifstream in(dir(id) / "checkpoint.bin", std::ios::binary);
    if (!in) return nullptr;
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return Film::fromBytes(bytes, width, height);
}

void JobFiles::removeCheckpoint(const std::string& id) const {
    std::error_code ec;
    fs::remove(dir(id) / "checkpoint.bin", ec);
}

void JobFiles::writeImage(const std::string& id, const std::string& name, const Film& film,
                          double exposure) const {
    try {
        fs::create_directories(dir(id));
        // caustic::writeImage writes a temporary file beside the target and renames it (and
        // removes the temporary file when the write fails).
        caustic::writeImage(dir(id) / name, RgbImage{film.width(), film.height(), film.meanRgb()},
                            exposure);
    } catch (const std::exception& e) {
        // OpenImageIO reports a failed write in its own words, without errno: a file system with
        // less room left than the uncompressed pixels (a bound on either format's size) ran out.
        const uint64_t rawBytes = uint64_t(film.width()) * uint64_t(film.height()) * 3 * 4;
        std::optional<DiskSpace> space = diskSpace(root_.parent_path());
        if (isNoSpace(e) || (space && space->freeBytes < rawBytes + 65536))
            throw StorageFull(fullDiskMessage(name));
        throw;
    }
}

void JobFiles::remove(const std::string& id) const {
    std::error_code ec;
    fs::remove_all(dir(id), ec);
}

int JobFiles::removeTemporaryFiles() const {
    // A job's own files have fixed names; ".tmp" marks those of writeFileAtomically and
    // caustic::writeImage.
    int removed = 0;
    std::error_code ec;
    try {
        for (const auto& job : fs::directory_iterator(root_, ec))
            for (const auto& file : fs::directory_iterator(job.path(), ec))
                if (file.is_regular_file(ec) &&
                    file.path().filename().string().find(".tmp") != std::string::npos &&
                    fs::remove(file.path(), ec))
                    ++removed;
    } catch (const fs::filesystem_error&) {
        // A folder that cannot be read keeps its leftovers: they only take space.
    }
    return removed;
}

}  // namespace caustic::server
