#include "store/job_files.h"

#include <unistd.h>

#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>

#include "film/image_io.h"

namespace caustic::server {
namespace fs = std::filesystem;

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
