// The job store's lease protocol (server/store/job_store.h) on every store, SQLite and (when it is
// built) PostgreSQL, as one typed suite (support/job_store_backends.h): claims in submission
// order, writes fenced by attempt, expired leases requeued, jobs that stall too often failed,
// cancellation of queued and running jobs, idempotency records, paging, the jobs retention
// removes. Assets: asset_store_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "support/job_store_fixture.h"

namespace caustic::server {
namespace {

template <class Backend>
class JobStoreTest : public testing::StoreTest<Backend> {};
TYPED_TEST_SUITE(JobStoreTest, testing::StoreBackends, testing::BackendNames);

constexpr double kLease = 10;

TYPED_TEST(JobStoreTest, ClaimsInSubmissionOrderWithALease) {
    this->submit("a");
    this->submit("b");
    std::optional<Job> first = this->store_->claim("w1", 1000, kLease, 3, 100);
    ASSERT_TRUE(first);
    EXPECT_EQ(first->id, "a");
    EXPECT_EQ(first->state, JobState::Running);
    EXPECT_EQ(first->attempt, 1);
    EXPECT_EQ(first->leaseOwner, "w1");
    EXPECT_DOUBLE_EQ(first->leaseExpires, 1000 + kLease);
    EXPECT_DOUBLE_EQ(first->startedAt, 1000);
    EXPECT_EQ(first->scene, (Json{{"camera", {{"width", 4}}}}));
    EXPECT_EQ(this->store_->claim("w2", 1000, kLease, 3, 100)->id, "b");
    EXPECT_FALSE(this->store_->claim("w3", 1000, kLease, 3, 100));
}

TYPED_TEST(JobStoreTest, HigherPrioritiesAreClaimedFirstThenSubmissionOrder) {
    this->submit("low", 100, {}, -1);
    this->submit("a", 100);
    this->submit("urgent", 100, {}, 7);
    this->submit("b", 100);
    std::vector<std::string> order;
    while (std::optional<Job> j = this->store_->claim("w", 1000, kLease, 3, 100))
        order.push_back(j->id);
    EXPECT_EQ(order, (std::vector<std::string>{"urgent", "a", "b", "low"}));
    EXPECT_EQ(this->store_->get("urgent")->priority, 7);
}

TYPED_TEST(JobStoreTest, WritesOfAStaleAttemptChangeNothing) {
    this->submit("a");
    Job one = *this->store_->claim("w1", 1000, kLease, 3, 100);
    // The lease expires; another worker takes the job over.
    Job two = *this->store_->claim("w2", 1000 + kLease + 1, kLease, 3, 100);
    EXPECT_EQ(two.id, "a");
    EXPECT_EQ(two.attempt, 2);
    EXPECT_EQ(this->store_->heartbeat("a", one.attempt, 1012, kLease), LeaseStatus::Lost);
    EXPECT_FALSE(this->store_->recordPass("a", one.attempt, 0.5, 1, 2, 0.1, 1, Json{{"pass", 1}}));
    EXPECT_FALSE(
        this->store_->finish("a", one.attempt, JobState::Succeeded, Json::object(), "", 1013));
    EXPECT_EQ(this->store_->heartbeat("a", two.attempt, 1012, kLease), LeaseStatus::Held);
    EXPECT_TRUE(this->store_->recordPass("a", two.attempt, 0.5, 1, 2, 0.1, 1, Json{{"pass", 1}}));
    EXPECT_TRUE(
        this->store_->finish("a", two.attempt, JobState::Succeeded, Json{{"rays", 7}}, "", 1014));
    // Finished once: a second finish of the same attempt changes nothing either.
    EXPECT_FALSE(
        this->store_->finish("a", two.attempt, JobState::Failed, Json::object(), "x", 1015));
    Job done = *this->store_->get("a");
    EXPECT_EQ(done.state, JobState::Succeeded);
    EXPECT_EQ(done.stats, (Json{{"rays", 7}}));
    EXPECT_DOUBLE_EQ(done.progress, 1.0);
    EXPECT_EQ(done.convergence.size(), 1u);
    EXPECT_DOUBLE_EQ(done.finishedAt, 1014);
}

TYPED_TEST(JobStoreTest, HeartbeatsKeepTheLease) {
    this->submit("a");
    Job one = *this->store_->claim("w1", 1000, kLease, 3, 100);
    for (double t = 1005; t < 1100; t += 5)
        ASSERT_EQ(this->store_->heartbeat("a", one.attempt, t, kLease), LeaseStatus::Held);
    EXPECT_FALSE(this->store_->claim("w2", 1100, kLease, 3, 100));
}

TYPED_TEST(JobStoreTest, JobsThatStallTooOftenFailWithTheReason) {
    this->submit("a");
    double t = 1000;
    for (int i = 0; i < 2; ++i) {
        Job j = *this->store_->claim("w", t, kLease, 3, 100);
        EXPECT_EQ(j.attempt, i + 1);
        t += kLease + 1;
    }
    // A finished pass resets the count: stalls must be in a row.
    Job third = *this->store_->claim("w", t, kLease, 3, 100);
    EXPECT_EQ(third.stalledLeases, 2);
    ASSERT_TRUE(
        this->store_->recordPass("a", third.attempt, 0.1, 1, 10, 0.2, 5, Json{{"pass", 1}}));
    t += kLease + 1;
    for (int i = 0; i < 2; ++i) {
        ASSERT_TRUE(this->store_->claim("w", t, kLease, 3, 100));
        t += kLease + 1;
    }
    EXPECT_FALSE(this->store_->claim("w", t, kLease, 3, 100));
    Job failed = *this->store_->get("a");
    EXPECT_EQ(failed.state, JobState::Failed);
    EXPECT_EQ(failed.stalledLeases, 3);
    EXPECT_NE(failed.error.find("3 times in a row"), std::string::npos) << failed.error;
}

TYPED_TEST(JobStoreTest, JobsStartedTooOftenFail) {
    // Killed from outside after every start (no fault, no stall counted): the attempt cap ends it.
    this->submit("a");
    for (const char* owner : {"w0", "w1", "w2", "w3"}) {
        ASSERT_TRUE(this->store_->claim(owner, 1000, kLease, 3, 4)) << owner;
        this->store_->expireLeasesNotOwnedBy("someone else", false);
    }
    EXPECT_FALSE(this->store_->claim("w", 1000, kLease, 3, 4));
    Job failed = *this->store_->get("a");
    EXPECT_EQ(failed.state, JobState::Failed);
    EXPECT_NE(failed.error.find("started 4 times"), std::string::npos) << failed.error;
}

TYPED_TEST(JobStoreTest, StartUpExpiresOtherOwnersLeases) {
    this->submit("a");
    this->submit("b");
    this->store_->claim("old", 1000, kLease, 3, 100);
    this->store_->claim("new", 1000, kLease, 3, 100);
    EXPECT_EQ(this->store_->expireLeasesNotOwnedBy("new", true), 1);
    // "a" is claimable at once, long before its lease would have expired; "b" is still held.
    std::optional<Job> again = this->store_->claim("new", 1001, kLease, 3, 100);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->id, "a");
    EXPECT_EQ(again->attempt, 2);
    EXPECT_EQ(again->stalledLeases, 1);  // the old process died of a fault: it counts
}

TYPED_TEST(JobStoreTest, StartUpAfterAKillRequeuesWithoutCountingAStall) {
    this->submit("a");
    this->submit("b");
    Job a = *this->store_->claim("old", 1000, kLease, 3, 100);
    this->store_->claim("old", 1000, kLease, 3, 100);
    this->store_->cancel("b", 1000);
    // Killed again and again before a pass: never failed for it.
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(this->store_->expireLeasesNotOwnedBy("new" + std::to_string(i), false),
                  i == 0 ? 2 : 1);
        EXPECT_EQ(this->store_->get("a")->state, JobState::Queued);
        a = *this->store_->claim("new" + std::to_string(i), 1001 + i, kLease, 3, 100);
        EXPECT_EQ(a.id, "a");
        EXPECT_EQ(a.attempt, i + 2);
        EXPECT_EQ(a.stalledLeases, 0);
    }
    // The job whose cancellation was asked ends cancelled, not queued.
    EXPECT_EQ(this->store_->get("b")->state, JobState::Cancelled);
}

