// The scale-out protocol of the PostgreSQL store (server/store/task.h) against a real server:
// tasks claimed by priority then submission order, leases fenced by attempt, results handed in
// without the job's lock and consolidated exactly whatever the order, one consolidation at a
// time, a target error merged in pass order, the blocklist, stalled leases, cancelling and
// re-queueing. Time passes by the database's clock: a test that needs a lease run out or a worker
// gone ages their rows in SQL.
#ifdef CAUSTIC_HAS_POSTGRES

#include <gtest/gtest.h>

#include <pqxx/pqxx>

#include <algorithm>
#include <chrono>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "core/rng.h"
#include "film/image_io.h"
#include "render/settings.h"
#include "render/stopping.h"
#include "store/pass_images.h"
#include "support/job_store_backends.h"

namespace caustic::server {
namespace {

using testing::PostgresBackend;

constexpr int kWidth = 4, kHeight = 3;
constexpr double kLease = 10;

// A pass's image: a function of its index only, as a render's passes are.
std::vector<Color> passImage(int pass) {
    Rng rng(uint64_t(pass) + 1);
    std::vector<Color> image(kWidth * kHeight);
    for (Color& c : image) c = Color(0.5f + rng.uniform(), 0.5f + rng.uniform(), 1.0f);
    return image;
}

class TaskStoreTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (std::optional<std::string> why = PostgresBackend::unavailable()) GTEST_SKIP() << *why;
        backend_.create();
        store_ = std::make_unique<PostgresJobStore>(backend_.conninfo());
    }
    void TearDown() override {
        store_.reset();
        backend_.destroy();
    }

    // Inserts a job of `passes` passes in tasks of `taskPasses`.
    Job submit(const std::string& id, int passes, int taskPasses, int priority = 0,
               double targetError = 0) {
        Job job;
        job.id = id;
        job.scene = Json::object();
        RenderSettings settings;
        settings.spp = passes;
        settings.sppPerPass = 1;
        settings.targetError = targetError;
        job.settings = settings.toJson();
        job.passesTotal = passes;
        job.taskPasses = taskPasses;
        job.priority = priority;
        job.createdAt = double(++clock_);
        store_->insert(job, {}, {});
        return job;
    }

    std::optional<ClaimedTask> claim(const std::string& worker) {
        return store_->claimTask(worker, policy_);
    }

    // Worker `id`'s row, renewed now.
    void seen(const std::string& id) {
        WorkerInfo w;
        w.id = id;
        w.startedAt = 1000;
        store_->workerSeen(w);
    }

    // Runs SQL on a connection of the test's own.
    void sql(const std::string& statement) {
        pqxx::connection c(backend_.conninfo());
        pqxx::work tx(c);
        tx.exec(statement);
        tx.commit();
    }
    // Every running task's lease runs out (as if kLease passed).
    void expireLeases() { sql("UPDATE tasks SET lease_expires = 0 WHERE state = 'running'"); }

    // Hands in `task`'s result and consolidates the job; what the consolidation did.
    Consolidation handIn(const Task& task, bool passImages = false) {
        EXPECT_EQ(store_->completeTask(task, resultOf(task, passImages)), TaskCommit::Accepted);
        return store_->consolidate(task.jobId);
    }

    // What a worker hands in for `task`: the film of its passes, or each pass's image.
    static TaskResult resultOf(const Task& task, bool passImages) {
        TaskResult r;
        r.width = kWidth;
        r.height = kHeight;
        Film film(kWidth, kHeight);
        for (int p = task.firstPass; p < task.lastPass; ++p) {
            film.addPass(p, passImage(p));
            if (passImages) appendPassImage(r.passImages, kWidth, kHeight, p, 0, passImage(p));
        }
        if (!passImages) r.film = film.toBytes();
        r.passesDone = task.lastPass - task.firstPass;
        return r;
    }

    // The EXR of one process adding passes [0, last).
    static std::string sequentialExr(int last) {
        Film film(kWidth, kHeight);
        for (int p = 0; p < last; ++p) film.addPass(p, passImage(p));
        return encodeImage(RgbImage{kWidth, kHeight, film.meanRgb()}, "exr");
    }

