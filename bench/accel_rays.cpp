// Our kd-tree against Embree (and brute force on the small mesh): build time, memory, and rays per
// second for primary and random rays, closest hit and occlusion, with 1 thread and with every
// OpenMP thread. kdtree and embree run side by side in one process, interleaved (A B A B), because
// the machine is shared and noisy; read the ratios, not the seconds.
#include <omp.h>

#include <sched.h>
#include "bench_common.h"
#include "bench_meshes.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "accel/accelerator.h"
#include "accel/kdtree/kdtree.h"
#include "core/sampling.h"
#include "scene/camera.h"
#include "scene/mesh_loader.h"

namespace {

using namespace caustic::bench;

using namespace caustic;

struct Options {
    int repeats = 3;
    std::vector<std::string> meshes = kMeshNames;
    int side = 512;                           // primary rays: side x side pixels, one ray each
    size_t randomRays = 262144;               // random rays
    size_t bruteRays = 16384;                 // at most this many rays per set for bruteforce
    std::vector<std::string> kdtreeVariants;  // kd-trees of other options, beside the default one
};

constexpr std::string_view kVariantPrefix = "kdtree ";

// KdTreeOptions::leafBlock, which renderers before a5fb0cb lack: the A/B scripts build this file
// against older revisions too (ab_common.sh).
template <class Options>
void setLeafBlock(Options& o, uint32_t block) {
    if constexpr (requires { o.leafBlock; })
        o.leafBlock = block;
    else
        throw std::invalid_argument("this renderer's kd-tree has no leafBlock");
}

// The stats' top cells (top_cells.h), or "—" for a revision without them.
template <class Stats>
std::string topCells(const Stats& s) {
    if constexpr (requires { s.topCells; })
        return std::to_string(s.topCells);
    else
        return "—";
}

template <class Options>
void setTopDepth(Options& o, int depth) {
    if constexpr (requires { o.topDepth; })
        o.topDepth = depth;
    else
        throw std::invalid_argument("this renderer's kd-tree has no topDepth");
}

// The options of a variant "key=value[:key=value...]" (keys: depth, traversal, intersect, block,
// bonus, top); throws on anything else.
KdTreeOptions variantOptions(const std::string& spec) {
    KdTreeOptions o;
    std::istringstream in(spec);
    for (std::string item; std::getline(in, item, ':');) {
        const size_t eq = item.find('=');
        const std::string key = item.substr(0, eq);
        const std::string value = eq == std::string::npos ? "" : item.substr(eq + 1);
        size_t used = 0;
        const double v = value.empty() ? 0.0 : std::stod(value, &used);
        if (used == 0 || used != value.size())
            throw std::invalid_argument("kd-tree variant '" + spec + "': '" + item +
                                        "' is not key=number");
        if (key == "depth" && v >= 1 && v <= KdTreeAccel::kMaxDepth && v == std::floor(v))
            o.maxDepth = int(v);
        else if (key == "traversal" && v > 0)
            o.traversalCost = float(v);
        else if (key == "intersect" && v > 0)
            o.intersectCost = float(v);
        else if (key == "block" && v >= 1 && v <= 1024 && std::has_single_bit(uint32_t(v)) &&
                 v == std::floor(v))
            setLeafBlock(o, uint32_t(v));
        else if (key == "bonus" && v >= 0 && v < 1)
            o.emptyBonus = float(v);
        else if (key == "top" && v >= 0 && v <= 6 && v == std::floor(v))
            setTopDepth(o, int(v));
        else
            throw std::invalid_argument(
                "kd-tree variant '" + spec + "': '" + item +
                "' is not depth=1..60, traversal=>0, intersect=>0, block=power of two, "
                "bonus=[0,1) or top=0..6");
    }
    return o;
}

// Parses the command line into `o`; returns -1 to run, else the exit code.
int parseArgs(int argc, char** argv, Options& o) {
    CLI::App app("Build time and rays per second of our SAH kd-tree against Embree on meshes.",
                 "bench_accel_rays");
    bool smoke = false;
    addCommonOptions(app, o.repeats, "Builds and interleaved kdtree / embree timings per measure",
                     smoke, "Teapot only, 64x64 primary rays, 4096 random rays, 1 repeat");
    app.add_option("--meshes", o.meshes, "Meshes, comma-separated")
        ->delimiter(',')
        ->check(CLI::IsMember(kMeshNames))
        ->type_name("LIST")
        ->capture_default_str();
    std::vector<int> depths;
    app.add_option("--kdtree-depths", depths,
                   "Also build kd-trees with these depth limits, comma-separated: the same as "
                   "--kdtree-variants depth=N,...")
        ->delimiter(',')
        ->check(CLI::Range(1, KdTreeAccel::kMaxDepth))
        ->type_name("LIST");
    app.add_option("--kdtree-variants", o.kdtreeVariants,
                   "Also build kd-trees of other KdTreeOptions, comma-separated, each "
                   "key=value[:key=value...] of depth (maxDepth), traversal (traversalCost), "
                   "intersect (intersectCost), block (leafBlock), bonus (emptyBonus), top "
                   "(topDepth); timed in "
                   "the same interleaved rounds: a table gives each one's cost over the default "
                   "kd-tree's")
        ->delimiter(',')
        ->check([](const std::string& spec) {
            try {
                variantOptions(spec);
                return std::string();
            } catch (const std::exception& e) {
                return std::string(e.what());
            }
        })
        ->type_name("LIST");
    if (int exitCode = parseBenchmarkArgs(app, argc, argv); exitCode >= 0) return exitCode;
    for (int depth : depths) o.kdtreeVariants.push_back("depth=" + std::to_string(depth));
    if (smoke) {
        o.repeats = 1;
        o.meshes = {"teapot"};
        o.side = 64;
        o.randomRays = 4096;
    }
    return -1;
}

// Edges used by exactly one triangle: the mesh's holes. Subdivision must only double them.
size_t boundaryEdges(const TriangleMesh& mesh) {
    std::unordered_map<uint64_t, uint32_t> uses;
    uses.reserve(2 * mesh.triangles.size());
    for (const glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = t[k], b = t[(k + 1) % 3];
            ++uses[uint64_t(std::min(a, b)) << 32 | std::max(a, b)];
        }
    return size_t(std::count_if(uses.begin(), uses.end(), [](auto& e) { return e.second == 1; }));
}

// Primary rays: a pinhole camera outside the unit box, looking at its centre; one ray through the
// centre of each pixel, row by row.
std::vector<Ray> primaryRays(int side) {
    const Camera camera(Vec3(1.1f, 0.7f, 1.9f), Vec3(0.0f), Vec3(0.0f, 1.0f, 0.0f), 30.0f, side,
                        side);
    std::vector<Ray> rays;
    rays.reserve(size_t(side) * size_t(side));
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x)
            rays.push_back(camera.generateRay(float(x) + 0.5f, float(y) + 0.5f));
    return rays;
}

