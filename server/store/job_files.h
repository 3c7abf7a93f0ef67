// A job's files in the data folder: data/jobs/<id>/ holds checkpoint.bin (the film after the last
// finished pass), preview.png (the film so far) and image.png / image.exr (the result). Every file
// is written to a temporary name and renamed, so a reader or a restarted server never sees a
// partial one.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "film/film.h"

namespace caustic::server {

class JobFiles {
public:
    explicit JobFiles(std::filesystem::path dataDir) : root_(std::move(dataDir) / "jobs") {}

    std::filesystem::path dir(const std::string& id) const { return root_ / id; }
    std::filesystem::path image(const std::string& id, const std::string& name) const {
        return dir(id) / name;
    }

    /// Saves the film (its exact sums and pass set, so a resumed render is bit-identical).
    void writeCheckpoint(const std::string& id, const Film& film) const;
    /// The saved film, or null when there is none or it does not fit width x height (a torn or
    /// foreign file is ignored: the render starts over).
    std::unique_ptr<Film> readCheckpoint(const std::string& id, int width, int height) const;
    void removeCheckpoint(const std::string& id) const;
    /// Writes the film's mean as image.png (with exposure), image.exr, or preview.png.
    void writeImage(const std::string& id, const std::string& name, const Film& film,
                    double exposure) const;
    /// Deletes every file of the job.
    void remove(const std::string& id) const;
    /// Deletes the temporary files that writers killed before their rename left in job folders
    /// (at start-up, when the data folder's lock proves that nobody is writing); returns how many.
    int removeTemporaryFiles() const;

private:
    std::filesystem::path root_;
};

/// Writes `bytes` to `file` through a temporary file in the same folder and a rename.
void writeFileAtomically(const std::filesystem::path& file, const std::string& bytes);

}  // namespace caustic::server
