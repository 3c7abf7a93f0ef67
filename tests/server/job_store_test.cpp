// The job store's lease protocol (server/store/job_store.h) on SQLite: claims in submission order,
// writes fenced by attempt, expired leases requeued, jobs that stall too often failed, cancellation
// of queued and running jobs, idempotency records, paging; uploaded assets, stored once by id and
// held by the jobs that use them.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "store/sqlite_job_store.h"

namespace caustic::server {
namespace {

namespace fs = std::filesystem;

class JobStoreTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ =
            fs::temp_directory_path() / ("caustic-store-" + std::to_string(std::random_device{}()));
        fs::create_directories(dir_);
        store_ = std::make_unique<SqliteJobStore>(dir_ / "jobs.sqlite3");
    }
    void TearDown() override {
        store_.reset();
        fs::remove_all(dir_);
    }
    Job submit(const std::string& id, double at = 100, std::vector<std::string> assets = {}) {
        Job j;
        j.id = id;
        j.scene = Json{{"camera", {{"width", 4}}}};
        j.settings = Json{{"spp", 4}};
        j.createdAt = at;
        j.assets = std::move(assets);
        store_->insert(j);
        return j;
    }
    // Stores an asset of `bytes` under `id` (any text: the store does not hash), used at `at`.
    AssetInsert upload(const std::string& id, const std::string& bytes, double at = 100,
                       int64_t maxTotal = int64_t(1) << 30, const std::string& name = "") {
        Asset a;
        a.id = id;
        a.format = "obj";
        a.name = name;
        a.triangles = 2;
        a.vertices = 4;
        a.boundsMin = {-1, -2, -3};
        a.boundsMax = {1, 2, 3};
        a.createdAt = at;
        a.lastUsedAt = at;
        return store_->insertAsset(a, bytes, maxTotal);
    }

    fs::path dir_;
    std::unique_ptr<JobStore> store_;
};

constexpr double kLease = 10;

TEST_F(JobStoreTest, ClaimsInSubmissionOrderWithALease) {
    submit("a");
    submit("b");
    std::optional<Job> first = store_->claim("w1", 1000, kLease, 3, 100);
    ASSERT_TRUE(first);
    EXPECT_EQ(first->id, "a");
    EXPECT_EQ(first->state, JobState::Running);
    EXPECT_EQ(first->attempt, 1);
    EXPECT_EQ(first->leaseOwner, "w1");
    EXPECT_DOUBLE_EQ(first->leaseExpires, 1000 + kLease);
    EXPECT_DOUBLE_EQ(first->startedAt, 1000);
    EXPECT_EQ(first->scene, (Json{{"camera", {{"width", 4}}}}));
    EXPECT_EQ(store_->claim("w2", 1000, kLease, 3, 100)->id, "b");
    EXPECT_FALSE(store_->claim("w3", 1000, kLease, 3, 100));
}

TEST_F(JobStoreTest, WritesOfAStaleAttemptChangeNothing) {
    submit("a");
    Job one = *store_->claim("w1", 1000, kLease, 3, 100);
    // The lease expires; another worker takes the job over.
    Job two = *store_->claim("w2", 1000 + kLease + 1, kLease, 3, 100);
    EXPECT_EQ(two.id, "a");
    EXPECT_EQ(two.attempt, 2);
    EXPECT_EQ(store_->heartbeat("a", one.attempt, 1012, kLease), LeaseStatus::Lost);
    EXPECT_FALSE(store_->recordPass("a", one.attempt, 0.5, 1, 2, 0.1, 1, Json{{"pass", 1}}));
    EXPECT_FALSE(store_->finish("a", one.attempt, JobState::Succeeded, Json::object(), "", 1013));
    EXPECT_EQ(store_->heartbeat("a", two.attempt, 1012, kLease), LeaseStatus::Held);
    EXPECT_TRUE(store_->recordPass("a", two.attempt, 0.5, 1, 2, 0.1, 1, Json{{"pass", 1}}));
    EXPECT_TRUE(store_->finish("a", two.attempt, JobState::Succeeded, Json{{"rays", 7}}, "", 1014));
    // Finished once: a second finish of the same attempt changes nothing either.
    EXPECT_FALSE(store_->finish("a", two.attempt, JobState::Failed, Json::object(), "x", 1015));
    Job done = *store_->get("a");
    EXPECT_EQ(done.state, JobState::Succeeded);
    EXPECT_EQ(done.stats, (Json{{"rays", 7}}));
    EXPECT_DOUBLE_EQ(done.progress, 1.0);
    EXPECT_EQ(done.convergence.size(), 1u);
    EXPECT_DOUBLE_EQ(done.finishedAt, 1014);
}

