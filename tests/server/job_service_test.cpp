// The job service (server/jobs/job_service.h) over a real SQLite store: it gives ids and time
// stamps, keeps Idempotency-Key answers, applies the queue limit, names the JSON path of a bad
// body, and admits a mesh scene by its counts, scanning each mesh file once.
#include "jobs/job_service.h"

#include <gtest/gtest.h>

#include <regex>

#include "jobs/worker_pool.h"
#include "store/sqlite/job_store.h"
#include "support/temp_dir.h"

namespace caustic::server {
namespace {

using caustic::testing::TempDir;
using Outcome = Submission::Outcome;

Json meshJob(const std::string& file) {
    return Json::parse(R"({"scene": {
      "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "width": 8, "height": 8},
      "materials": {"white": {"type": "diffuse"}},
      "shapes": [{"type": "mesh", "file": ")" +
                       file + R"(", "material": "white"}]}, "settings": {"spp": 1}})");
}

class JobServiceTest : public ::testing::Test {
protected:
    JobServiceTest()
        : store_(dir_.path() / "jobs.sqlite3"),
          files_(dir_.path()),
          service_(config_, store_, files_, events_, [this] { ++wakes_; }) {
        config_.assetsDir = dir_.path();
        config_.scenesDir = CAUSTIC_SOURCE_DIR "/scenes";
        config_.limits.maxQueuedJobs = 3;
        dir_.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    }
    Submission submit(const Json& body, const std::string& key = {}) {
        if (std::optional<Submission> earlier = service_.replay(key, body.dump())) return *earlier;
        return service_.submit(body, body.dump(), key, [](const Job& j) { return j.id; });
    }

    TempDir dir_;
    ServerConfig config_;
    SqliteJobStore store_;
    FolderJobFiles files_;
    JobEvents events_;
    int wakes_ = 0;
    JobService service_;
};

TEST_F(JobServiceTest, QueuesWithARandomIdAndATime) {
    const double before = unixNow();
    Submission a = submit({{"scene", "cornell-spheres"}});
    Submission b = submit({{"scene", "cornell-spheres"}});
    ASSERT_EQ(a.outcome, Outcome::Accepted) << a.detail;
    EXPECT_EQ(a.response.status, 202);
    EXPECT_TRUE(std::regex_match(a.response.jobId, std::regex("[0-9a-f]{32}")));
    EXPECT_NE(a.response.jobId, b.response.jobId);
    EXPECT_EQ(a.response.body, a.response.jobId);  // what `respond` made
    std::optional<Job> job = service_.get(a.response.jobId);
    ASSERT_TRUE(job);
    EXPECT_EQ(job->state, JobState::Queued);
    EXPECT_GE(job->createdAt, before);
    EXPECT_LE(job->createdAt, unixNow());
    EXPECT_EQ(wakes_, 2);
}

TEST_F(JobServiceTest, IdempotencyKeyReplaysTheFirstAnswer) {
    const Json body{{"scene", "cornell-spheres"}};
    Submission first = submit(body, "k1");
    Submission again = submit(body, "k1");
    EXPECT_EQ(again.outcome, Outcome::Replayed);
    EXPECT_EQ(again.response.jobId, first.response.jobId);
    EXPECT_EQ(service_.countByState()[JobState::Queued], 1);
    EXPECT_EQ(submit({{"scene", "cornell-box"}}, "k1").outcome, Outcome::KeyReused);
    EXPECT_EQ(submit(body, std::string(201, 'k')).outcome, Outcome::BadKey);
}

TEST_F(JobServiceTest, QueueLimitAndInvalidBodies) {
    Submission bad = submit({{"scene", "cornell-spheres"}, {"settings", {{"spp", 0}}}});
    EXPECT_EQ(bad.outcome, Outcome::Invalid);
    EXPECT_EQ(bad.pointer, "/settings/spp");
    for (int i = 0; i < 3; ++i)
        EXPECT_EQ(submit({{"scene", "cornell-spheres"}}).outcome, Outcome::Accepted);
    Submission full = submit({{"scene", "cornell-spheres"}});
    EXPECT_EQ(full.outcome, Outcome::QueueFull);
    EXPECT_EQ(full.detail, "the queue is full (3 jobs waiting)");
    // Cancelled and deleted jobs wait no more.
    ASSERT_TRUE(service_.cancel(service_.list(std::nullopt, 1, INT64_MAX).jobs[0].id));
    EXPECT_EQ(submit({{"scene", "cornell-spheres"}}).outcome, Outcome::Accepted);
    EXPECT_TRUE(service_.remove(service_.list(std::nullopt, 1, INT64_MAX).jobs[0].id));
    EXPECT_FALSE(service_.remove("0123456789abcdef0123456789abcdef"));
}

// Admission reads a mesh's counts once, and never parses it: a vertex no render could take is
// admitted (the worker's load refuses it), and a file that does not change is not read again.
TEST_F(JobServiceTest, AdmitsAMeshByItsCountsScanningItOnce) {
    config_.limits.maxQueuedJobs = 10;
    for (int i = 0; i < 2; ++i) EXPECT_EQ(submit(meshJob("tri.obj")).outcome, Outcome::Accepted);
    EXPECT_EQ(service_.meshScans(), 1u);
    dir_.write("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n");
    EXPECT_EQ(submit(meshJob("inf.obj")).outcome, Outcome::Accepted);
    EXPECT_EQ(service_.meshScans(), 2u);
    Submission missing = submit(meshJob("missing.obj"));
    EXPECT_EQ(missing.outcome, Outcome::Invalid);
    EXPECT_EQ(missing.pointer, "/scene/shapes/0/file");
}

}  // namespace
}  // namespace caustic::server
