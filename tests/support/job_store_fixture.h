// The fixture of the store's typed suites (tests/server/job_store_test.cpp, asset_store_test.cpp):
// a test gets an empty store of each backend (support/job_store_backends.h) and helpers to fill it.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "support/job_store_backends.h"

namespace caustic::testing {

using server::Asset;
using server::AssetInsert;
using server::Job;
using server::JobStore;
using server::Json;

template <class Backend>
class StoreTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (std::optional<std::string> why = Backend::unavailable()) GTEST_SKIP() << *why;
        backend_.create();
        store_ = backend_.open();
    }
    void TearDown() override {
        store_.reset();
        backend_.destroy();
    }
    /// Closes the store and opens it again, as a restarted server does.
    void reopen() {
        store_.reset();
        store_ = backend_.open();
    }
    Job submit(const std::string& id, double at = 100, std::vector<std::string> assets = {},
               int priority = 0) {
        Job j;
        j.priority = priority;
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

    Backend backend_;
    std::unique_ptr<JobStore> store_;
};

#ifdef CAUSTIC_HAS_POSTGRES
using StoreBackends = ::testing::Types<SqliteBackend, PostgresBackend>;
#else
using StoreBackends = ::testing::Types<SqliteBackend>;
#endif

struct BackendNames {
    template <class Backend>
    static std::string GetName(int) {
        return Backend::kName;
    }
};

}  // namespace caustic::testing
