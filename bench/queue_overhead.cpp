// The scale-out queue's cost per task on PostgreSQL (server/store/task.h): what one call of each
// store operation a worker makes per task takes — claimTask, heartbeatTask, workerSeen and
// completeTask (the hand-in, which stores the task's film) — and a consolidation batch of one
// result (read the job's film.bin, merge, write it and the preview) and the last one (the
// images), at 64², 256² and 512², with the bytes each moves. bench/README.md, "Scale-out".
//
// Google Benchmark with manual time: each benchmark times one operation with a steady clock; what
// it needs around it (the claim before a hand-in, the hand-in after a claim) runs untimed. Each
// benchmark runs a fixed number of iterations on jobs of its own, removed at its end, so the
// medians and maxima of the Markdown table at the end come from the same calls as Google
// Benchmark's means.
//
// The server is a throwaway cluster (tests/support/postgres.sh: PostgreSQL 15 on 127.0.0.1, fsync
// off), or the one of --store / $CAUSTIC_BENCH_STORE: a database nobody else uses (claims take the
// oldest job's tasks, whoever queued them).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <pqxx/pqxx>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>

#include "bench_common.h"
#include "film/film.h"
#include "jobs/clock.h"
#include "postgres_cluster.h"
#include "render/settings.h"
#include "scene/scene.h"
#include "store/postgres/job_store.h"

namespace {

using namespace caustic;
using namespace caustic::server;

// What a benchmark measured, call by call, for the table at the end.
struct Row {
    std::string operation{}, image{};
    std::vector<double> ms{};
    std::map<std::string, double> bytes{};  ///< Column name -> bytes per call.
};
std::vector<Row> rows;

// The store every benchmark uses, and a plain connection for the byte counts.
std::unique_ptr<PostgresJobStore> store;
std::unique_ptr<pqxx::connection> sql;
const FarmPolicy kPolicy{.leaseSeconds = 600};  // no lease expires during a run

// A split job of `tasks` one-pass tasks on cornell-box at size², as the service stores one.
Job makeJob(int size, int tasks) {
    static int count = 0;
    Job job;
    job.id = "bench-" + std::to_string(getpid()) + "-" + std::to_string(++count);
    job.scene = readJsonFile(CAUSTIC_DEFAULT_SCENES_DIR "/cornell-box.json");
    job.scene["camera"]["width"] = job.scene["camera"]["height"] = size;
    job.sceneName = "cornell-box";
    RenderSettings settings;
    settings.spp = tasks;
    settings.sppPerPass = 1;
    job.settings = settings.toJson();
    job.createdAt = unixNow();
    job.taskPasses = 1;
    job.passesTotal = tasks;
    store->insert(job, {}, {});
    return job;
}

// One pass with a renderer's spread of values: most 0-10, 1% fireflies up to 1e6.
std::vector<Color> passImage(int size) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Color> pass(size_t(size) * size_t(size));
    for (Color& c : pass)
        for (int k = 0; k < 3; ++k)
            c[k] = u(rng) < 0.01f ? std::pow(10.0f, 6.0f * u(rng)) : 10.0f * u(rng) * u(rng);
    return pass;
}

// The result of a one-pass task, as a worker hands it in (Film::toBytes()).
TaskResult makeResult(const Task& task, const std::vector<Color>& pass, int size) {
    Film film(size, size);
    film.addPass(task.firstPass, pass);
    TaskResult result;
    result.width = result.height = size;
    result.film = film.toBytes();
    result.passesDone = 1;
    result.rays = uint64_t(size) * uint64_t(size);
    result.renderSeconds = 1;
    return result;
}

Task claim(const std::string& worker) {
    std::optional<ClaimedTask> claimed = store->claimTask(worker, kPolicy);
    if (!claimed) throw std::runtime_error("no task to claim");
    return claimed->task;
}

// Times `call` (one store operation) into the benchmark's manual time and `row`.
template <typename F>
void timed(benchmark::State& state, Row& row, F&& call) {
    const auto start = std::chrono::steady_clock::now();
    call();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(seconds);
    row.ms.push_back(seconds * 1000);
}

// The size of each of a job's files, by name, and of its film.bin as stored (TOAST may compress
// it) under "film.bin stored".
std::map<std::string, double> fileBytes(const std::string& jobId) {
    std::map<std::string, double> sizes;
    pqxx::nontransaction tx(*sql);
    for (const pqxx::row& r : tx.exec_params(
             "SELECT name, octet_length(data), pg_column_size(data) FROM job_files WHERE job_id "
             "= $1",
             jobId)) {
        sizes[r[0].as<std::string>()] = r[1].as<double>();
        sizes[r[0].as<std::string>() + " stored"] = r[2].as<double>();
    }
    return sizes;
}