    PostgresBackend backend_;
    std::unique_ptr<PostgresJobStore> store_;
    FarmPolicy policy_{kLease, 3, 2, 3};
    int clock_ = 0;
};

TEST_F(TaskStoreTest, TasksGoByPriorityThenSubmissionThenPass) {
    submit("low", 4, 2);
    submit("high", 4, 2, /*priority=*/5);
    submit("low2", 2, 2);
    std::vector<std::string> order;
    for (int i = 0; i < 5; ++i) {
        std::optional<ClaimedTask> c = claim("w");
        ASSERT_TRUE(c);
        order.push_back(c->task.jobId + ":" + std::to_string(c->task.firstPass) + "-" +
                        std::to_string(c->task.lastPass));
        EXPECT_EQ(c->task.attempt, 1);
        EXPECT_EQ(c->job.state, JobState::Running);
    }
    EXPECT_EQ(order,
              (std::vector<std::string>{"high:0-2", "high:2-4", "low:0-2", "low:2-4", "low2:0-2"}));
    EXPECT_FALSE(claim("w"));
}

TEST_F(TaskStoreTest, ResultsHandedInOutOfOrderMergeToOneProcessesImage) {
    submit("j", 10, 3);  // tasks 0-3, 3-6, 6-9, 9-10
    std::vector<Task> tasks;
    while (std::optional<ClaimedTask> c = claim("w")) tasks.push_back(c->task);
    ASSERT_EQ(tasks.size(), 4u);
    EXPECT_EQ(tasks.back().lastPass, 10);
    // Handed in; a batch merges what waits, in any order.
    for (int i : {2, 0})
        EXPECT_EQ(store_->completeTask(tasks[i], resultOf(tasks[i], false)), TaskCommit::Accepted);
    EXPECT_EQ(store_->get("j")->passesDone, 0) << "a hand-in merges nothing";
    EXPECT_EQ(store_->consolidate("j"), Consolidation::Merged);
    EXPECT_EQ(store_->consolidate("j"), Consolidation::Nothing);
    EXPECT_EQ(handIn(tasks[3]), Consolidation::Merged);
    std::optional<Job> mid = store_->get("j");
    EXPECT_EQ(mid->passesDone, 7);
    EXPECT_TRUE(store_->getFile("j", "preview.png"));
    EXPECT_EQ(handIn(tasks[1]), Consolidation::Finished);
    std::optional<Job> done = store_->get("j");
    EXPECT_EQ(done->state, JobState::Succeeded);
    EXPECT_EQ(done->passesDone, 10);
    EXPECT_EQ(done->stats["tasks"], 4);
    EXPECT_EQ(store_->getFile("j", "image.exr"), sequentialExr(10));
    EXPECT_FALSE(store_->getFile("j", "film.bin"));  // the merged film goes with the job's end
}

TEST_F(TaskStoreTest, ABatchMergesAtMostItsLimit) {
    submit("j", 5, 1);
    std::vector<Task> tasks;
    while (std::optional<ClaimedTask> c = claim("w")) tasks.push_back(c->task);
    for (const Task& t : tasks)
        ASSERT_EQ(store_->completeTask(t, resultOf(t, false)), TaskCommit::Accepted);
    const ConsolidationLimits two{.results = 2, .seconds = 60};
    EXPECT_EQ(store_->consolidate("j", two), Consolidation::More);
    EXPECT_EQ(store_->get("j")->passesDone, 2);
    EXPECT_EQ(store_->consolidate("j", two), Consolidation::More);
    EXPECT_EQ(store_->consolidate("j", two), Consolidation::Finished);
    EXPECT_EQ(store_->getFile("j", "image.exr"), sequentialExr(5));
}

