// Long reference renders for error measurements, cached on disk (bench_equal_time, bench_study),
// and the sums that compare an image with one.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "render/renderer.h"

namespace caustic::bench {

// FNV-1a, 64-bit, continued from `h`.
inline uint64_t fnv1a(const std::string& bytes, uint64_t h = 1469598103934665603ull) {
    for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
    return h;
}

inline std::string fileBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// The reference image: its mean and its per-pixel standard error (interleaved RGB).
struct Reference {
    std::vector<float> mean, se;
    int passes = 0;
    double seconds = 0;
};

inline bool loadReference(const std::filesystem::path& file, size_t values, Reference& ref) {
    std::ifstream in(file, std::ios::binary);
    uint64_t n = 0;
    if (!in.read(reinterpret_cast<char*>(&n), sizeof(n)) || n != values) return false;
    ref.mean.resize(values);
    ref.se.resize(values);
    in.read(reinterpret_cast<char*>(&ref.passes), sizeof(ref.passes));
    in.read(reinterpret_cast<char*>(&ref.seconds), sizeof(ref.seconds));
    in.read(reinterpret_cast<char*>(ref.mean.data()), std::streamsize(values * sizeof(float)));
    in.read(reinterpret_cast<char*>(ref.se.data()), std::streamsize(values * sizeof(float)));
    return bool(in);
}

inline void saveReference(const std::filesystem::path& file, const Reference& ref) {
    std::filesystem::create_directories(file.parent_path());
    std::ofstream out(file.string() + ".tmp", std::ios::binary);
    uint64_t n = ref.mean.size();
    out.write(reinterpret_cast<const char*>(&n), sizeof(n));
    out.write(reinterpret_cast<const char*>(&ref.passes), sizeof(ref.passes));
    out.write(reinterpret_cast<const char*>(&ref.seconds), sizeof(ref.seconds));
    out.write(reinterpret_cast<const char*>(ref.mean.data()), std::streamsize(n * sizeof(float)));
    out.write(reinterpret_cast<const char*>(ref.se.data()), std::streamsize(n * sizeof(float)));
    out.close();
    std::filesystem::rename(file.string() + ".tmp", file);
}

/// The reference render of `scene` (whose JSON is `doc`) with `settings`: from the cache in `dir`,
/// else rendered (progress on stderr) and saved there. The file's name carries the image size,
/// spp, seed and a hash of the settings, the scene and the renderer library (`library`, the
/// static library's path), so that any change to them renders it anew.
inline Reference cachedReference(const caustic::Scene& scene, const nlohmann::json& doc,
                                 const caustic::RenderSettings& settings,
                                 const std::filesystem::path& dir, const char* library,
                                 std::filesystem::path* fileOut = nullptr) {
    const uint64_t key =
        fnv1a(settings.toJson().dump(), fnv1a(doc.dump(), fnv1a(fileBytes(library))));
    const int width = scene.camera.width(), height = scene.camera.height();
    char name[160];
    std::snprintf(name, sizeof(name), "ref-%dx%d-%dspp-seed%llu-%016llx.bin", width, height,
                  settings.spp, (unsigned long long)settings.seed, (unsigned long long)key);
    const std::filesystem::path file = dir / name;
    if (fileOut) *fileOut = file;
    Reference ref;
    if (loadReference(file, size_t(width) * size_t(height) * 3, ref)) return ref;

    std::cerr << "rendering the reference (" << settings.spp << " spp) into " << file << "\n";
    caustic::RenderCallbacks progress;
    progress.onPass = [](const caustic::Film& f) {
        if (f.passes() % 8 == 0) std::cerr << "  reference: " << f.passes() << " passes\n";
    };
    caustic::RenderResult r = caustic::render(scene, settings, progress);
    ref.mean = r.film->meanRgb();
    ref.se = r.film->standardErrorRgb();
    ref.passes = r.stats.passes;
    ref.seconds = r.stats.totalSeconds;
    saveReference(file, ref);
    return ref;
}

// Sums over pixels and channels of one image against the reference.
struct Sums {
    double sqErr = 0, runVar = 0, refVar = 0, refSq = 0, img = 0, ref = 0;
    size_t n = 0;
    void add(double v, double runSe, double r, double refSe) {
        sqErr += (v - r) * (v - r);
        runVar += runSe * runSe;
        refVar += refSe * refSe;
        refSq += r * r;
        img += v;
        ref += r;
        ++n;
    }
    double rmse() const { return std::sqrt(sqErr / double(n)); }
    // The reference's noise adds to the expected squared error: without it, what the RMSE
    // against the true image would be.
    double rmseLessReference() const {
        return std::sqrt(std::max(0.0, sqErr - refVar) / double(n));
    }
    double relativeLessReference() const {
        return std::sqrt(std::max(0.0, sqErr - refVar) / refSq);
    }
    // The run's own noise (RMS standard error of its passes) and what the error leaves beyond
    // both images' noise: E[(v - r)^2] = bias^2 + var(v) + var(r).
    double noise() const { return std::sqrt(runVar / double(n)); }
    double relativeNoise() const { return std::sqrt(runVar / refSq); }
    double bias() const { return std::sqrt(std::max(0.0, sqErr - runVar - refVar) / double(n)); }
};

}  // namespace caustic::bench
