// The asset half of the PostgreSQL store (store/job_store.h, "Assets"): uploaded meshes as rows
// with their bytes in a bytea, and the jobs that hold them in job_assets, as on SQLite.
#include <nlohmann/json.hpp>

#include "store/page.h"
#include "store/postgres/job_store.h"
#include "store/postgres/transaction.h"

namespace caustic::server {
using postgres::transact;

namespace {

const char* kAssetColumns =
    "seq, id, format, name, bytes, triangles, vertices, bounds, created_at, last_used_at";

// pg_advisory_xact_lock's key serializing uploads, so that two processes storing assets at once
// cannot both pass the storage limit: "assets" in ASCII.
constexpr int64_t kAssetInsertLock = 0x617373657473;

Asset readAsset(const pqxx::row& r) {
    Asset a;
    a.seq = r[0].as<int64_t>();
    a.id = r[1].as<std::string>();
    a.format = r[2].as<std::string>();
    a.name = r[3].as<std::string>();
    a.bytes = r[4].as<int64_t>();
    a.triangles = r[5].as<int64_t>();
    a.vertices = r[6].as<int64_t>();
    const nlohmann::json bounds = nlohmann::json::parse(r[7].as<std::string>());
    a.boundsMin = bounds.at("min").get<std::array<double, 3>>();
    a.boundsMax = bounds.at("max").get<std::array<double, 3>>();
    a.createdAt = r[8].as<double>();
    a.lastUsedAt = r[9].as<double>();
    return a;
}

std::string selectAssets(const std::string& where) {
    return std::string("SELECT ") + kAssetColumns + " FROM assets " + where;
}

std::optional<Asset> findAsset(pqxx::work& tx, const std::string& id) {
    pqxx::result r = tx.exec_params(selectAssets("WHERE id = $1"), id);
    if (r.empty()) return std::nullopt;
    return readAsset(r[0]);
}

int64_t totalBytes(pqxx::work& tx) {
    return tx.exec1("SELECT COALESCE(SUM(bytes), 0)::BIGINT FROM assets")[0].as<int64_t>();
}

}  // namespace

AssetInsert PostgresJobStore::insertAsset(Asset& asset, const std::string& bytes,
                                          int64_t maxTotalBytes) {
    return transact(*pool_, [&](pqxx::work& tx) {
        tx.exec_params("SELECT pg_advisory_xact_lock($1)", kAssetInsertLock);
        tx.exec_params("UPDATE assets SET last_used_at = GREATEST(last_used_at, $2) WHERE id = $1",
                       asset.id, asset.lastUsedAt);
        if (std::optional<Asset> stored = findAsset(tx, asset.id)) {
            asset = *stored;
            return AssetInsert::Existing;
        }
        if (totalBytes(tx) + int64_t(bytes.size()) > maxTotalBytes) return AssetInsert::Full;
        const nlohmann::json bounds{{"min", asset.boundsMin}, {"max", asset.boundsMax}};
        asset.seq = tx.exec_params1(
                          "INSERT INTO assets (id, format, name, bytes, triangles, "
                          "vertices, bounds, created_at, last_used_at, data) VALUES "
                          "($1, $2, $3, $4, $5, $6, $7, $8, $9, $10) RETURNING seq",
                          asset.id, asset.format, asset.name, int64_t(bytes.size()),
                          asset.triangles, asset.vertices, bounds.dump(), asset.createdAt,
                          asset.lastUsedAt, pqxx::binarystring(bytes))[0]
                        .as<int64_t>();
        asset.bytes = int64_t(bytes.size());
        return AssetInsert::Inserted;
    });
}

std::optional<Asset> PostgresJobStore::getAsset(const std::string& id) {
    return transact(*pool_, [&](pqxx::work& tx) { return findAsset(tx, id); });
}

std::shared_ptr<const std::string> PostgresJobStore::assetBytes(const std::string& id) {
    return transact(*pool_, [&](pqxx::work& tx) {
        pqxx::result r = tx.exec_params("SELECT data FROM assets WHERE id = $1", id);
        if (r.empty()) return std::shared_ptr<const std::string>();
        return std::make_shared<const std::string>(pqxx::binarystring(r[0][0]).str());
    });
}

AssetPage PostgresJobStore::listAssets(int limit, std::optional<int64_t> before) {
    return transact(*pool_, [&](pqxx::work& tx) {
        AssetPage page;
        for (const pqxx::row& r :
             tx.exec_params(selectAssets("WHERE seq < $1 ORDER BY seq DESC LIMIT $2"),
                            before.value_or(INT64_MAX), int64_t(limit) + 1))
            page.assets.push_back(readAsset(r));
        page.next = trimPage(page.assets, limit);
        return page;
    });
}

AssetRemoval PostgresJobStore::removeAsset(const std::string& id) {
    return transact(*pool_, [&](pqxx::work& tx) {
        // The row lock orders this against a job's insert (holdAssets updates the row): either
        // the job is seen below, or the job finds no asset.
        if (tx.exec_params("SELECT 1 FROM assets WHERE id = $1 FOR UPDATE", id).empty())
            return AssetRemoval::Unknown;
        if (!tx.exec_params("SELECT 1 FROM job_assets JOIN jobs ON jobs.id = job_assets.job_id "
                            "WHERE job_assets.asset_id = $1 AND jobs.state IN ('queued', "
                            "'running') LIMIT 1",
                            id)
                 .empty())
            return AssetRemoval::InUse;
        tx.exec_params("DELETE FROM job_assets WHERE asset_id = $1", id);
        tx.exec_params("DELETE FROM assets WHERE id = $1", id);
        return AssetRemoval::Removed;
    });
}

std::vector<std::string> PostgresJobStore::removeUnusedAssets(double unusedSince) {
    return transact(*pool_, [&](pqxx::work& tx) {
        std::vector<std::string> removed;
        for (const pqxx::row& r :
             tx.exec_params("DELETE FROM assets WHERE last_used_at < $1 AND NOT EXISTS (SELECT 1 "
                            "FROM job_assets WHERE job_assets.asset_id = assets.id) RETURNING id",
                            unusedSince))
            removed.push_back(r[0].as<std::string>());
        return removed;
    });
}

int64_t PostgresJobStore::assetBytesTotal() {
    return transact(*pool_, [&](pqxx::work& tx) { return totalBytes(tx); });
}

void PostgresJobStore::reclaimSpace() {
    // VACUUM cannot run in a transaction block. Autovacuum does the same in its own time; this
    // makes the space of the rows retention just removed reusable (and gives back the tables'
    // empty tails) now.
    postgres::Pool::Lease connection = pool_->acquire();
    pqxx::nontransaction tx(connection.get());
    tx.exec("VACUUM jobs, idempotency, assets, job_assets");
}

}  // namespace caustic::server