TEST_F(TaskStoreTest, AHandInWaitsForNoLockOnItsJob) {
    submit("j", 4, 2);
    std::optional<ClaimedTask> c = claim("w");
    ASSERT_TRUE(c);
    // Another transaction holds the job's row and its consolidation lock (as a long batch does).
    pqxx::connection other(backend_.conninfo());
    pqxx::work tx(other);
    tx.exec("SELECT 1 FROM jobs WHERE id = 'j' FOR UPDATE");
    tx.exec("SELECT pg_advisory_xact_lock(1668247155, hashtext('j'))");  // "cons"
    std::future<TaskCommit> handedIn = std::async(std::launch::async, [&] {
        return store_->completeTask(c->task, resultOf(c->task, false));
    });
    ASSERT_EQ(handedIn.wait_for(std::chrono::seconds(5)), std::future_status::ready)
        << "the hand-in waited for the job's lock";
    EXPECT_EQ(handedIn.get(), TaskCommit::Accepted);
    EXPECT_EQ(store_->consolidate("j"), Consolidation::Busy) << "one consolidation at a time";
    tx.abort();
    EXPECT_EQ(store_->consolidate("j"), Consolidation::Merged);
}

TEST_F(TaskStoreTest, AResultOfAnOldAttemptIsNeverCountedAgain) {
    submit("j", 2, 2);
    std::optional<ClaimedTask> first = claim("w1");
    ASSERT_TRUE(first);
    // The lease runs out: the next claim re-queues the task and takes it as attempt 2.
    expireLeases();
    std::optional<ClaimedTask> second = claim("w2");
    ASSERT_TRUE(second);
    EXPECT_EQ(second->task.attempt, 2);
    EXPECT_EQ(store_->heartbeatTask(first->task, kLease), LeaseStatus::Lost);
    EXPECT_EQ(store_->completeTask(first->task, resultOf(first->task, false)), TaskCommit::Fenced);
    EXPECT_EQ(store_->heartbeatTask(second->task, kLease), LeaseStatus::Held);
    EXPECT_EQ(store_->completeTask(second->task, resultOf(second->task, false)),
              TaskCommit::Accepted);
    EXPECT_EQ(store_->completeTask(second->task, resultOf(second->task, false)),
              TaskCommit::Fenced);
    EXPECT_EQ(store_->consolidate("j"), Consolidation::Finished);
    EXPECT_EQ(store_->get("j")->passesDone, 2);
    EXPECT_EQ(store_->getFile("j", "image.exr"), sequentialExr(2));
}

TEST_F(TaskStoreTest, ATargetErrorStopsAtTheSamePassAsOneProcess) {
    // The pass one process stops at: the first whose film reaches the target.
    Film film(kWidth, kHeight);
    std::vector<double> errors;
    for (int p = 0; p < 40; ++p) {
        film.addPass(p, passImage(p));
        errors.push_back(film.relativeError());
    }
    const double target = errors[17];
    Film sequential(kWidth, kHeight);
    int stop = 0;
    for (; !reachedTargetError(sequential, target); ++stop)
        sequential.addPass(stop, passImage(stop));

    submit("t", 40, 4, 0, target);
    std::vector<Task> tasks;
    while (std::optional<ClaimedTask> c = claim("w")) tasks.push_back(c->task);
    ASSERT_EQ(tasks.size(), 10u);
    // Later ranges first: they wait, unmerged, for the ones before them.
    std::reverse(tasks.begin(), tasks.end());
    Consolidation last = Consolidation::Nothing;
    for (const Task& t : tasks) {
        last = handIn(t, /*passImages=*/true);
        if (last == Consolidation::Finished) break;
    }
    EXPECT_EQ(last, Consolidation::Finished);
    std::optional<Job> job = store_->get("t");
    EXPECT_EQ(job->state, JobState::Succeeded);
    EXPECT_EQ(job->passesDone, stop);
    EXPECT_EQ(job->stats["stop_reason"], "target_error");
    EXPECT_EQ(store_->getFile("t", "image.exr"), sequentialExr(stop));
}