void finish(benchmark::State& state, Row row, const Job& job) {
    for (const auto& [name, bytes] : row.bytes)
        state.counters[name] =
            benchmark::Counter(bytes, benchmark::Counter::kDefaults, benchmark::Counter::kIs1024);
    store->remove(job.id);
    rows.push_back(std::move(row));
}

std::string sizeName(int size) {
    return std::to_string(size) + "²";
}

// A claim of the next task (the hand-in after it untimed, so the job's tasks run out as in a
// render). The job row it returns holds the scene and settings JSON.
void BM_Claim(benchmark::State& state) {
    const int size = int(state.range(0));
    const Job job = makeJob(size, int(state.max_iterations) + 1);
    const std::vector<Color> pass = passImage(size);
    Row row{"claimTask", sizeName(size)};
    for (auto _ : state) {
        Task task;
        timed(state, row, [&] { task = claim("bench-worker"); });
        store->completeTask(task, makeResult(task, pass, size));
        store->consolidate(job.id);
    }
    row.bytes["job JSON bytes"] = double(job.scene.dump().size() + job.settings.dump().size());
    finish(state, std::move(row), job);
}

// A lease renewal of a running task (the worker sends one a second: min(1, lease / 4) s).
void BM_Heartbeat(benchmark::State& state) {
    const Job job = makeJob(int(state.range(0)), 2);
    const Task task = claim("bench-worker");
    Row row{"heartbeatTask", sizeName(int(state.range(0)))};
    for (auto _ : state)
        timed(state, row, [&] {
            if (store->heartbeatTask(task, kPolicy.leaseSeconds) != LeaseStatus::Held)
                throw std::runtime_error("the lease was lost");
        });
    finish(state, std::move(row), job);
}

// The worker's row, written twice per task (before the claim and after it: GET /api/workers).
void BM_WorkerSeen(benchmark::State& state) {
    const Job job = makeJob(int(state.range(0)), 1);
    WorkerInfo me;
    me.id = "bench-worker";
    me.host = "bench";
    me.cores = 2;
    me.threads = 1;
    me.startedAt = unixNow();
    Row row{"workerSeen", "any"};
    for (auto _ : state)
        timed(state, row, [&] {
            me.lastSeen = unixNow();
            store->workerSeen(me);
        });
    finish(state, std::move(row), job);
}

// A hand-in: the task's film stored in its row (no lock on the job, no film read).
void BM_Complete(benchmark::State& state) {
    const int size = int(state.range(0));
    const Job job = makeJob(size, int(state.max_iterations) + 1);
    const std::vector<Color> pass = passImage(size);
    Row row{"completeTask (hand-in)", sizeName(size)};
    TaskResult result;
    for (auto _ : state) {
        const Task task = claim("bench-worker");
        result = makeResult(task, pass, size);
        timed(state, row, [&] {
            if (store->completeTask(task, result) != TaskCommit::Accepted)
                throw std::runtime_error("the result was not accepted");
        });
        store->consolidate(job.id);
    }
    row.bytes["result film bytes"] = double(result.film.size());
    finish(state, std::move(row), job);
}

// A consolidation batch of one result into a job that goes on: read film.bin, decode, merge, write
// film.bin and preview.png, update the job, in one transaction under the job's advisory lock.
void BM_Consolidate(benchmark::State& state) {
    const int size = int(state.range(0));
    const Job job = makeJob(size, int(state.max_iterations) + 1);
    const std::vector<Color> pass = passImage(size);
    Row row{"consolidate (one result)", sizeName(size)};
    for (auto _ : state) {
        const Task task = claim("bench-worker");
        store->completeTask(task, makeResult(task, pass, size));
        timed(state, row, [&] {
            if (store->consolidate(job.id) != Consolidation::Merged)
                throw std::runtime_error("the result was not merged");
        });
    }
    const std::map<std::string, double> files = fileBytes(job.id);
    row.bytes["film.bin bytes (read + written)"] = files.at("film.bin");
    row.bytes["film.bin stored bytes"] = files.at("film.bin stored");
    row.bytes["preview.png bytes"] = files.at("preview.png");
    finish(state, std::move(row), job);
}

