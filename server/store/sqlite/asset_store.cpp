// The asset half of the embedded store (store/job_store.h, "Assets"): uploaded meshes as rows with
// their bytes in a BLOB, so that an upload is one transaction (nothing to rename, nothing half
// written after a crash), and the jobs that hold them in job_assets.
#include <nlohmann/json.hpp>

#include "store/page.h"
#include "store/sqlite/job_store.h"
#include "store/sqlite/statement.h"

namespace caustic::server {
using sqlite::exec;
using sqlite::Statement;
using sqlite::Transaction;

namespace {

// The bytes come last: SQLite reads a row's overflow pages only for the columns asked for, so the
// metadata queries never touch a file's bytes.
const char* kAssetSchema = R"sql(
CREATE TABLE IF NOT EXISTS assets (
    seq INTEGER PRIMARY KEY AUTOINCREMENT,
    id TEXT NOT NULL UNIQUE,
    format TEXT NOT NULL,
    name TEXT NOT NULL DEFAULT '',
    bytes INTEGER NOT NULL,
    triangles INTEGER NOT NULL,
    vertices INTEGER NOT NULL,
    bounds TEXT NOT NULL,
    created_at REAL NOT NULL,
    last_used_at REAL NOT NULL,
    data BLOB NOT NULL
);
CREATE TABLE IF NOT EXISTS job_assets (
    job_id TEXT NOT NULL,
    asset_id TEXT NOT NULL,
    PRIMARY KEY (job_id, asset_id)
);
CREATE INDEX IF NOT EXISTS job_assets_by_asset ON job_assets (asset_id);
)sql";

const char* kAssetColumns =
    "seq, id, format, name, bytes, triangles, vertices, bounds, created_at, last_used_at";

Asset readAsset(const Statement& s) {
    Asset a;
    a.seq = s.integer(0);
    a.id = s.text(1);
    a.format = s.text(2);
    a.name = s.text(3);
    a.bytes = s.integer(4);
    a.triangles = s.integer(5);
    a.vertices = s.integer(6);
    const nlohmann::json bounds = nlohmann::json::parse(s.text(7));
    a.boundsMin = bounds.at("min").get<std::array<double, 3>>();
    a.boundsMax = bounds.at("max").get<std::array<double, 3>>();
    a.createdAt = s.real(8);
    a.lastUsedAt = s.real(9);
    return a;
}

std::string selectAssets(const std::string& where) {
    return std::string("SELECT ") + kAssetColumns + " FROM assets " + where;
}

std::optional<Asset> findAsset(sqlite3* db, const std::string& id) {
    Statement s(db, selectAssets("WHERE id = ?"));
    s.bind(1, id);
    if (!s.step()) return std::nullopt;
    return readAsset(s);
}

}  // namespace

void SqliteJobStore::createAssetSchema() {
    exec(db_, kAssetSchema);
}

void SqliteJobStore::holdAssets(const Job& job) {
    for (const std::string& id : job.assets) {
        if (Statement(db_, "UPDATE assets SET last_used_at = MAX(last_used_at, ?2) WHERE id = ?1")
                .bind(1, id)
                .bind(2, job.createdAt)
                .run() == 0)
            throw AssetMissing(id);
        Statement(db_, "INSERT OR IGNORE INTO job_assets (job_id, asset_id) VALUES (?, ?)")
            .bind(1, job.id)
            .bind(2, id)
            .run();
    }
}

AssetInsert SqliteJobStore::insertAsset(Asset& asset, const std::string& bytes,
                                        int64_t maxTotalBytes) {
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    Statement(db_, "UPDATE assets SET last_used_at = MAX(last_used_at, ?2) WHERE id = ?1")
        .bind(1, asset.id)
        .bind(2, asset.lastUsedAt)
        .run();
    if (std::optional<Asset> stored = findAsset(db_, asset.id)) {
        tx.commit();
        asset = *stored;
        return AssetInsert::Existing;
    }
    Statement total(db_, "SELECT COALESCE(SUM(bytes), 0) FROM assets");
    total.step();
    if (total.integer(0) + int64_t(bytes.size()) > maxTotalBytes) return AssetInsert::Full;
    const nlohmann::json bounds{{"min", asset.boundsMin}, {"max", asset.boundsMax}};
    Statement(db_,
              "INSERT INTO assets (id, format, name, bytes, triangles, vertices, bounds, "
              "created_at, last_used_at, data) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)")
        .bind(1, asset.id)
        .bind(2, asset.format)
        .bind(3, asset.name)
        .bind(4, int64_t(bytes.size()))
        .bind(5, asset.triangles)
        .bind(6, asset.vertices)
        .bind(7, bounds.dump())
        .bind(8, asset.createdAt)
        .bind(9, asset.lastUsedAt)
        .bindBlob(10, bytes)
        .run();
    asset.seq = sqlite3_last_insert_rowid(db_);
    asset.bytes = int64_t(bytes.size());
    tx.commit();
    return AssetInsert::Inserted;
}

std::optional<Asset> SqliteJobStore::getAsset(const std::string& id) {
    std::lock_guard lock(mutex_);
    return findAsset(db_, id);
}

std::shared_ptr<const std::string> SqliteJobStore::assetBytes(const std::string& id) {
    std::lock_guard lock(mutex_);
    Statement s(db_, "SELECT data FROM assets WHERE id = ?");
    s.bind(1, id);
    if (!s.step()) return nullptr;
    return std::make_shared<const std::string>(s.blob(0));
}

AssetPage SqliteJobStore::listAssets(int limit, std::optional<int64_t> before) {
    std::lock_guard lock(mutex_);
    Statement s(db_, selectAssets("WHERE seq < ?1 ORDER BY seq DESC LIMIT ?2"));
    s.bind(1, before.value_or(INT64_MAX)).bind(2, int64_t(limit) + 1);
    AssetPage page;
    while (s.step()) page.assets.push_back(readAsset(s));
    page.next = trimPage(page.assets, limit);
    return page;
}

AssetRemoval SqliteJobStore::removeAsset(const std::string& id) {
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    Statement known(db_, "SELECT 1 FROM assets WHERE id = ?");
    known.bind(1, id);
    if (!known.step()) return AssetRemoval::Unknown;
    Statement inUse(db_,
                    "SELECT 1 FROM job_assets JOIN jobs ON jobs.id = job_assets.job_id WHERE "
                    "job_assets.asset_id = ? AND jobs.state IN ('queued', 'running') LIMIT 1");
    inUse.bind(1, id);
    if (inUse.step()) return AssetRemoval::InUse;
    Statement(db_, "DELETE FROM job_assets WHERE asset_id = ?").bind(1, id).run();
    Statement(db_, "DELETE FROM assets WHERE id = ?").bind(1, id).run();
    tx.commit();
    return AssetRemoval::Removed;
}

std::vector<std::string> SqliteJobStore::removeUnusedAssets(double unusedSince) {
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    Statement s(db_,
                "DELETE FROM assets WHERE last_used_at < ? AND NOT EXISTS (SELECT 1 FROM "
                "job_assets WHERE job_assets.asset_id = assets.id) RETURNING id");
    s.bind(1, unusedSince);
    std::vector<std::string> removed;
    while (s.step()) removed.push_back(s.text(0));
    tx.commit();
    return removed;
}

int64_t SqliteJobStore::assetBytesTotal() {
    std::lock_guard lock(mutex_);
    Statement s(db_, "SELECT COALESCE(SUM(bytes), 0) FROM assets");
    s.step();
    return s.integer(0);
}

}  // namespace caustic::server
