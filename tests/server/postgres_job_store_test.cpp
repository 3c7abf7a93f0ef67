// What the PostgreSQL store adds to the protocol every store keeps (job_store_test.cpp): several
// processes on one database (here one connection each, on threads) claim every job exactly once,
// settle each expired lease once, keep one job per idempotency key and the asset storage limit;
// the schema's migrations are versioned; a restarted server is reconnected to.
#ifdef CAUSTIC_HAS_POSTGRES

#include <gtest/gtest.h>

#include <pqxx/pqxx>

#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "support/job_store_backends.h"

namespace caustic::server {
namespace {

using testing::PostgresBackend;
using testing::PostgresCluster;

constexpr int kProcesses = 4;

// prefix + i (not operator+ on a literal, which GCC 12's -Wrestrict misreads).
std::string named(const char* prefix, int i) {
    return std::string(prefix).append(std::to_string(i));
}

class PostgresJobStoreTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (std::optional<std::string> why = PostgresBackend::unavailable()) GTEST_SKIP() << *why;
        backend_.create();
    }
    void TearDown() override { backend_.destroy(); }

    // Runs body(store, i) on kProcesses threads, each with a store (a connection) of its own.
    template <class Body>
    void inProcesses(Body body) {
        std::vector<std::unique_ptr<JobStore>> stores;
        for (int i = 0; i < kProcesses; ++i) stores.push_back(backend_.open());
        std::vector<std::thread> threads;
        for (int i = 0; i < kProcesses; ++i) threads.emplace_back([&, i] { body(*stores[i], i); });
        for (std::thread& t : threads) t.join();
    }
    static Job job(const std::string& id) {
        Job j;
        j.id = id;
        j.scene = Json::object();
        j.settings = Json::object();
        return j;
    }

    // Inserts jobs j0, j1, ...; with `claimed`, each is leased at once until 1010.
    void submitJobs(int n, bool claimed) {
        std::unique_ptr<JobStore> store = backend_.open();
        for (int i = 0; i < n; ++i) {
            Job j = job(named("j", i));
            store->insert(j);
            if (claimed) {
                ASSERT_TRUE(store->claim("gone", 1000, 10, 3, 100));
            }
        }
    }
    // Claims at `now` from every process until the queue is empty; how often each job was
    // claimed. Each claim must be the job's attempt `attempt`, after `stalls` stalled leases.
    std::map<std::string, int> claimAll(double now, int attempt, int stalls) {
        std::mutex mutex;
        std::map<std::string, int> claims;
        inProcesses([&](JobStore& store, int i) {
            while (std::optional<Job> j = store.claim(named("w", i), now, 10, 3, 100)) {
                EXPECT_EQ(j->attempt, attempt) << j->id;
                EXPECT_EQ(j->stalledLeases, stalls) << j->id;
                std::lock_guard lock(mutex);
                ++claims[j->id];
            }
        });
        return claims;
    }

    PostgresBackend backend_;
};

TEST_F(PostgresJobStoreTest, ConcurrentClaimersTakeEachJobOnce) {
    submitJobs(40, false);
    std::map<std::string, int> claims = claimAll(1000, 1, 0);
    EXPECT_EQ(claims.size(), 40u);
    for (const auto& [id, n] : claims) EXPECT_EQ(n, 1) << id;
}

TEST_F(PostgresJobStoreTest, ConcurrentClaimersRequeueEachExpiredLeaseOnce) {
    submitJobs(20, true);
    // Every lease has expired by 2000: each job is requeued (one stall) and claimed again, once.
    std::map<std::string, int> claims = claimAll(2000, 2, 1);
    EXPECT_EQ(claims.size(), 20u);
    for (const auto& [id, n] : claims) EXPECT_EQ(n, 1) << id;
}

TEST_F(PostgresJobStoreTest, ConcurrentRetriesOfOneKeyAddOneJob) {
    std::mutex mutex;
    std::vector<std::string> inserted, told;
    inProcesses([&](JobStore& store, int i) {
        const std::string id = named("j", i);
        Job j = job(id);
        std::optional<StoredResponse> first =
            store.insert(j, "key", StoredResponse{"hash", 202, "{\"id\":\"" + id + "\"}", id});
        std::lock_guard lock(mutex);
        (first ? told : inserted).push_back(first ? first->jobId : id);
    });
    ASSERT_EQ(inserted.size(), 1u);
    EXPECT_EQ(told, std::vector<std::string>(kProcesses - 1, inserted[0]));
    std::unique_ptr<JobStore> store = backend_.open();
    EXPECT_EQ(store->list(std::nullopt, 10, std::nullopt).jobs.size(), 1u);
}

TEST_F(PostgresJobStoreTest, ConcurrentUploadsKeepTheStorageLimit) {
    std::mutex mutex;
    std::map<AssetInsert, int> outcomes;
    inProcesses([&](JobStore& store, int i) {
        Asset a;
        a.id = named("a", i);
        a.format = "obj";
        AssetInsert outcome = store.insertAsset(a, std::string(30, 'x'), 100);
        std::lock_guard lock(mutex);
        ++outcomes[outcome];
    });
    EXPECT_EQ(outcomes[AssetInsert::Inserted], 3);
    EXPECT_EQ(outcomes[AssetInsert::Full], kProcesses - 3);
    EXPECT_EQ(backend_.open()->assetBytesTotal(), 90);
}

TEST_F(PostgresJobStoreTest, MigrationsAreAppliedOnceAndANewerSchemaIsRefused) {
    backend_.open();
    backend_.open();
    pqxx::connection db(backend_.conninfo());
    pqxx::work tx(db);
    pqxx::result versions = tx.exec("SELECT version FROM schema_migrations ORDER BY version");
    ASSERT_EQ(versions.size(), size_t(PostgresJobStore::schemaVersion()));
    EXPECT_EQ(versions[versions.size() - 1][0].as<int>(), PostgresJobStore::schemaVersion());
    tx.exec_params("INSERT INTO schema_migrations (version) VALUES ($1)",
                   PostgresJobStore::schemaVersion() + 1);
    tx.commit();
    try {
        backend_.open();
        FAIL() << "a newer schema was opened";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("newer than this program's"), std::string::npos)
            << e.what();
    }
}

TEST_F(PostgresJobStoreTest, ReconnectsAfterTheServerRestarts) {
    std::unique_ptr<JobStore> store = backend_.open();
    Job a = job("a");
    store->insert(a);
    Job running = *store->claim("w", 1000, 10, 3, 100);
    for (const char* mode : {"fast", "immediate"}) {
        PostgresCluster::shared().restart(mode);
        EXPECT_EQ(store->heartbeat("a", running.attempt, 1001, 10), LeaseStatus::Held) << mode;
    }
    EXPECT_TRUE(store->finish("a", running.attempt, JobState::Succeeded, nullptr, "", 1002));
    EXPECT_EQ(store->get("a")->state, JobState::Succeeded);
}

}  // namespace
}  // namespace caustic::server

#endif  // CAUSTIC_HAS_POSTGRES
