// Photon look-ups: our PhotonKdTree against nanoflann's KDTreeSingleIndexAdaptor on the same points
// (photons traced in cornell-spheres), and against brute force. Build time, memory, and queries per
// second for the k nearest (k = 10, 50, 100) and a fixed radius, with 1 thread and with every
// OpenMP thread. The indexes run interleaved (A B C A B C) because the machine is shared and noisy;
// read the ratios, not the seconds.
#include <omp.h>
#include <nanoflann.hpp>

#include "bench_common.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "photons/brute_force_neighbors.h"
#include "photons/photon_kdtree.h"
#include "photons/photon_tracer.h"
#include "scene/scene.h"

namespace {

using namespace caustic;
using namespace caustic::bench;

struct Options {
    int repeats = 5;
    std::vector<int> sizes = {10000, 100000, 1000000};
    int queries = 100000;
    std::vector<int> leaves = {10, 8, 16};
    double bruteWork = 2e7;  // brute-force queries per size: this over the size (at least 5)
};

// Parses the command line into `o`; returns -1 to run, else the exit code.
int parseArgs(int argc, char** argv, Options& o) {
    CLI::App app("k-nearest photon look-ups: our photon kd-tree against nanoflann and brute force.",
                 "bench_photon_knn");
    bool smoke = false;
    addCommonOptions(app, o.repeats, "Builds and interleaved timings per measure", smoke,
                     "1000 and 5000 photons, 1000 queries, 1 repeat");
    caustic::cli::addNumber(app, "--sizes", o.sizes, 1, 1e9, "Photons in the map, comma-separated");
    caustic::cli::addNumber(app, "--queries", o.queries, 1, 1e9,
                            "Query points, the same for every index and size");
    caustic::cli::addNumber(app, "--leaves", o.leaves, 1, 1e6,
                            "nanoflann leaf_max_size values, comma-separated (ours is fixed: PhotonKdTree::kLeafSize)");
    if (int exitCode = parseBenchmarkArgs(app, argc, argv); exitCode >= 0) return exitCode;
    if (smoke) {
        o.repeats = 1;
        o.sizes = {1000, 5000};
        o.queries = 1000;
        o.bruteWork = 1e6;
    }
    return -1;
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    std::string a, b, c;
    in >> a >> b >> c;
    return a + " " + b + " " + c;
}

// One row of a Markdown table.
template <class... Cells>
void row(std::ostream& out, const Cells&... cells) {
    ((out << "| " << cells << " "), ...);
    out << "|\n";
}

// At least `want` stored photon positions (fewer only if the scene stores none), from paths traced
// with `seed`: a pilot run gives the photons stored per path.
std::vector<Vec3> photonPositions(const Scene& scene, const Accelerator& accel, size_t want,
                                  uint64_t seed, uint64_t& emitted) {
    PhotonTracingOptions o;
    o.seed = seed;
    o.photons = 20000;
    const PhotonTracing pilot = tracePhotons(scene, accel, o);
    const double perPath = std::max(1e-3, double(pilot.photons.size()) / double(o.photons));
    o.photons = uint64_t(1.05 * double(want) / perPath) + 1000;
    const PhotonTracing t = tracePhotons(scene, accel, o);
    emitted = t.emitted;
    std::vector<Vec3> p;
    for (const Photon& ph : t.photons) p.push_back(ph.p);
    return p;
}

// Per-thread buffers, reused from query to query.
struct Scratch {
    std::vector<Neighbor> found;                   // ours
    std::vector<uint32_t> ids;                     // nanoflann kNN
    std::vector<float> dist2;                      // nanoflann kNN
    std::vector<std::pair<uint32_t, float>> hits;  // nanoflann radius
};

// One index under test. query(): k > 0, the k nearest; k == 0, every point within radius2.
// Returns how many were found; dist2(s, j) is then the j-th smallest squared distance.
struct Index {
    double bytes = 0;         // held by the index, per point
    bool readsInput = false;  // it also reads the caller's points (12 bytes each)
    virtual ~Index() = default;
    virtual size_t query(const Vec3& p, int k, float radius2, Scratch& s) const = 0;
    virtual float dist2(const Scratch& s, size_t j) const = 0;
};

// Indexes that answer into Scratch::found, as ours does.
struct FoundIndex : Index {
    float dist2(const Scratch& s, size_t j) const override { return s.found[j].dist2; }
};

struct Ours final : FoundIndex {
    PhotonKdTree tree;
    explicit Ours(const std::vector<Vec3>& points) : tree(points) {
        bytes = double(tree.memoryBytes()) / double(points.size());
    }
    size_t query(const Vec3& p, int k, float radius2, Scratch& s) const override {
        if (k > 0)
            tree.nearest(p, k, kInfinity, s.found);
        else
            tree.withinRadius(p, radius2, s.found);
        return s.found.size();
    }
};

// Brute force: BruteForceNeighbors, the tests' reference and the renderer's brute_force look-up,
// one scan of every point into a bounded max-heap of k.
struct Brute final : FoundIndex {
    BruteForceNeighbors reference;
    explicit Brute(const std::vector<Vec3>& p) : reference(p) {}
    size_t query(const Vec3& p, int k, float, Scratch& s) const override {
        reference.nearest(p, k, kInfinity, s.found);
        return s.found.size();
    }
};

// nanoflann reads the points where they are, through this adaptor.
struct Cloud {
    const std::vector<Vec3>* points;
    size_t kdtree_get_point_count() const { return points->size(); }
    float kdtree_get_pt(uint32_t i, size_t d) const { return (*points)[i][glm::length_t(d)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;
    }
};
using NanoTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>,
                                                     Cloud, 3, uint32_t>;

// nanoflann as documented: its leaves index the caller's points through its index array (vAcc).
// `reorder`: after the build, a copy of the points in vAcc order replaces them and vAcc becomes
// the identity, so that leaves read contiguous points, as ours does (same tree, same answers).
struct Nano final : Index {
    Cloud cloud;  // before `tree`, which keeps a reference to it
    NanoTree tree;
    std::vector<Vec3> ordered;
    Nano(const std::vector<Vec3>& points, int leaf, bool reorder)
        : cloud{&points}, tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(size_t(leaf))) {
        bytes = double(tree.usedMemory(tree)) / double(points.size());
        readsInput = !reorder;
        if (!reorder) return;
        ordered.reserve(points.size());
        for (uint32_t& a : tree.vAcc) {
            ordered.push_back(points[a]);
            a = uint32_t(ordered.size() - 1);
        }
        cloud.points = &ordered;
        bytes += sizeof(Vec3);
    }
    size_t query(const Vec3& p, int k, float radius2, Scratch& s) const override {
        if (k == 0) return tree.radiusSearch(&p.x, radius2, s.hits, nanoflann::SearchParams());
        s.ids.resize(size_t(k));
        s.dist2.resize(size_t(k));
        return tree.knnSearch(&p.x, size_t(k), s.ids.data(), s.dist2.data());
    }
    float dist2(const Scratch& s, size_t j) const override { return s.dist2[j]; }
};

// Answers every query with `threads` threads; returns seconds. The count found is summed into
// `checksum` so that the work cannot be optimized away.
double timed(const Index& index, const std::vector<Vec3>& q, int k, float radius2, int threads,
             double& checksum) {
    double sum = 0;
    const auto start = std::chrono::steady_clock::now();
#pragma omp parallel num_threads(threads) reduction(+ : sum)
    {
        Scratch s;
#pragma omp for schedule(dynamic, 64)
        for (ptrdiff_t i = 0; i < ptrdiff_t(q.size()); ++i)
            sum += double(index.query(q[size_t(i)], k, radius2, s));
    }
    const double seconds = secondsSince(start);
    checksum += sum;
    return seconds;
}

// Counts the queries whose sorted dist2 differ from ours by more than `tolerance` (relative);
// `worst` gets the largest relative difference. Also the warm-up. kth: ours' k-th dist2 per query.
size_t differing(const Index& ours, const Index& other, const std::vector<Vec3>& queries, int k,
                 double tolerance, double& worst, std::vector<float>& kth) {
    size_t bad = 0;
    worst = 0;
    kth.resize(queries.size());
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : bad) reduction(max : worst)
    for (ptrdiff_t i = 0; i < ptrdiff_t(queries.size()); ++i) {
        Scratch a, b;
        const size_t found = ours.query(queries[size_t(i)], k, 0, a);
        bool same = other.query(queries[size_t(i)], k, 0, b) == found;
        kth[size_t(i)] = ours.dist2(a, found - 1);
        for (size_t j = 0; same && j < found; ++j) {
            double rel = std::abs(double(ours.dist2(a, j)) - other.dist2(b, j)) /
                         std::max(1e-30, double(ours.dist2(a, j)));
            worst = std::max(worst, rel);
            same = rel <= tolerance;
        }
        bad += !same;
    }
    return bad;
}