TEST_F(JobStoreTest, HeartbeatsKeepTheLease) {
    submit("a");
    Job one = *store_->claim("w1", 1000, kLease, 3, 100);
    for (double t = 1005; t < 1100; t += 5)
        ASSERT_EQ(store_->heartbeat("a", one.attempt, t, kLease), LeaseStatus::Held);
    EXPECT_FALSE(store_->claim("w2", 1100, kLease, 3, 100));
}

TEST_F(JobStoreTest, JobsThatStallTooOftenFailWithTheReason) {
    submit("a");
    double t = 1000;
    for (int i = 0; i < 2; ++i) {
        Job j = *store_->claim("w", t, kLease, 3, 100);
        EXPECT_EQ(j.attempt, i + 1);
        t += kLease + 1;
    }
    // A finished pass resets the count: stalls must be in a row.
    Job third = *store_->claim("w", t, kLease, 3, 100);
    EXPECT_EQ(third.stalledLeases, 2);
    ASSERT_TRUE(store_->recordPass("a", third.attempt, 0.1, 1, 10, 0.2, 5, Json{{"pass", 1}}));
    t += kLease + 1;
    for (int i = 0; i < 2; ++i) {
        ASSERT_TRUE(store_->claim("w", t, kLease, 3, 100));
        t += kLease + 1;
    }
    EXPECT_FALSE(store_->claim("w", t, kLease, 3, 100));
    Job failed = *store_->get("a");
    EXPECT_EQ(failed.state, JobState::Failed);
    EXPECT_EQ(failed.stalledLeases, 3);
    EXPECT_NE(failed.error.find("3 times in a row"), std::string::npos) << failed.error;
}

TEST_F(JobStoreTest, JobsStartedTooOftenFail) {
    // Killed from outside after every start (no fault, no stall counted): the attempt cap ends it.
    submit("a");
    for (const char* owner : {"w0", "w1", "w2", "w3"}) {
        ASSERT_TRUE(store_->claim(owner, 1000, kLease, 3, 4)) << owner;
        store_->expireLeasesNotOwnedBy("someone else", false);
    }
    EXPECT_FALSE(store_->claim("w", 1000, kLease, 3, 4));
    Job failed = *store_->get("a");
    EXPECT_EQ(failed.state, JobState::Failed);
    EXPECT_NE(failed.error.find("started 4 times"), std::string::npos) << failed.error;
}

TEST_F(JobStoreTest, StartUpExpiresOtherOwnersLeases) {
    submit("a");
    submit("b");
    store_->claim("old", 1000, kLease, 3, 100);
    store_->claim("new", 1000, kLease, 3, 100);
    EXPECT_EQ(store_->expireLeasesNotOwnedBy("new", true), 1);
    // "a" is claimable at once, long before its lease would have expired; "b" is still held.
    std::optional<Job> again = store_->claim("new", 1001, kLease, 3, 100);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->id, "a");
    EXPECT_EQ(again->attempt, 2);
    EXPECT_EQ(again->stalledLeases, 1);  // the old process died of a fault: it counts
}