// Incoherent rays: origins uniform in the bounds grown by 50% about their centre, directions
// uniform on the sphere. Fixed seed: every run traces the same rays.
std::vector<Ray> randomRays(const Bounds3& bounds, size_t n) {
    std::mt19937 rng(20240607u);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const Vec3 lo = bounds.center() - 0.75f * bounds.diagonal(), size = 1.5f * bounds.diagonal();
    std::vector<Ray> rays(n);
    for (Ray& r : rays) {
        r.o = lo + Vec3(u01(rng), u01(rng), u01(rng)) * size;
        r.d = sampleUniformSphere(Vec2(u01(rng), u01(rng)));
    }
    return rays;
}

// At most `limit` rays of a set, spread over all of it (for bruteforce).
std::vector<Ray> spread(const std::vector<Ray>& rays, size_t limit) {
    size_t stride = std::max<size_t>(1, rays.size() / limit);
    std::vector<Ray> out;
    for (size_t i = 0; i < rays.size() && out.size() < limit; i += stride) out.push_back(rays[i]);
    return out;
}

enum class Query { Closest, Occluded };

// Traces every ray with `threads` threads; returns seconds. `checksum` gets the sum of hit
// distances (closest) or the number of occluded rays, so that the work cannot be optimized away.
double trace(const Accelerator& accel, const std::vector<Ray>& rays, Query query, int threads,
             double& checksum) {
    const ptrdiff_t n = ptrdiff_t(rays.size());
    double sum = 0;
    auto start = std::chrono::steady_clock::now();
    if (query == Query::Closest) {
#pragma omp parallel for schedule(dynamic, 1024) num_threads(threads) reduction(+ : sum)
        for (ptrdiff_t i = 0; i < n; ++i)
            if (std::optional<Hit> h = accel.intersect(rays[size_t(i)], kInfinity)) sum += h->t;
    } else {
#pragma omp parallel for schedule(dynamic, 1024) num_threads(threads) reduction(+ : sum)
        for (ptrdiff_t i = 0; i < n; ++i)
            if (accel.occluded(rays[size_t(i)], kInfinity)) sum += 1.0;
    }
    double seconds = secondsSince(start);
    checksum = sum;
    return seconds;
}