TYPED_TEST(JobStoreTest, CancelStopsQueuedJobsAtOnceAndAsksRunningOnes) {
    this->submit("queued");
    this->submit("running");
    this->store_->cancel("queued", 1);  // before any claim
    Job running = *this->store_->claim("w", 1000, kLease, 3, 100);
    EXPECT_EQ(running.id, "running");
    EXPECT_EQ(this->store_->get("queued")->state, JobState::Cancelled);

    std::optional<Job> asked = this->store_->cancel("running", 1001);
    EXPECT_EQ(asked->state, JobState::Running);
    EXPECT_TRUE(asked->cancelRequested);
    EXPECT_EQ(this->store_->heartbeat("running", running.attempt, 1002, kLease),
              LeaseStatus::CancelRequested);
    EXPECT_TRUE(this->store_->finish("running", running.attempt, JobState::Cancelled, nullptr,
                                     "cancelled", 1003));
    EXPECT_EQ(this->store_->get("running")->state, JobState::Cancelled);
    EXPECT_FALSE(this->store_->cancel("nobody", 1));

    // A running job whose renderer vanished after a cancel request ends cancelled, not requeued.
    this->submit("orphan");
    Job orphan = *this->store_->claim("w", 2000, kLease, 3, 100);
    this->store_->cancel("orphan", 2001);
    EXPECT_FALSE(this->store_->claim("w", 2000 + kLease + 1, kLease, 3, 100));
    EXPECT_EQ(this->store_->get("orphan")->state, JobState::Cancelled);
    (void)orphan;
}