TEST_F(JobStoreTest, StartUpAfterAKillRequeuesWithoutCountingAStall) {
    submit("a");
    submit("b");
    Job a = *store_->claim("old", 1000, kLease, 3, 100);
    store_->claim("old", 1000, kLease, 3, 100);
    store_->cancel("b", 1000);
    // Killed again and again before a pass: never failed for it.
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(store_->expireLeasesNotOwnedBy("new" + std::to_string(i), false), i == 0 ? 2 : 1);
        EXPECT_EQ(store_->get("a")->state, JobState::Queued);
        a = *store_->claim("new" + std::to_string(i), 1001 + i, kLease, 3, 100);
        EXPECT_EQ(a.id, "a");
        EXPECT_EQ(a.attempt, i + 2);
        EXPECT_EQ(a.stalledLeases, 0);
    }
    // The job whose cancellation was asked ends cancelled, not queued.
    EXPECT_EQ(store_->get("b")->state, JobState::Cancelled);
}

TEST_F(JobStoreTest, CancelStopsQueuedJobsAtOnceAndAsksRunningOnes) {
    submit("queued");
    submit("running");
    store_->cancel("queued", 1);  // before any claim
    Job running = *store_->claim("w", 1000, kLease, 3, 100);
    EXPECT_EQ(running.id, "running");
    EXPECT_EQ(store_->get("queued")->state, JobState::Cancelled);

    std::optional<Job> asked = store_->cancel("running", 1001);
    EXPECT_EQ(asked->state, JobState::Running);
    EXPECT_TRUE(asked->cancelRequested);
    EXPECT_EQ(store_->heartbeat("running", running.attempt, 1002, kLease),
              LeaseStatus::CancelRequested);
    EXPECT_TRUE(store_->finish("running", running.attempt, JobState::Cancelled, nullptr,
                               "cancelled", 1003));
    EXPECT_EQ(store_->get("running")->state, JobState::Cancelled);
    EXPECT_FALSE(store_->cancel("nobody", 1));

    // A running job whose renderer vanished after a cancel request ends cancelled, not requeued.
    submit("orphan");
    Job orphan = *store_->claim("w", 2000, kLease, 3, 100);
    store_->cancel("orphan", 2001);
    EXPECT_FALSE(store_->claim("w", 2000 + kLease + 1, kLease, 3, 100));
    EXPECT_EQ(store_->get("orphan")->state, JobState::Cancelled);
    (void)orphan;
}

TEST_F(JobStoreTest, IdempotencyKeysKeepTheFirstResponse) {
    Job a;
    a.id = "a";
    a.scene = a.settings = Json::object();
    EXPECT_FALSE(store_->insert(a, "key", StoredResponse{"h1", 202, "{\"id\":\"a\"}", "a"}));
    Job b = a;
    b.id = "b";
    std::optional<StoredResponse> first =
        store_->insert(b, "key", StoredResponse{"h2", 202, "{\"id\":\"b\"}", "b"});
    ASSERT_TRUE(first);
    EXPECT_EQ(first->requestHash, "h1");
    EXPECT_EQ(first->jobId, "a");
    EXPECT_EQ(first->body, "{\"id\":\"a\"}");
    EXPECT_FALSE(store_->get("b"));  // nothing added
    EXPECT_EQ(store_->storedResponse("key")->status, 202);
    // Deleting the job frees its key.
    EXPECT_TRUE(store_->remove("a"));
    EXPECT_FALSE(store_->storedResponse("key"));
    EXPECT_FALSE(store_->remove("a"));
}

