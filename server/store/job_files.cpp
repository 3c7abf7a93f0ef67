#include "store/job_files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <vector>

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
    // On the disk before it is renamed into place: a rename can reach the disk before the data
    // it names, leaving an empty file after a power cut (ext4 with data=writeback, XFS).
    if (error == 0 && ::fsync(fd) != 0) error = errno;
    // close(2) can report a deferred write error (NFS, quotas).
    if (::close(fd) != 0 && error == 0) error = errno;
    return error;
}

// Makes a folder's entries durable: a file created or renamed in it is in the folder only once the
// folder itself is synced (fsync(2): "Calling fsync() does not necessarily ensure that the entry in
// the directory containing the file has also reached disk"), as SQLite does for its journal.
int syncFolder(const fs::path& folder) {
    int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return errno;
    int error = ::fsync(fd) == 0 ? 0 : errno;
    ::close(fd);
    return error;
}

// The folders from `file`'s up to the first that exists, which creating them adds an entry to.
std::vector<fs::path> foldersToCreate(const fs::path& file) {
    std::vector<fs::path> folders;
    fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
    for (; !folder.empty() && !fs::exists(folder); folder = folder.parent_path())
        folders.push_back(folder);
    if (!folder.empty()) folders.push_back(folder);
    return folders;
}

}  // namespace

void writeFileAtomically(const fs::path& file, const std::string& bytes) {
    fs::path tmp = file;
    tmp += ".tmp" + std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}());
    int error = 0;
    try {
        // The file's folder and any folder created for it are synced after the rename: the file
        // is on the disk when this returns (and a commit that names it may follow).
        const std::vector<fs::path> folders = foldersToCreate(file);
        fs::create_directories(file.parent_path());
        error = writeNewFile(tmp, bytes);
        if (error == 0) fs::rename(tmp, file);
        for (size_t i = 0; i < folders.size() && error == 0; ++i) error = syncFolder(folders[i]);
    } catch (const fs::filesystem_error& e) {
        error = e.code().value();
    }
    if (error == 0) return;
    std::error_code ignored;
    fs::remove(tmp, ignored);
    if (isNoSpaceError(error)) throw StorageFull(fullDiskMessage(file));
    throw std::runtime_error("cannot write " + file.string() + ": " + std::strerror(error));
}

std::unique_ptr<Film> JobFiles::readCheckpoint(const std::string& id, int width, int height) const {
    std::optional<std::string> bytes = read(id, "checkpoint.bin");
    return bytes ? Film::fromBytes(*bytes, width, height) : nullptr;
}

bool JobFiles::writeImage(const std::string& id, int attempt, const std::string& name,
                          const Film& film, double exposure) const {
    const std::string format = fs::path(name).extension().string().substr(1);
    const RgbImage image{film.width(), film.height(), film.meanRgb()};
    return write(id, attempt, name, encodeImage(image, format, format == "png" ? exposure : 0.0));
}

bool FolderJobFiles::write(const std::string& id, int, const std::string& name,
                           const std::string& bytes) const {
    writeFileAtomically(dir(id) / name, bytes);
    return true;
}

std::optional<std::string> FolderJobFiles::read(const std::string& id,
                                                const std::string& name) const {
    std::ifstream in(dir(id) / name, std::ios::binary);
    if (!in) return std::nullopt;
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void FolderJobFiles::removeFile(const std::string& id, const std::string& name) const {
    std::error_code ec;
    fs::remove(dir(id) / name, ec);
}

void FolderJobFiles::remove(const std::string& id) const {
    std::error_code ec;
    fs::remove_all(dir(id), ec);
}

int FolderJobFiles::removeTemporaryFiles() const {
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