// Hit (1) or miss (0) of each ray: the untimed warm-up pass, kept for the agreement check.
std::vector<uint8_t> hitFlags(const Accelerator& accel, const std::vector<Ray>& rays) {
    std::vector<uint8_t> hit(rays.size());
#pragma omp parallel for schedule(dynamic, 1024)
    for (ptrdiff_t i = 0; i < ptrdiff_t(rays.size()); ++i)
        hit[size_t(i)] = accel.intersect(rays[size_t(i)], kInfinity) ? 1 : 0;
    return hit;
}

double fraction(const std::vector<uint8_t>& a, const std::vector<uint8_t>* b) {
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i) n += b ? a[i] == (*b)[i] : a[i];
    return double(n) / double(a.size());
}

struct RayRow {
    std::string kind;
    Query query;
    int threads;
    std::map<std::string, std::vector<double>> seconds;  // accelerator -> one per repeat
    std::map<std::string, size_t> rays;
    std::map<std::string, double> checksum;
    double raysPerSecond(const std::string& accel) const {
        return double(rays.at(accel)) / median(seconds.at(accel));
    }
    double bestRaysPerSecond(const std::string& accel) const {
        const std::vector<double>& s = seconds.at(accel);
        return double(rays.at(accel)) / *std::min_element(s.begin(), s.end());
    }
};

struct SetAgreement {
    std::string kind;
    size_t rays;
    double kdHits, embreeHits, agree;
};

struct MeshResult {
    std::string name;
    size_t triangles, vertices, holes, geometryBytes;
    std::vector<std::string> accels;
    std::map<std::string, std::vector<double>> buildSeconds;
    std::map<std::string, size_t> memory;
    KdTreeStats kd;
    std::map<std::string, KdTreeStats> variantStats;  // of each kd-tree variant
    std::vector<SetAgreement> agreement;
    std::vector<RayRow> rows;
};

MeshResult runMesh(const std::string& name, const Options& opt, int allThreads) {
    MeshResult r;
    r.name = name;
    TriangleMesh mesh = loadMesh(name);
    Geometry geometry;
    geometry.addTriangles(mesh.positions, mesh.triangles, 0);
    r.triangles = mesh.triangles.size();
    r.vertices = mesh.positions.size();
    r.holes = boundaryEdges(mesh);
    r.geometryBytes = geometry.memoryBytes();
    r.accels = {"kdtree", "embree"};
    if (name == "teapot") r.accels.push_back("bruteforce");
    for (const std::string& spec : opt.kdtreeVariants)
        r.accels.push_back(std::string(kVariantPrefix) + spec);

    // Build each accelerator --repeats times, interleaved; keep the last of each.
    std::map<std::string, std::unique_ptr<Accelerator>> accel;
    for (int rep = 0; rep < opt.repeats; ++rep)
        for (const std::string& a : r.accels) {
            accel[a].reset();
            auto start = std::chrono::steady_clock::now();
            accel[a] = a.starts_with(kVariantPrefix)
                           ? std::make_unique<KdTreeAccel>(
                                 geometry, variantOptions(a.substr(kVariantPrefix.size())))
                           : createAccelerator(a, geometry);
            r.buildSeconds[a].push_back(secondsSince(start));
        }
    for (const std::string& a : r.accels) r.memory[a] = accel[a]->memoryBytes();
    r.kd = dynamic_cast<const KdTreeAccel&>(*accel["kdtree"]).stats();
    for (const std::string& spec : opt.kdtreeVariants) {
        const std::string a = std::string(kVariantPrefix) + spec;
        r.variantStats[a] = dynamic_cast<const KdTreeAccel&>(*accel[a]).stats();
    }

    const std::vector<std::pair<std::string, std::vector<Ray>>> sets = {
        {"primary", primaryRays(opt.side)},
        {"random", randomRays(geometry.bounds(), opt.randomRays)}};
    for (const auto& [kind, rays] : sets) {
        // Warm up (untimed) and check that kdtree and embree agree on hit or miss.
        std::vector<uint8_t> kdHit = hitFlags(*accel["kdtree"], rays);
        std::vector<uint8_t> emHit = hitFlags(*accel["embree"], rays);
        r.agreement.push_back({kind, rays.size(), fraction(kdHit, nullptr),
                               fraction(emHit, nullptr), fraction(kdHit, &emHit)});
        const std::vector<Ray> few = spread(rays, opt.bruteRays);
        for (Query query : {Query::Closest, Query::Occluded})
            for (int threads : {1, allThreads}) {
                RayRow row{kind, query, threads, {}, {}, {}};
                for (int rep = 0; rep < opt.repeats; ++rep)
                    for (const std::string& a : r.accels) {
                        const std::vector<Ray>& set = a == "bruteforce" ? few : rays;
                        row.seconds[a].push_back(
                            trace(*accel[a], set, query, threads, row.checksum[a]));
                        row.rays[a] = set.size();
                    }
                r.rows.push_back(std::move(row));
            }
    }
    return r;
}