TEST_F(JobStoreTest, ListsNewestFirstInPagesAndByState) {
    for (int i = 0; i < 7; ++i) submit(std::string(1, 'j').append(std::to_string(i)));
    store_->claim("w", 1000, kLease, 3, 100);  // j0 runs
    std::vector<std::string> seen;
    std::optional<int64_t> cursor;
    do {
        JobPage page = store_->list(std::nullopt, 3, cursor);
        EXPECT_LE(page.jobs.size(), 3u);
        for (const Job& j : page.jobs) seen.push_back(j.id);
        cursor = page.next;
    } while (cursor);
    EXPECT_EQ(seen, (std::vector<std::string>{"j6", "j5", "j4", "j3", "j2", "j1", "j0"}));
    JobPage running = store_->list(JobState::Running, 10, std::nullopt);
    ASSERT_EQ(running.jobs.size(), 1u);
    EXPECT_EQ(running.jobs[0].id, "j0");
    EXPECT_FALSE(running.next);
    auto counts = store_->countByState();
    EXPECT_EQ(counts[JobState::Queued], 6);
    EXPECT_EQ(counts[JobState::Running], 1);
    EXPECT_EQ(counts[JobState::Failed], 0);
}

TEST_F(JobStoreTest, SurvivesReopening) {
    submit("a");
    Job one = *store_->claim("w", 1000, kLease, 3, 100);
    ASSERT_TRUE(store_->recordPass("a", one.attempt, 0.25, 1, 4, 0.3, 3, Json{{"pass", 1}}));
    store_ = std::make_unique<SqliteJobStore>(dir_ / "jobs.sqlite3");
    Job back = *store_->get("a");
    EXPECT_EQ(back.state, JobState::Running);
    EXPECT_EQ(back.passesDone, 1);
    EXPECT_DOUBLE_EQ(back.relativeError, 0.3);
    EXPECT_EQ(back.convergence, (Json::array({Json{{"pass", 1}}})));
}

TEST_F(JobStoreTest, StoresAnAssetOnceByIdWithItsBytes) {
    // Bytes that are not text: a NUL, invalid UTF-8.
    const std::string bytes("v 0 0 0\0\xff\xfe", 10);
    EXPECT_EQ(upload("x", bytes, 100, int64_t(1) << 30, "first.obj"), AssetInsert::Inserted);
    std::optional<Asset> a = store_->getAsset("x");
    ASSERT_TRUE(a);
    EXPECT_GT(a->seq, 0);
    EXPECT_EQ(a->format, "obj");
    EXPECT_EQ(a->name, "first.obj");
    EXPECT_EQ(a->bytes, 10);
    EXPECT_EQ(a->triangles, 2);
    EXPECT_EQ(a->vertices, 4);
    EXPECT_EQ(a->boundsMin, (std::array<double, 3>{-1, -2, -3}));
    EXPECT_EQ(a->boundsMax, (std::array<double, 3>{1, 2, 3}));
    EXPECT_DOUBLE_EQ(a->createdAt, 100);
    EXPECT_EQ(*store_->assetBytes("x"), bytes);
    EXPECT_EQ(store_->assetBytesTotal(), 10);

    // The same id again: the stored asset, as it was, only its last use moved.
    Asset again;
    again.id = "x";
    again.name = "second.obj";
    again.lastUsedAt = 200;
    EXPECT_EQ(store_->insertAsset(again, bytes, int64_t(1) << 30), AssetInsert::Existing);
    EXPECT_EQ(again.name, "first.obj");
    EXPECT_EQ(again.seq, a->seq);
    EXPECT_DOUBLE_EQ(again.lastUsedAt, 200);
    EXPECT_EQ(store_->assetBytesTotal(), 10);
    EXPECT_FALSE(store_->getAsset("y"));
    EXPECT_EQ(store_->assetBytes("y"), nullptr);
}

TEST_F(JobStoreTest, RefusesAnAssetOverTheStorageLimit) {
    EXPECT_EQ(upload("a", std::string(60, 'a'), 100, 100), AssetInsert::Inserted);
    EXPECT_EQ(upload("b", std::string(41, 'b'), 100, 100), AssetInsert::Full);
    EXPECT_FALSE(store_->getAsset("b"));
    EXPECT_EQ(upload("c", std::string(40, 'c'), 100, 100), AssetInsert::Inserted);
    EXPECT_EQ(store_->assetBytesTotal(), 100);
    // A stored asset is found whatever the storage holds.
    EXPECT_EQ(upload("a", std::string(60, 'a'), 100, 100), AssetInsert::Existing);
}