TYPED_TEST(JobStoreTest, IdempotencyKeysKeepTheFirstResponse) {
    Job a;
    a.id = "a";
    a.scene = a.settings = Json::object();
    EXPECT_FALSE(this->store_->insert(a, "key", StoredResponse{"h1", 202, "{\"id\":\"a\"}", "a"}));
    Job b = a;
    b.id = "b";
    std::optional<StoredResponse> first =
        this->store_->insert(b, "key", StoredResponse{"h2", 202, "{\"id\":\"b\"}", "b"});
    ASSERT_TRUE(first);
    EXPECT_EQ(first->requestHash, "h1");
    EXPECT_EQ(first->jobId, "a");
    EXPECT_EQ(first->body, "{\"id\":\"a\"}");
    EXPECT_FALSE(this->store_->get("b"));  // nothing added
    EXPECT_EQ(this->store_->storedResponse("key")->status, 202);
    // Deleting the job frees its key.
    EXPECT_TRUE(this->store_->remove("a"));
    EXPECT_FALSE(this->store_->storedResponse("key"));
    EXPECT_FALSE(this->store_->remove("a"));
}

TYPED_TEST(JobStoreTest, ListsNewestFirstInPagesAndByState) {
    for (int i = 0; i < 7; ++i) this->submit(std::string(1, 'j').append(std::to_string(i)));
    this->store_->claim("w", 1000, kLease, 3, 100);  // j0 runs
    std::vector<std::string> seen;
    std::optional<int64_t> cursor;
    do {
        JobPage page = this->store_->list(std::nullopt, 3, cursor);
        EXPECT_LE(page.jobs.size(), 3u);
        for (const Job& j : page.jobs) seen.push_back(j.id);
        cursor = page.next;
    } while (cursor);
    EXPECT_EQ(seen, (std::vector<std::string>{"j6", "j5", "j4", "j3", "j2", "j1", "j0"}));
    JobPage running = this->store_->list(JobState::Running, 10, std::nullopt);
    ASSERT_EQ(running.jobs.size(), 1u);
    EXPECT_EQ(running.jobs[0].id, "j0");
    EXPECT_FALSE(running.next);
    auto counts = this->store_->countByState();
    EXPECT_EQ(counts[JobState::Queued], 6);
    EXPECT_EQ(counts[JobState::Running], 1);
    EXPECT_EQ(counts[JobState::Failed], 0);
}

TYPED_TEST(JobStoreTest, SurvivesReopening) {
    this->submit("a");
    Job one = *this->store_->claim("w", 1000, kLease, 3, 100);
    ASSERT_TRUE(this->store_->recordPass("a", one.attempt, 0.25, 1, 4, 0.3, 3, Json{{"pass", 1}}));
    this->reopen();
    Job back = *this->store_->get("a");
    EXPECT_EQ(back.state, JobState::Running);
    EXPECT_EQ(back.passesDone, 1);
    EXPECT_DOUBLE_EQ(back.relativeError, 0.3);
    EXPECT_EQ(back.convergence, (Json::array({Json{{"pass", 1}}})));
}

