// The store's assets (server/store/job_store.h, "Assets") on every store, SQLite and (when it is
// built) PostgreSQL, as one typed suite (support/job_store_fixture.h): stored once by id with
// their bytes, the storage limit, the jobs that hold them, retention of unused ones, paging.
#include <gtest/gtest.h>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "support/job_store_fixture.h"

namespace caustic::server {
namespace {

template <class Backend>
class AssetStoreTest : public testing::StoreTest<Backend> {};
TYPED_TEST_SUITE(AssetStoreTest, testing::StoreBackends, testing::BackendNames);

constexpr double kLease = 10;

TYPED_TEST(AssetStoreTest, StoresAnAssetOnceByIdWithItsBytes) {
    // Bytes that are not text: a NUL, invalid UTF-8.
    const std::string bytes("v 0 0 0\0\xff\xfe", 10);
    EXPECT_EQ(this->upload("x", bytes, 100, int64_t(1) << 30, "first.obj"), AssetInsert::Inserted);
    std::optional<Asset> a = this->store_->getAsset("x");
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
    EXPECT_EQ(*this->store_->assetBytes("x"), bytes);
    EXPECT_EQ(this->store_->assetBytesTotal(), 10);

    // The same id again: the stored asset, as it was, only its last use moved.
    Asset again;
    again.id = "x";
    again.name = "second.obj";
    again.lastUsedAt = 200;
    EXPECT_EQ(this->store_->insertAsset(again, bytes, int64_t(1) << 30), AssetInsert::Existing);
    EXPECT_EQ(again.name, "first.obj");
    EXPECT_EQ(again.seq, a->seq);
    EXPECT_DOUBLE_EQ(again.lastUsedAt, 200);
    EXPECT_EQ(this->store_->assetBytesTotal(), 10);
    EXPECT_FALSE(this->store_->getAsset("y"));
    EXPECT_EQ(this->store_->assetBytes("y"), nullptr);
}

TYPED_TEST(AssetStoreTest, RefusesAnAssetOverTheStorageLimit) {
    EXPECT_EQ(this->upload("a", std::string(60, 'a'), 100, 100), AssetInsert::Inserted);
    EXPECT_EQ(this->upload("b", std::string(41, 'b'), 100, 100), AssetInsert::Full);
    EXPECT_FALSE(this->store_->getAsset("b"));
    EXPECT_EQ(this->upload("c", std::string(40, 'c'), 100, 100), AssetInsert::Inserted);
    EXPECT_EQ(this->store_->assetBytesTotal(), 100);
    // A stored asset is found whatever the storage holds.
    EXPECT_EQ(this->upload("a", std::string(60, 'a'), 100, 100), AssetInsert::Existing);
}

TYPED_TEST(AssetStoreTest, QueuedAndRunningJobsHoldTheirAssets) {
    this->upload("m", "mesh");
    this->upload("n", "other mesh");
    this->submit("job", 150, {"m", "n"});
    EXPECT_EQ(this->store_->get("job")->assets, (std::vector<std::string>{"m", "n"}));
    EXPECT_DOUBLE_EQ(this->store_->getAsset("m")->lastUsedAt, 150);
    EXPECT_EQ(this->store_->removeAsset("m"), AssetRemoval::InUse);
    Job running = *this->store_->claim("w", 1000, kLease, 3, 100);
    EXPECT_EQ(this->store_->removeAsset("m"), AssetRemoval::InUse);
    ASSERT_TRUE(
        this->store_->finish("job", running.attempt, JobState::Succeeded, nullptr, "", 1001));
    // A finished job no longer holds them.
    EXPECT_EQ(this->store_->removeAsset("m"), AssetRemoval::Removed);
    EXPECT_EQ(this->store_->removeAsset("m"), AssetRemoval::Unknown);
    EXPECT_FALSE(this->store_->getAsset("m"));
    EXPECT_EQ(this->store_->get("job")->assets, (std::vector<std::string>{"n"}));
    EXPECT_TRUE(this->store_->remove("job"));
    EXPECT_EQ(this->store_->removeAsset("n"), AssetRemoval::Removed);
}

TYPED_TEST(AssetStoreTest, AJobNamingAMissingAssetIsNotInserted) {
    this->upload("m", "mesh");
    Job j;
    j.id = "job";
    j.scene = Json::object();
    j.settings = Json::object();
    j.assets = {"m", "gone"};
    EXPECT_THROW(this->store_->insert(j), AssetMissing);
    EXPECT_FALSE(this->store_->get("job"));
    EXPECT_EQ(this->store_->removeAsset("m"), AssetRemoval::Removed);
}

TYPED_TEST(AssetStoreTest, RemovesAssetsUnusedSinceACutOff) {
    this->upload("old", "1", 100);
    this->upload("recent", "22", 500);
    this->upload("held", "333", 100);
    this->submit("job", 100, {"held"});
    EXPECT_EQ(this->store_->removeUnusedAssets(300), (std::vector<std::string>{"old"}));
    EXPECT_TRUE(this->store_->getAsset("recent"));
    EXPECT_TRUE(this->store_->getAsset("held"));
    // Deleting the job lets go of its asset.
    EXPECT_TRUE(this->store_->remove("job"));
    EXPECT_EQ(this->store_->removeUnusedAssets(300), (std::vector<std::string>{"held"}));
    EXPECT_EQ(this->store_->assetBytesTotal(), 2);
}

TYPED_TEST(AssetStoreTest, ReclaimingSpaceKeepsWhatIsStored) {
    this->upload("gone", std::string(100000, 'g'));
    this->upload("kept", std::string(1000, 'k'));
    this->submit("job", 100, {"kept"});
    ASSERT_EQ(this->store_->removeAsset("gone"), AssetRemoval::Removed);
    this->store_->reclaimSpace();
    EXPECT_EQ(*this->store_->assetBytes("kept"), std::string(1000, 'k'));
    EXPECT_EQ(this->store_->get("job")->assets, (std::vector<std::string>{"kept"}));
    EXPECT_EQ(this->store_->assetBytesTotal(), 1000);
}

TYPED_TEST(AssetStoreTest, ListsAssetsNewestFirstInPagesAndSurvivesReopening) {
    const std::vector<std::string> ids{"a0", "a1", "a2", "a3", "a4"};
    for (size_t i = 0; i < ids.size(); ++i) this->upload(ids[i], std::string(i + 1, 'x'));
    AssetPage first = this->store_->listAssets(2, std::nullopt);
    ASSERT_EQ(first.assets.size(), 2u);
    EXPECT_EQ(first.assets[0].id, "a4");
    EXPECT_EQ(first.assets[1].id, "a3");
    ASSERT_TRUE(first.next);
    AssetPage rest = this->store_->listAssets(10, first.next);
    ASSERT_EQ(rest.assets.size(), 3u);
    EXPECT_EQ(rest.assets[2].id, "a0");
    EXPECT_FALSE(rest.next);
    this->reopen();
    EXPECT_EQ(*this->store_->assetBytes("a2"), "xxx");
    EXPECT_EQ(this->store_->listAssets(10, std::nullopt).assets.size(), 5u);
}

}  // namespace
}  // namespace caustic::server