TEST_F(TaskStoreTest, AWorkerThatFailsAJobsTasksIsBlockedFromIt) {
    submit("j", 4, 1);
    for (const char* id : {"a", "b", "c"}) seen(id);
    for (int i = 0; i < 2; ++i) {
        std::optional<ClaimedTask> c = claim("a");
        ASSERT_TRUE(c);
        EXPECT_FALSE(store_->failTask(c->task, "a", "boom", policy_));
    }
    EXPECT_FALSE(claim("a")) << "a failed the job twice: it gets none of its tasks";
    std::optional<ClaimedTask> b = claim("b");
    ASSERT_TRUE(b);
    EXPECT_EQ(b->task.firstPass, 0);  // a's failed task went back to the queue
    EXPECT_FALSE(store_->failTask(b->task, "b", "boom", policy_));
    EXPECT_FALSE(store_->failTask(claim("b")->task, "b", "boom", policy_));
    std::vector<WorkerInfo> workers = store_->listWorkers(kWorkerAliveSeconds);
    ASSERT_EQ(workers.size(), 3u);
    EXPECT_EQ(workers[0].tasksFailed, 2);
    // The third distinct worker blocked fails it (--fail-after-workers 3).
    EXPECT_FALSE(store_->failTask(claim("c")->task, "c", "boom", policy_));
    EXPECT_TRUE(store_->failTask(claim("c")->task, "c", "last words", policy_));
    std::optional<Job> job = store_->get("j");
    EXPECT_EQ(job->state, JobState::Failed);
    EXPECT_NE(job->error.find("3 workers"), std::string::npos) << job->error;
    EXPECT_NE(job->error.find("last words"), std::string::npos) << job->error;
}

TEST_F(TaskStoreTest, AJobFailsOnceEveryWorkerLeftIsBlockedFromIt) {
    submit("j", 4, 1);
    for (const char* id : {"a", "b", "c"}) seen(id);
    for (const char* id : {"a", "b"})
        for (int i = 0; i < 2; ++i)
            EXPECT_FALSE(store_->failTask(claim(id)->task, id, "boom", policy_)) << id;
    // c, alive and not blocked, could render it: the job waits for c.
    EXPECT_FALSE(claim("a"));
    EXPECT_EQ(store_->get("j")->state, JobState::Running);
    // c is gone (its row not renewed for kWorkerAliveSeconds); a and b keep their rows up.
    sql("UPDATE workers SET last_seen = last_seen - " + std::to_string(kWorkerAliveSeconds + 1) +
        " WHERE id = 'c'");
    EXPECT_FALSE(claim("a"));
    std::optional<Job> job = store_->get("j");
    EXPECT_EQ(job->state, JobState::Failed);
    EXPECT_NE(job->error.find("2 workers"), std::string::npos) << job->error;
    EXPECT_NE(job->error.find("boom"), std::string::npos) << job->error;
}

TEST_F(TaskStoreTest, ATaskThatStallsTooOftenFailsItsJob) {
    submit("j", 2, 2);
    for (int i = 0; i < 3; ++i) {
        ASSERT_TRUE(claim("w")) << i;
        expireLeases();
    }
    EXPECT_FALSE(claim("w"));
    std::optional<Job> job = store_->get("j");
    EXPECT_EQ(job->state, JobState::Failed);
    EXPECT_NE(job->error.find("3 times in a row"), std::string::npos) << job->error;
}

TEST_F(TaskStoreTest, CancellingEndsTheJobWhenItsLastRunningTaskIsGivenBack) {
    submit("j", 4, 2);
    std::optional<ClaimedTask> c = claim("w");
    ASSERT_TRUE(c);
    EXPECT_EQ(store_->cancel("j", 1001)->state, JobState::Running);
    EXPECT_EQ(store_->heartbeatTask(c->task, kLease), LeaseStatus::CancelRequested);
    EXPECT_FALSE(claim("w")) << "a cancelled job's tasks are not handed out";
    store_->releaseTask(c->task);
    EXPECT_EQ(store_->get("j")->state, JobState::Cancelled);
    // A queued split job ends at once.
    submit("q", 2, 1);
    EXPECT_EQ(store_->cancel("q", 1003)->state, JobState::Cancelled);
}