TYPED_TEST(JobStoreTest, KeepsScenesAndEstimatesBitForBit) {
    // A job renders what was submitted, on whichever node: the scene's numbers come back exactly
    // (a negative zero, the last bit of a double, a huge and a tiny one, an integer kept so).
    Job j;
    j.id = "a";
    j.scene =
        Json{{"numbers", {-0.0, 0.1, 1.0 / 3.0, 1e300, 5e-324, 4, 4.0}}, {"text", "\u00e9 \""}};
    j.settings = Json{{"seed", 18446744073709551615ull}};
    this->store_->insert(j);
    Job back = *this->store_->get("a");
    EXPECT_EQ(back.scene.dump(), j.scene.dump());
    EXPECT_EQ(back.settings.dump(), j.settings.dump());
    // No estimate before two passes: NaN, as the film reports it.
    EXPECT_TRUE(std::isnan(back.relativeError));
    EXPECT_DOUBLE_EQ(back.etaSeconds, -1);
    EXPECT_EQ(back.convergence, Json::array());
    Job running = *this->store_->claim("w", 1000, kLease, 3, 100);
    ASSERT_TRUE(this->store_->recordPass("a", running.attempt, 0.25, 1, 4, std::nan(""), -1,
                                         Json{{"pass", 1}, {"relative_error", nullptr}}));
    EXPECT_TRUE(std::isnan(this->store_->get("a")->relativeError));
    ASSERT_TRUE(this->store_->recordPass("a", running.attempt, 0.5, 2, 4, 1.0 / 3.0, 7,
                                         Json{{"pass", 2}, {"relative_error", 1.0 / 3.0}}));
    back = *this->store_->get("a");
    EXPECT_EQ(back.relativeError, 1.0 / 3.0);
    EXPECT_EQ(back.convergence, (Json::array({Json{{"pass", 1}, {"relative_error", nullptr}},
                                              Json{{"pass", 2}, {"relative_error", 1.0 / 3.0}}})));
}

TYPED_TEST(JobStoreTest, RetentionSelectsFinishedJobsPastTheirAgeOrBeyondTheCount) {
    // Finished at 1000 + i: "s0" first, "c3" last; one queued and one running (for ever, both).
    const std::string ids[] = {"s0", "f1", "s2", "c3"};
    for (const std::string& id : ids) this->submit(id);
    for (int i = 0; i < 4; ++i) {
        Job j = *this->store_->claim("w", 900, 1e9, 3, 100);
        JobState end = ids[i][0] == 's'   ? JobState::Succeeded
                       : ids[i][0] == 'f' ? JobState::Failed
                                          : JobState::Cancelled;
        ASSERT_TRUE(this->store_->finish(j.id, j.attempt, end, Json::object(), "", 1000 + i));
    }
    this->submit("running");
    ASSERT_EQ(this->store_->claim("w", 0, 1e9, 3, 100)->id, "running");
    this->submit("queued");
    auto named = [](const std::vector<ExpiredJob>& jobs) {
        std::vector<std::string> out;
        for (const ExpiredJob& j : jobs) out.push_back(j.id + (j.tooOld ? ":old" : ":count"));
        return out;
    };
    using Ids = std::vector<std::string>;
    // By age alone: finished before 1002, oldest first.
    EXPECT_EQ(named(this->store_->expiredJobs(1002, -1)), (Ids{"s0:old", "f1:old"}));
    // By count alone: the two most recently finished stay.
    EXPECT_EQ(named(this->store_->expiredJobs(0, 2)), (Ids{"s0:count", "f1:count"}));
    // Both: a job past its age is reported so even when the count would remove it too.
    EXPECT_EQ(named(this->store_->expiredJobs(1001, 1)), (Ids{"s0:old", "f1:count", "s2:count"}));
    // Never a queued or running job, however old or many.
    EXPECT_EQ(named(this->store_->expiredJobs(1e12, 0)),
              (Ids{"s0:old", "f1:old", "s2:old", "c3:old"}));
    EXPECT_TRUE(this->store_->expiredJobs(0, -1).empty());
}

}  // namespace
}  // namespace caustic::server
