// The job-file half of the PostgreSQL store (store/postgres/job_files.h).
#include "store/postgres/job_store.h"
#include "store/postgres/transaction.h"

namespace caustic::server {
using postgres::transact;

bool PostgresJobStore::putFile(const std::string& id, int attempt, const std::string& name,
                               const std::string& bytes) {
    return transact(*pool_, [&](pqxx::work& tx) {
        // The job's row lock orders this against a newer claim: a write of an old attempt that
        // commits after the claim finds another attempt and writes nothing.
        return !tx.exec_params(
                      "INSERT INTO job_files (job_id, name, data) "
                      "SELECT id, $3, $4 FROM jobs WHERE id = $1 AND attempt = $2 "
                      "FOR UPDATE "
                      "ON CONFLICT (job_id, name) DO UPDATE SET data = excluded.data "
                      "RETURNING 1",
                      id, attempt, name, pqxx::binarystring(bytes))
                    .empty();
    });
}

std::optional<std::string> PostgresJobStore::getFile(const std::string& id,
                                                     const std::string& name) {
    return transact(*pool_, [&](pqxx::work& tx) -> std::optional<std::string> {
        pqxx::result r =
            tx.exec_params("SELECT data FROM job_files WHERE job_id = $1 AND name = $2", id, name);
        if (r.empty()) return std::nullopt;
        return pqxx::binarystring(r[0][0]).str();
    });
}

void PostgresJobStore::removeFiles(const std::string& id, const std::string& name) {
    transact(*pool_, [&](pqxx::work& tx) {
        if (name.empty())
            tx.exec_params("DELETE FROM job_files WHERE job_id = $1", id);
        else
            tx.exec_params("DELETE FROM job_files WHERE job_id = $1 AND name = $2", id, name);
        return 0;
    });
}

}  // namespace caustic::server