TEST_F(TaskStoreTest, ATaskHandedInAfterItsJobsCancelEndsTheJob) {
    // Handed in before its heartbeat saw the cancel: nothing else would end the job. Its result
    // is kept for a re-queue.
    submit("j", 4, 2);
    std::optional<ClaimedTask> c = claim("w");
    ASSERT_TRUE(c);
    store_->cancel("j", 1001);
    EXPECT_EQ(store_->completeTask(c->task, resultOf(c->task, false)), TaskCommit::Accepted);
    EXPECT_EQ(store_->get("j")->state, JobState::Cancelled);
    EXPECT_EQ(store_->requeue("j")->state, JobState::Queued);
    std::optional<ClaimedTask> rest = claim("w");
    ASSERT_TRUE(rest);
    EXPECT_EQ(rest->task.firstPass, 2) << "the finished task 0-2 is not rendered again";
    EXPECT_EQ(handIn(rest->task), Consolidation::Finished);
    EXPECT_EQ(store_->getFile("j", "image.exr"), sequentialExr(4));
}

TEST_F(TaskStoreTest, AnEndedJobsTasksLoseTheirLeases) {
    submit("j", 4, 2);
    std::optional<ClaimedTask> a = claim("w1");
    std::optional<ClaimedTask> b = claim("w2");
    ASSERT_TRUE(a && b);
    EXPECT_TRUE(store_->failJob(a->task, "bad input"));
    EXPECT_EQ(store_->heartbeatTask(b->task, kLease), LeaseStatus::Lost)
        << "a failed job's other tasks stop at their next heartbeat";
    EXPECT_EQ(store_->completeTask(b->task, resultOf(b->task, false)), TaskCommit::Fenced);
}

TEST_F(TaskStoreTest, ARequeuedJobKeepsItsFinishedTasks) {
    submit("j", 6, 2);
    std::optional<ClaimedTask> first = claim("w");
    std::optional<ClaimedTask> second = claim("w");
    ASSERT_TRUE(first && second);
    EXPECT_EQ(handIn(first->task), Consolidation::Merged);
    store_->cancel("j", 1002);
    store_->releaseTask(second->task);
    ASSERT_EQ(store_->get("j")->state, JobState::Cancelled);

    EXPECT_EQ(store_->requeue("j")->state, JobState::Queued);
    std::vector<Task> rest;
    while (std::optional<ClaimedTask> c = claim("w")) rest.push_back(c->task);
    ASSERT_EQ(rest.size(), 2u) << "the finished task 0-2 is not rendered again";
    EXPECT_EQ(rest[0].firstPass, 2);
    for (const Task& t : rest) store_->completeTask(t, resultOf(t, false));
    EXPECT_EQ(store_->consolidate("j"), Consolidation::Finished);
    std::optional<Job> job = store_->get("j");
    EXPECT_EQ(job->state, JobState::Succeeded);
    EXPECT_EQ(store_->getFile("j", "image.exr"), sequentialExr(6));
    // Only failed or cancelled jobs go back.
    EXPECT_EQ(store_->requeue("j")->state, JobState::Succeeded);
    EXPECT_FALSE(store_->requeue("nope"));
}

TEST_F(TaskStoreTest, FilesOfAnOldAttemptAreNotWritten) {
    submit("j", 2, 0);  // not split: the job-level protocol, whose attempt fences the files
    std::optional<Job> claimed = store_->claim("w", 1000, kLease, 3, 100);
    ASSERT_TRUE(claimed);
    EXPECT_TRUE(store_->putFile("j", claimed->attempt, "checkpoint.bin", "one"));
    EXPECT_FALSE(store_->putFile("j", claimed->attempt + 1, "checkpoint.bin", "two"));
    EXPECT_EQ(store_->getFile("j", "checkpoint.bin"), "one");
    store_->removeFiles("j");
    EXPECT_FALSE(store_->getFile("j", "checkpoint.bin"));
}

}  // namespace
}  // namespace caustic::server

#endif  // CAUSTIC_HAS_POSTGRES