TEST_F(JobStoreTest, QueuedAndRunningJobsHoldTheirAssets) {
    upload("m", "mesh");
    upload("n", "other mesh");
    submit("job", 150, {"m", "n"});
    EXPECT_EQ(store_->get("job")->assets, (std::vector<std::string>{"m", "n"}));
    EXPECT_DOUBLE_EQ(store_->getAsset("m")->lastUsedAt, 150);
    EXPECT_EQ(store_->removeAsset("m"), AssetRemoval::InUse);
    Job running = *store_->claim("w", 1000, kLease, 3, 100);
    EXPECT_EQ(store_->removeAsset("m"), AssetRemoval::InUse);
    ASSERT_TRUE(store_->finish("job", running.attempt, JobState::Succeeded, nullptr, "", 1001));
    // A finished job no longer holds them.
    EXPECT_EQ(store_->removeAsset("m"), AssetRemoval::Removed);
    EXPECT_EQ(store_->removeAsset("m"), AssetRemoval::Unknown);
    EXPECT_FALSE(store_->getAsset("m"));
    EXPECT_EQ(store_->get("job")->assets, (std::vector<std::string>{"n"}));
    EXPECT_TRUE(store_->remove("job"));
    EXPECT_EQ(store_->removeAsset("n"), AssetRemoval::Removed);
}

TEST_F(JobStoreTest, AJobNamingAMissingAssetIsNotInserted) {
    upload("m", "mesh");
    Job j;
    j.id = "job";
    j.scene = Json::object();
    j.settings = Json::object();
    j.assets = {"m", "gone"};
    EXPECT_THROW(store_->insert(j), AssetMissing);
    EXPECT_FALSE(store_->get("job"));
    EXPECT_EQ(store_->removeAsset("m"), AssetRemoval::Removed);
}

TEST_F(JobStoreTest, RemovesAssetsUnusedSinceACutOff) {
    upload("old", "1", 100);
    upload("recent", "22", 500);
    upload("held", "333", 100);
    submit("job", 100, {"held"});
    EXPECT_EQ(store_->removeUnusedAssets(300), (std::vector<std::string>{"old"}));
    EXPECT_TRUE(store_->getAsset("recent"));
    EXPECT_TRUE(store_->getAsset("held"));
    // Deleting the job lets go of its asset.
    EXPECT_TRUE(store_->remove("job"));
    EXPECT_EQ(store_->removeUnusedAssets(300), (std::vector<std::string>{"held"}));
    EXPECT_EQ(store_->assetBytesTotal(), 2);
}

TEST_F(JobStoreTest, ListsAssetsNewestFirstInPagesAndSurvivesReopening) {
    const std::vector<std::string> ids{"a0", "a1", "a2", "a3", "a4"};
    for (size_t i = 0; i < ids.size(); ++i) upload(ids[i], std::string(i + 1, 'x'));
    AssetPage first = store_->listAssets(2, std::nullopt);
    ASSERT_EQ(first.assets.size(), 2u);
    EXPECT_EQ(first.assets[0].id, "a4");
    EXPECT_EQ(first.assets[1].id, "a3");
    ASSERT_TRUE(first.next);
    AssetPage rest = store_->listAssets(10, first.next);
    ASSERT_EQ(rest.assets.size(), 3u);
    EXPECT_EQ(rest.assets[2].id, "a0");
    EXPECT_FALSE(rest.next);
    store_ = std::make_unique<SqliteJobStore>(dir_ / "jobs.sqlite3");
    EXPECT_EQ(*store_->assetBytes("a2"), "xxx");
    EXPECT_EQ(store_->listAssets(10, std::nullopt).assets.size(), 5u);
}

}  // namespace
}  // namespace caustic::server
