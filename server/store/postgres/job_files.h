// Job files kept in the PostgreSQL store (table job_files), so that a worker on any machine
// writes a job's checkpoint and images and an API process on any other serves them. Writes are
// fenced by attempt, as every other write of a lease holder.
#pragma once

#include "store/job_files.h"
#include "store/postgres/job_store.h"

namespace caustic::server {

class PostgresJobFiles final : public JobFiles {
public:
    explicit PostgresJobFiles(PostgresJobStore& store) : store_(store) {}

    bool write(const std::string& id, int attempt, const std::string& name,
               const std::string& bytes) const override {
        return store_.putFile(id, attempt, name, bytes);
    }
    std::optional<std::string> read(const std::string& id, const std::string& name) const override {
        return store_.getFile(id, name);
    }
    void removeFile(const std::string& id, const std::string& name) const override {
        store_.removeFiles(id, name);
    }
    void remove(const std::string& id) const override { store_.removeFiles(id); }

private:
    PostgresJobStore& store_;
};

}  // namespace caustic::server