std::string ratioCell(double ratio) {
    return fmt("%.2f×", ratio);
}

void printTables(const std::vector<MeshResult>& results, const Options& opt, int allThreads) {
    const std::string reps = std::to_string(opt.repeats);
    std::cout << "### Meshes (each normalized to fit a unit box)\n\n"
              << "| mesh | triangles | vertices | boundary edges | Geometry MB "
                 "|\n|---|---:|---:|---:|---:|\n";
    for (const MeshResult& r : results)
        std::cout << "| " << r.name << " | " << r.triangles << " | " << r.vertices << " | "
                  << r.holes << " | " << fmt("%.2f", double(r.geometryBytes) / (1024.0 * 1024.0))
                  << " |\n";

    std::cout << "\n### Summary: kdtree cost relative to embree (> 1: kdtree slower)\n\n"
              << "Build: kdtree seconds / embree seconds. Rays: embree rays/s / kdtree rays/s. "
              << "1T = 1 thread, " << allThreads << "T = all threads.\n\n"
              << "| mesh | build |";
    for (const char* kind : {"primary", "random"})
        for (const char* query : {"closest", "occluded"})
            for (int t : {1, allThreads})
                std::cout << " " << kind << " " << query << " " << t << "T |";
    std::cout << "\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const MeshResult& r : results) {
        std::cout << "| " << r.name << " | "
                  << ratioCell(median(r.buildSeconds.at("kdtree")) /
                               median(r.buildSeconds.at("embree")))
                  << " |";
        for (const RayRow& row : r.rows)
            std::cout << " " << ratioCell(row.raysPerSecond("embree") / row.raysPerSecond("kdtree"))
                      << " |";
        std::cout << "\n";
    }

    std::cout << "\n### Build (all threads: both builders are parallel), median of " << reps
              << " interleaved builds\n\n"
              << "| mesh | accelerator | build ms | min ms | memoryBytes MB | bytes / triangle |\n"
              << "|---|---|---:|---:|---:|---:|\n";
    for (const MeshResult& r : results)
        for (const std::string& a : r.accels) {
            const std::vector<double>& s = r.buildSeconds.at(a);
            double mb = double(r.memory.at(a)) / (1024.0 * 1024.0);
            std::cout << "| " << r.name << " | " << a << " | " << fmt("%.2f", 1e3 * median(s))
                      << " | " << fmt("%.2f", 1e3 * *std::min_element(s.begin(), s.end())) << " | "
                      << fmt("%.2f", mb) << " | "
                      << fmt("%.1f", double(r.memory.at(a)) / double(r.triangles)) << " |\n";
        }
    std::cout << "\nmemoryBytes: what the accelerator holds beyond the Geometry. Embree's is what "
                 "its device's memory monitor reports (BVH and vertex buffers).\n";

    std::cout
        << "\n### kdtree structure\n\n"
        << "| mesh | nodes | interior | leaves | empty leaves | max depth | references / "
           "triangle | SAH cost | top cells |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const MeshResult& r : results)
        std::cout << "| " << r.name << " | " << r.kd.interiorNodes + r.kd.leaves << " | "
                  << r.kd.interiorNodes << " | " << r.kd.leaves << " | " << r.kd.emptyLeaves
                  << " | " << r.kd.maxDepth << " | "
                  << fmt("%.2f", double(r.kd.references) / double(r.triangles)) << " | "
                  << fmt("%.2f", r.kd.sahCost) << " | " << topCells(r.kd) << " |\n";

    std::cout << "\n### Rays per second (millions), median of " << reps
              << " interleaved runs; closest = intersect, occluded = occluded(tMax = inf)\n\n"
              << "| mesh | rays | query | threads | rays traced | kdtree | embree | bruteforce "
                 "| embree / kdtree | same, of mins "
                 "|\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const MeshResult& r : results)
        for (const RayRow& row : r.rows) {
            double kd = row.raysPerSecond("kdtree"), em = row.raysPerSecond("embree");
            std::cout << "| " << r.name << " | " << row.kind << " | "
                      << (row.query == Query::Closest ? "closest" : "occluded") << " | "
                      << row.threads << " | " << row.rays.at("kdtree") << " | "
                      << fmt("%.3f", kd / 1e6) << " | " << fmt("%.3f", em / 1e6) << " | "
                      << (row.rays.count("bruteforce")
                              ? fmt("%.4f", row.raysPerSecond("bruteforce") / 1e6) + " (" +
                                    std::to_string(row.rays.at("bruteforce")) + " rays)"
                              : "—")
                      << " | " << ratioCell(em / kd) << " | "
                      << ratioCell(row.bestRaysPerSecond("embree") /
                                   row.bestRaysPerSecond("kdtree"))
                      << " |\n";
        }

    if (!opt.kdtreeVariants.empty()) {
        std::cout
            << "\n### kd-tree variants: cost relative to the default kd-tree (> 1: "
               "slower), medians of the same interleaved rounds\n\n"
            << "| mesh | kd-tree | nodes | empty leaves | references / triangle | MB | build |";
        for (const RayRow& row : results.front().rows)
            std::cout << " " << row.kind << " "
                      << (row.query == Query::Closest ? "closest" : "occluded") << " "
                      << row.threads << "T |";
        std::cout
            << "\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (const MeshResult& r : results)
            for (const std::string& spec : opt.kdtreeVariants) {
                const std::string a = std::string(kVariantPrefix) + spec;
                const KdTreeStats& s = r.variantStats.at(a);
                std::cout << "| " << r.name << " | " << a << " | " << s.interiorNodes + s.leaves
                          << " | " << s.emptyLeaves << " | "
                          << fmt("%.2f", double(s.references) / double(r.triangles)) << " | "
                          << fmt("%.2f", double(r.memory.at(a)) / (1024.0 * 1024.0)) << " | "
                          << ratioCell(median(r.buildSeconds.at(a)) /
                                       median(r.buildSeconds.at("kdtree")))
                          << " |";
                for (const RayRow& row : r.rows)
                    std::cout << " "
                              << ratioCell(row.raysPerSecond("kdtree") / row.raysPerSecond(a))
                              << " |";
                std::cout << "\n";
            }
    }

    std::cout << "\n### Sanity: hit or miss per ray, kdtree against embree (primary must agree on "
                 ">= 99.9%)\n\n| mesh | rays | count | kdtree hits | embree hits | agreement |\n"
                 "|---|---|---:|---:|---:|---:|\n";
    for (const MeshResult& r : results)
        for (const SetAgreement& a : r.agreement)
            std::cout << "| " << r.name << " | " << a.kind << " | " << a.rays << " | "
                      << fmt("%.2f%%", 100 * a.kdHits) << " | " << fmt("%.2f%%", 100 * a.embreeHits)
                      << " | " << fmt("%.4f%%", 100 * a.agree)
                      << (a.kind == "primary" && a.agree < 0.999 ? " **below 99.9%**" : "")
                      << " |\n";
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    if (int exitCode = parseArgs(argc, argv, opt); exitCode >= 0) return exitCode;
    const int allThreads = omp_get_max_threads();

    std::vector<MeshResult> results;
    try {
        for (const std::string& name : opt.meshes) {
            results.push_back(runMesh(name, opt, allThreads));
            std::cerr << "done " << name << "\n";
        }
    } catch (const std::exception& e) {
        std::cerr << "bench_accel_rays: " << e.what() << "\n";
        return 1;
    }
    printTables(results, opt, allThreads);
    for (const MeshResult& r : results)
        if (r.agreement.front().agree < 0.999) return 1;
    return 0;
}