double qps(const std::vector<double>& seconds, size_t n, bool ofMin = false) {
    return double(n) /
           (ofMin ? *std::min_element(seconds.begin(), seconds.end()) : median(seconds));
}

// Every measure on one photon map: its tables go to `out`, its row of the summary to `summary`.
// Returns false when a sanity check fails.
bool runSize(const std::vector<Vec3>& points, const std::vector<Vec3>& queries, const Options& opt,
             int allThreads, std::ostream& summary, std::ostream& out) {
    const size_t n = points.size(), nq = queries.size();
    const std::string reps = std::to_string(opt.repeats);
    struct Variant {
        std::string name;
        int leaf;  // 0: ours
        bool reorder;
        int threads;
    };
    std::vector<Variant> variants = {{"ours", 0, false, allThreads},
                                     {"ours, 1 thread", 0, false, 1}};
    for (int leaf : opt.leaves)
        variants.push_back({"nanoflann leaf " + std::to_string(leaf), leaf, false, 1});
    variants.push_back(
        {"nanoflann leaf " + std::to_string(opt.leaves[0]) + " reordered", opt.leaves[0], true, 1});
    std::map<std::string, std::vector<double>> build;
    std::map<std::string, std::unique_ptr<Index>> idx;
    for (int rep = 0; rep < opt.repeats; ++rep)  // builds, interleaved; the last of each is kept
        for (const Variant& v : variants) {
            idx[v.name].reset();
            omp_set_num_threads(v.threads);
            const auto start = std::chrono::steady_clock::now();
            if (v.leaf == 0)
                idx[v.name] = std::make_unique<Ours>(points);
            else
                idx[v.name] = std::make_unique<Nano>(points, v.leaf, v.reorder);
            build[v.name].push_back(secondsSince(start));
            omp_set_num_threads(allThreads);
        }
    out << "### " << n << " photons\n\nBuild, median of " << reps << " interleaved builds (ours "
        << "on every OpenMP thread, or on 1; nanoflann 1.4.3 builds on 1 thread):\n\n| index | "
        << "build ms | min ms | index bytes / point | + input points it reads |\n"
        << "|---|---:|---:|---:|---:|\n";
    std::vector<std::string> names;
    double nanoBuild = 1e30;
    for (const auto& [name, leaf, reorder, threads] : variants) {
        const Index& x = *idx[name];
        const std::vector<double>& s = build[name];
        row(out, name, fmt("%.2f", 1e3 * median(s)),
            fmt("%.2f", 1e3 * *std::min_element(s.begin(), s.end())), fmt("%.2f", x.bytes),
            fmt("%.2f", x.bytes + double(x.readsInput ? sizeof(Vec3) : 0)));
        if (name.rfind("nanoflann", 0) == 0) nanoBuild = std::min(nanoBuild, median(s));
        if (name != "ours, 1 thread") names.push_back(name);
    }
    idx.erase("ours, 1 thread");

    // Sanity, and the warm-up: each nanoflann's sorted k = 50 dist2 against ours, on every query.
    const int k = std::min<int>(50, int(n));
    std::vector<float> kth;
    bool ok = true;
    out << "\nSanity: sorted k = 50 dist² against ours, relative tolerance 1e-5, on every query:"
        << "\n\n| index | queries differing | max relative difference |\n|---|---:|---:|\n";
    for (size_t m = 1; m < names.size(); ++m) {
        double worst = 0;
        const size_t bad = differing(*idx["ours"], *idx[names[m]], queries, k, 1e-5, worst, kth);
        row(out, names[m], bad, fmt("%.2g", worst));
        ok = ok && bad == 0;
    }
    std::nth_element(kth.begin(), kth.begin() + ptrdiff_t(nq / 2), kth.end());
    const float radius2 = kth[nq / 2];  // finds about 50 points around the median query

    out << "\nQueries per second (millions), " << nq << " queries, median of " << reps
        << " interleaved runs; radius: r² = " << fmt("%.3g", radius2)
        << ", the median query's 50th-nearest dist²:\n\n| query | threads |";
    for (const std::string& name : names) out << " " << name << " |";
    out << " fastest nanoflann | ours / it | same, of mins |\n|---|---:|";
    for (size_t i = 0; i < names.size() + 3; ++i) out << "---:|";
    out << "\n";
    summary << "| " << n;
    double kdOne = 0;  // ours, k = 50, 1 thread
    for (int kq : {50, 10, 100, 0})
        for (int threads : {1, allThreads}) {
            std::map<std::string, std::vector<double>> s;
            double checksum = 0;
            for (int rep = 0; rep < opt.repeats; ++rep)
                for (const std::string& name : names)
                    s[name].push_back(timed(*idx[name], queries, kq, radius2, threads, checksum));
            std::string best = names[1];
            for (const std::string& name : names)
                if (name != "ours" && qps(s[name], nq) > qps(s[best], nq)) best = name;
            const std::string ratio = fmt("%.2f×", qps(s["ours"], nq) / qps(s[best], nq));
            out << "| " << (kq ? "k = " + std::to_string(kq) : "radius") << " | " << threads
                << " |";
            for (const std::string& name : names)
                out << " " << fmt("%.3f", qps(s[name], nq) / 1e6) << " |";
            out << " " << best.substr(10) << " | " << ratio << " | "
                << fmt("%.2f×", qps(s["ours"], nq, true) / qps(s[best], nq, true)) << " |\n";
            if (kq == 50) summary << " | " << ratio << " (" << best.substr(10) << ")";
            if (kq == 50 && threads == 1) kdOne = qps(s["ours"], nq);
        }

    // Brute force, 1 thread, k = 50, on queries spread over the set.
    const size_t bq = std::min(nq, std::max<size_t>(5, size_t(opt.bruteWork / double(n))));
    std::vector<Vec3> sample;
    for (size_t j = 0; j < bq; ++j) sample.push_back(queries[j * (nq / bq)]);
    const Brute brute(points);
    std::vector<double> bruteSeconds;
    double checksum = 0;
    for (int rep = 0; rep < opt.repeats; ++rep)
        bruteSeconds.push_back(timed(brute, sample, k, 0, 1, checksum));
    out << "\nBrute force against ours, k = 50, 1 thread, " << bq << " queries spread over the "
        << "set, median of " << reps << " runs (ours: the k = 50, 1-thread row above):\n\n"
        << "| method | queries / s | ours / it | answers differing from ours |\n"
        << "|---|---:|---:|---:|\n";
    double worst = 0;
    const size_t bad = differing(*idx["ours"], brute, sample, k, 0, worst, kth);
    const double speedup = kdOne / qps(bruteSeconds, bq);
    row(out, "BruteForceNeighbors (bounded heap of 50)", fmt("%.1f", qps(bruteSeconds, bq)),
        fmt("%.0f×", speedup), bad);
    ok = ok && bad == 0;
    row(out, "ours", fmt("%.0f", kdOne), "1×", "—");
    out << "\n";
    summary << " | " << fmt("%.2f×", nanoBuild / median(build["ours, 1 thread"])) << " | "
            << fmt("%.0f×", speedup) << " |\n";
    return ok;
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    if (int exitCode = parseArgs(argc, argv, opt); exitCode >= 0) return exitCode;
    const int allThreads = omp_get_max_threads();
    const std::string loadBefore = loadAverage();
    std::ostringstream summary, detail;
    bool ok = true;
    try {
        auto scene = loadScene(
            readJsonFile(std::string(CAUSTIC_DEFAULT_SCENES_DIR) + "/cornell-spheres.json"),
            SceneOptions{CAUSTIC_DEFAULT_ASSETS_DIR});
        auto accel = createAccelerator("embree", scene->geometry);
        const size_t most = size_t(*std::max_element(opt.sizes.begin(), opt.sizes.end()));
        uint64_t emitted = 0, queryEmitted = 0;
        const std::vector<Vec3> all = photonPositions(*scene, *accel, most, 1, emitted);
        std::vector<Vec3> queries =
            photonPositions(*scene, *accel, size_t(opt.queries), 2, queryEmitted);
        queries.resize(std::min(queries.size(), size_t(opt.queries)));
        std::cout << "Points: the first N photons stored by tracePhotons in cornell-spheres.json "
                  << "(seed 1: " << all.size() << " stored from " << emitted << " paths). Queries: "
                  << "the first " << queries.size() << " photons of an independent tracing (seed "
                  << "2), the same for every index and size.\n\n";
        for (int size : opt.sizes) {
            const std::vector<Vec3> points(
                all.begin(), all.begin() + std::min<ptrdiff_t>(size, ptrdiff_t(all.size())));
            ok = runSize(points, queries, opt, allThreads, summary, detail) && ok;
            std::cerr << "done " << points.size() << " points\n";
        }
    } catch (const std::exception& e) {
        std::cerr << "bench_photon_knn: " << e.what() << "\n";
        return 1;
    }
    std::cout << "### Summary: ours over the fastest nanoflann variant (> 1: ours faster), and "
              << "ours over brute force\n\n| photons | k = 50, 1 thread | k = 50, " << allThreads
              << " threads | build, both 1 thread | ours / BruteForceNeighbors |\n"
              << "|---:|---:|---:|---:|---:|\n"
              << summary.str() << "\n"
              << detail.str() << "Load average before: " << loadBefore
              << "; after: " << loadAverage() << ".\n";
    return ok ? 0 : 1;
}