// The last batch of a job: merges and writes image.exr and image.png, ends the job (no film.bin
// to read: a one-task job).
void BM_ConsolidateLast(benchmark::State& state) {
    const int size = int(state.range(0));
    const std::vector<Color> pass = passImage(size);
    Row row{"consolidate (last: images)", sizeName(size)};
    Job job;
    for (auto _ : state) {
        if (!job.id.empty()) store->remove(job.id);
        job = makeJob(size, 1);
        const Task task = claim("bench-worker");
        store->completeTask(task, makeResult(task, pass, size));
        timed(state, row, [&] {
            if (store->consolidate(job.id) != Consolidation::Finished)
                throw std::runtime_error("the job did not finish");
        });
    }
    const std::map<std::string, double> files = fileBytes(job.id);
    row.bytes["image.exr bytes"] = files.at("image.exr");
    finish(state, std::move(row), job);
}

void registerBenchmarks(bool smoke) {
    const std::vector<int64_t> sizes =
        smoke ? std::vector<int64_t>{64} : std::vector<int64_t>{64, 256, 512};
    const auto iterations = [smoke](int64_t n) { return smoke ? 3 : n; };
    const auto add = [](const char* name, void (*fn)(benchmark::State&)) {
        return benchmark::RegisterBenchmark(name, fn)->UseManualTime()->Unit(
            benchmark::kMillisecond);
    };
    add("claimTask", BM_Claim)->Arg(64)->Iterations(iterations(200));
    add("heartbeatTask", BM_Heartbeat)->Arg(64)->Iterations(iterations(200));
    add("workerSeen", BM_WorkerSeen)->Arg(64)->Iterations(iterations(200));
    for (int64_t size : sizes) {
        const int64_t n = size >= 512 ? 20 : size >= 256 ? 40 : 100;
        add("completeTask", BM_Complete)->Arg(size)->Iterations(iterations(n));
        add("consolidate/one", BM_Consolidate)->Arg(size)->Iterations(iterations(n));
        add("consolidate/last", BM_ConsolidateLast)->Arg(size)->Iterations(iterations(n / 4));
    }
}

void printTable() {
    std::cout << "\n| operation | image | calls | median ms | mean ms | max ms | bytes per call "
                 "|\n|---|---|---:|---:|---:|---:|---|\n";
    for (const Row& row : rows) {
        double sum = 0;
        for (double ms : row.ms) sum += ms;
        std::string bytes;
        for (const auto& [name, b] : row.bytes)
            bytes += (bytes.empty() ? "" : "; ") + name + " " + std::to_string(int64_t(b));
        std::cout << "| " << row.operation << " | " << row.image << " | " << row.ms.size() << " | "
                  << bench::fmt("%.3f", bench::median(row.ms)) << " | "
                  << bench::fmt("%.3f", sum / double(row.ms.size())) << " | "
                  << bench::fmt("%.3f", *std::max_element(row.ms.begin(), row.ms.end())) << " | "
                  << bytes << " |\n";
    }
}

}  // namespace

int main(int argc, char** argv) {
    const std::string command = bench::commandLine(argc, argv);
    benchmark::Initialize(&argc, argv);
    CLI::App app("The scale-out queue's cost per task on PostgreSQL.", "queue_overhead");
    std::string url = std::getenv("CAUSTIC_BENCH_STORE") ? std::getenv("CAUSTIC_BENCH_STORE") : "";
    bool smoke = false;
    app.add_option("--store", url,
                   "A postgresql:// database nobody else uses (default: $CAUSTIC_BENCH_STORE, "
                   "else a throwaway cluster from tests/support/postgres.sh)");
    app.add_flag("--smoke", smoke, "64² only, 3 calls each: checks that it runs (CTest)");
    if (int exitCode = cli::parseCommandLine(app, argc, argv); exitCode >= 0) return exitCode;
    std::cout << "Machine: nproc " << bench::onlineCpus() << ", " << bench::cpuModel()
              << ". Command: `" << command << "`\n\n";
    std::unique_ptr<bench::PostgresCluster> cluster;
    int status = 0;
    try {
        if (url.empty()) {
            if (!bench::haveServerBinaries()) {
                std::cerr << "queue_overhead: no PostgreSQL 15 server binaries: skipped\n";
                return 77;
            }
            cluster = std::make_unique<bench::PostgresCluster>();
            url = cluster->url();
        }
        store = std::make_unique<PostgresJobStore>(url);
        sql = std::make_unique<pqxx::connection>(url);
        registerBenchmarks(smoke);
        benchmark::RunSpecifiedBenchmarks();
        benchmark::Shutdown();
        printTable();
    } catch (const std::exception& e) {
        std::cerr << "queue_overhead: " << e.what() << "\n";
        status = 1;
    }
    // Connections first: then the cluster stops.
    sql.reset();
    store.reset();
    return status;
}
