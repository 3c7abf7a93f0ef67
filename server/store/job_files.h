// A job's files: checkpoint.bin (the film after the last finished pass), preview.png (the film so
// far) and image.png / image.exr (the result). Where they live is the store's choice: the data
// folder for the embedded store (FolderJobFiles), the database itself for a store that several
// machines share (store/stored_job_files.h), so that nodes share nothing but the database.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "film/film.h"

namespace caustic::server {

class JobFiles {
public:
    virtual ~JobFiles() = default;

    /// Writes a file of a job's attempt whole: a reader never sees part of one. Returns false,
    /// writing nothing, where the store can tell that `attempt` is no longer the job's current
    /// one (the folder cannot: two attempts write the same bytes, as every pass depends only on
    /// its index). Throws StorageFull when there is no room.
    virtual bool write(const std::string& id, int attempt, const std::string& name,
                       const std::string& bytes) const = 0;
    /// A job's file; nothing when it does not exist (yet).
    virtual std::optional<std::string> read(const std::string& id,
                                            const std::string& name) const = 0;
    virtual void removeFile(const std::string& id, const std::string& name) const = 0;
    /// Deletes every file of the job.
    virtual void remove(const std::string& id) const = 0;

    /// Saves the film (its exact sums and pass set, so a resumed render is bit-identical).
    bool writeCheckpoint(const std::string& id, int attempt, const Film& film) const {
        return write(id, attempt, "checkpoint.bin", film.toBytes());
    }
    /// The saved film, or null when there is none or it does not fit width x height (a torn or
    /// foreign file is ignored: the render starts over).
    std::unique_ptr<Film> readCheckpoint(const std::string& id, int width, int height) const;
    void removeCheckpoint(const std::string& id) const { removeFile(id, "checkpoint.bin"); }
    /// Writes the film's mean as image.png (with exposure), image.exr, or preview.png.
    bool writeImage(const std::string& id, int attempt, const std::string& name, const Film& film,
                    double exposure) const;
};

/// The embedded store's files: data/jobs/<id>/<name>, each written to a temporary name and
/// renamed.
class FolderJobFiles final : public JobFiles {
public:
    explicit FolderJobFiles(std::filesystem::path dataDir) : root_(std::move(dataDir) / "jobs") {}

    bool write(const std::string& id, int attempt, const std::string& name,
               const std::string& bytes) const override;
    std::optional<std::string> read(const std::string& id, const std::string& name) const override;
    void removeFile(const std::string& id, const std::string& name) const override;
    void remove(const std::string& id) const override;

    /// Deletes the temporary files that writers killed before their rename left in job folders
    /// (at start-up, when the data folder's lock proves that nobody is writing); returns how many.
    int removeTemporaryFiles() const;

private:
    std::filesystem::path dir(const std::string& id) const { return root_ / id; }

    std::filesystem::path root_;
};

/// Writes `bytes` to `file` through a temporary file in the same folder and a rename, and syncs
/// the file and its folder (and any folder created for it): when it returns, the file survives a
/// power cut. Throws StorageFull on a full disk, std::runtime_error on other failures.
void writeFileAtomically(const std::filesystem::path& file, const std::string& bytes);

}  // namespace caustic::server
