// The kd-tree's build alone, against Embree's build of the same mesh in the same process: many
// builds, interleaved (kdtree, embree, kdtree, ...), the fastest and the median of each. It is
// small and uses only the accelerators' public interface, so that bench/kdtree_build_ab.sh can
// compile this same file against two revisions of the renderer and run them in alternation: the
// way to measure a change to the build on a machine too noisy for one run to tell.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "accel/kdtree/kdtree.h"
#include "bench_common.h"
#include "bench_meshes.h"

namespace {

using namespace caustic;
using namespace caustic::bench;

struct Options {
    int builds = 20;
    std::vector<std::string> meshes = {"bunny", "teapot"};
    bool embree = true;
    bool tsv = false;
};

struct Row {
    std::string mesh;
    double kdMin, kdMedian, embreeMin = 0, embreeMedian = 0;
    KdTreeStats stats;
    size_t triangles;
};

Row measure(const std::string& name, const Options& opt) {
    const TriangleMesh mesh = loadMesh(name);
    Geometry geometry;
    geometry.addTriangles(mesh.positions, mesh.triangles, 0);
    std::vector<double> kd, embree;
    Row row{name, 0, 0, 0, 0, {}, mesh.triangles.size()};
    for (int b = 0; b < opt.builds; ++b) {
        auto start = std::chrono::steady_clock::now();
        {
            const KdTreeAccel tree(geometry);
            kd.push_back(secondsSince(start));
            row.stats = tree.stats();
        }
        if (opt.embree) {
            start = std::chrono::steady_clock::now();
            const std::unique_ptr<Accelerator> accel = createAccelerator("embree", geometry);
            embree.push_back(secondsSince(start));
        }
    }
    row.kdMin = *std::min_element(kd.begin(), kd.end()) * 1e3;
    row.kdMedian = median(kd) * 1e3;
    if (opt.embree) {
        row.embreeMin = *std::min_element(embree.begin(), embree.end()) * 1e3;
        row.embreeMedian = median(embree) * 1e3;
    }
    return row;
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    CLI::App app("Build time of our SAH kd-tree (and of Embree's BVH, interleaved) on meshes.",
                 "bench_kdtree_build");
    bool smoke = false;
    addCommonOptions(app, opt.builds, "Builds of each accelerator per mesh", smoke,
                     "Teapot only, 2 builds");
    app.add_option("--meshes", opt.meshes, "Meshes, comma-separated")
        ->delimiter(',')
        ->check(CLI::IsMember(kMeshNames))
        ->type_name("LIST")
        ->capture_default_str();
    app.add_flag("!--no-embree", opt.embree, "Build only the kd-tree");
    app.add_flag("--tsv", opt.tsv,
                 "One tab-separated line per mesh (mesh, kd-tree min and median ms, Embree min "
                 "and median ms, interior nodes, references, SAH cost) and nothing else");
    if (int exitCode = cli::parseCommandLine(app, argc, argv); exitCode >= 0) return exitCode;
    if (smoke) {
        opt.builds = 2;
        opt.meshes = {"teapot"};
    }
    if (!opt.tsv) {
        printMachine(argc, argv);
        std::cout << "| mesh | triangles | kd-tree min ms | kd-tree median ms | Embree min ms | "
                     "Embree median ms | median ratio | interior nodes | references / triangle "
                     "| SAH cost |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    }
    for (const std::string& name : opt.meshes) {
        const Row r = measure(name, opt);
        const double refsPerTriangle = double(r.stats.references) / double(r.triangles);
        if (opt.tsv) {
            std::printf("%s\t%.3f\t%.3f\t%.3f\t%.3f\t%u\t%llu\t%.4f\n", r.mesh.c_str(), r.kdMin,
                        r.kdMedian, r.embreeMin, r.embreeMedian, r.stats.interiorNodes,
                        static_cast<unsigned long long>(r.stats.references), r.stats.sahCost);
            continue;
        }
        std::cout << "| " << r.mesh << " | " << r.triangles << " | " << fmt("%.2f", r.kdMin)
                  << " | " << fmt("%.2f", r.kdMedian) << " | "
                  << (opt.embree ? fmt("%.2f", r.embreeMin) : "—") << " | "
                  << (opt.embree ? fmt("%.2f", r.embreeMedian) : "—") << " | "
                  << (opt.embree ? fmt("%.2f×", r.kdMedian / r.embreeMedian) : "—") << " | "
                  << r.stats.interiorNodes << " | " << fmt("%.2f", refsPerTriangle) << " | "
                  << fmt("%.2f", r.stats.sahCost) << " |\n";
    }
    return 0;
}
