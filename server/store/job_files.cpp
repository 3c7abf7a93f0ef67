#include "store/job_files.h"

#include <unistd.h>

#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "film/image_io.h"

namespace caustic::server {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'C', 'A', 'U', 'S', 'T', 'I', 'C', '1'};

struct CheckpointHeader {
    char magic[8];
    int32_t width, height, passes;
    int32_t reserved;
    uint64_t dropped;
};

template <typename T>
void append(std::string& out, const T* data, size_t count) {
    out.append(reinterpret_cast<const char*>(data), count * sizeof(T));
}

}  // namespace

void writeFileAtomically(const fs::path& file, const std::string& bytes) {
    fs::create_directories(file.parent_path());
    fs::path tmp = file;
    tmp += ".tmp" + std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        if (!out) throw std::runtime_error("cannot write " + tmp.string());
    }
    fs::rename(tmp, file);
}

void JobFiles::writeCheckpoint(const std::string& id, const Film& film) const {
    CheckpointHeader h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.width = film.width();
    h.height = film.height();
    h.passes = film.passes();
    h.dropped = film.droppedSamples();
    std::string bytes;
    bytes.reserve(sizeof h + 2 * film.sums().size() * sizeof(double));
    append(bytes, &h, 1);
    append(bytes, film.sums().data(), film.sums().size());
    append(bytes, film.sumsOfSquares().data(), film.sumsOfSquares().size());
    writeFileAtomically(dir(id) / "checkpoint.bin", bytes);
}

std::unique_ptr<Film> JobFiles::readCheckpoint(const std::string& id, int width, int height) const {
    std::ifstream in(dir(id) / "checkpoint.bin", std::ios::binary);
    if (!in) return nullptr;
    CheckpointHeader h{};
    in.read(reinterpret_cast<char*>(&h), sizeof h);
    if (!in || std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 || h.width != width ||
        h.height != height || h.passes < 0)
        return nullptr;
    const size_t n = size_t(width) * size_t(height) * 3;
    std::vector<double> sum(n), sumSq(n);
    in.read(reinterpret_cast<char*>(sum.data()), std::streamsize(n * sizeof(double)));
    in.read(reinterpret_cast<char*>(sumSq.data()), std::streamsize(n * sizeof(double)));
    if (!in) return nullptr;
    auto film = std::make_unique<Film>(width, height);
    film->restore(std::move(sum), std::move(sumSq), h.passes, h.dropped);
    return film;
}

void JobFiles::removeCheckpoint(const std::string& id) const {
    std::error_code ec;
    fs::remove(dir(id) / "checkpoint.bin", ec);
}

void JobFiles::writeImage(const std::string& id, const std::string& name, const Film& film,
                          double exposure) const {
    fs::create_directories(dir(id));
    // caustic::writeImage writes a temporary file beside the target and renames it.
    caustic::writeImage(dir(id) / name, RgbImage{film.width(), film.height(), film.meanRgb()},
                        exposure);
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
