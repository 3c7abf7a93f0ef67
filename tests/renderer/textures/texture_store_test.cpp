// The texture store: decoding (sRGB for colour, linear for data), lookups and their filters, the
// bounded cache with an image larger than it, and bad images.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "support/temp_dir.h"
#include "support/texture_images.h"
#include "textures/texture_store.h"

namespace caustic {
namespace {

TextureStore::Options storeIn(const testing::TempDir& dir, size_t cacheBytes = size_t(64) << 20) {
    TextureStore::Options o;
    o.directory = dir.path() / "prepared";
    o.cacheBytes = cacheBytes;
    return o;
}

// A lookup at the centre of texel (x, y) of a size x size image, with no footprint.
TextureQuery texelCentre(int x, int y, int size) {
    TextureQuery q;
    q.st = Vec2((float(x) + 0.5f) / float(size), (float(y) + 0.5f) / float(size));
    return q;
}

TEST(TextureStore, DecodesSrgbColourAndKeepsDataLinear) {
    testing::TempDir dir;
    // 8-bit 188: sRGB 0.7373 -> linear 0.5029 (IEC 61966-2-1).
    testing::writeTextureImage(dir.path() / "grey.png", 4, 4, 3,
                               [](int, int, int) { return 188.0f / 255.0f; });
    TextureStore store(storeIn(dir));
    const auto& colour = store.addFile(dir.path() / "grey.png", TextureEncoding::Srgb, "/c");
    const auto& data = store.addFile(dir.path() / "grey.png", TextureEncoding::Linear, "/d");
    EXPECT_NE(&colour, &data);
    EXPECT_EQ(&store.addFile(dir.path() / "grey.png", TextureEncoding::Srgb, "/c"), &colour);
    float c[3], d[3];
    store.lookup(colour, texelCentre(1, 1, 4), TextureFilter::Anisotropic, 0, 3, c);
    store.lookup(data, texelCentre(1, 1, 4), TextureFilter::Anisotropic, 0, 3, d);
    const float srgb = 188.0f / 255.0f;
    const float linear = std::pow((srgb + 0.055f) / 1.055f, 2.4f);
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(c[i], linear, 1e-3f);  // half floats: 11 bits
        EXPECT_NEAR(d[i], srgb, 1e-3f);
    }
}

TEST(TextureStore, ChannelsPastTheImagesAreZeroAndAlphaOne) {
    testing::TempDir dir;
    testing::writeTextureImage(dir.path() / "one.exr", 2, 2, 1,
                               [](int, int, int) { return 0.25f; });
    TextureStore store(storeIn(dir));
    const auto& image = store.addFile(dir.path() / "one.exr", TextureEncoding::Srgb, "/t");
    EXPECT_EQ(image.channels, 1);
    float v[4];
    store.lookup(image, texelCentre(0, 0, 2), TextureFilter::Nearest, 0, 4, v);
    EXPECT_FLOAT_EQ(v[0], 0.25f);  // float images are linear already
    EXPECT_EQ(v[1], 0.0f);
    EXPECT_EQ(v[2], 0.0f);
    EXPECT_EQ(v[3], 1.0f);
}

TEST(TextureStore, NearestReadsOneTexelAndAFootprintAveragesMany) {
    testing::TempDir dir;
    testing::writeChecker(dir.path() / "checker.png", 256, 128);  // 2-texel squares
    TextureStore store(storeIn(dir));
    const auto& image = store.addFile(dir.path() / "checker.png", TextureEncoding::Linear, "/t");
    TextureQuery q = texelCentre(0, 0, 256);
    q.dstdx = Vec2(32.0f / 256.0f, 0.0f);  // a footprint of 32 x 32 texels
    q.dstdy = Vec2(0.0f, 32.0f / 256.0f);
    float nearest, filtered, trilinear;
    store.lookup(image, q, TextureFilter::Nearest, 0, 1, &nearest);
    store.lookup(image, q, TextureFilter::Anisotropic, 0, 1, &filtered);
    store.lookup(image, q, TextureFilter::Trilinear, 0, 1, &trilinear);
    EXPECT_EQ(nearest, 0.0f);
    EXPECT_NEAR(filtered, 0.5f, 0.02f);
    EXPECT_NEAR(trilinear, 0.5f, 0.02f);
}

// An image of 2048 x 2048 RGBA half floats holds 32 MiB (43 MiB with its MIP levels) against a
// cache of 4 MiB: every texel is still read right, tiles are read again as they are evicted,
// and the cache stays within its bound.
TEST(TextureStore, AnImageLargerThanTheCacheIsReadRightThroughIt) {
    testing::TempDir dir;
    constexpr int kSize = 2048;
    auto value = [](int x, int y, int c) { return float((x * 7 + y * 13 + c * 29) % 64) / 64.0f; };
    testing::writeTextureImage(dir.path() / "large.exr", kSize, kSize, 4, value);
    const size_t cache = size_t(4) << 20;
    TextureStore store(storeIn(dir, cache));
    const auto& image = store.addFile(dir.path() / "large.exr", TextureEncoding::Linear, "/t");
    int wrong = 0;
    // Two sweeps over the whole image, in rows of 64-texel steps: the second finds the first's
    // tiles evicted.
    for (int sweep = 0; sweep < 2; ++sweep)
        for (int y = 3; y < kSize; y += 61)
            for (int x = 5; x < kSize; x += 37) {
                float v[4];
                store.lookup(image, texelCentre(x, y, kSize), TextureFilter::Nearest, 0, 4, v);
                for (int c = 0; c < 4; ++c) wrong += std::abs(v[c] - value(x, y, c)) > 1e-3f;
            }
    EXPECT_EQ(wrong, 0);
    const TextureStore::Stats stats = store.stats();
    std::printf(
        "cache %zu bytes: %d tiles read, at most %d held, %lld bytes held at the end, "
        "%lld bytes read\n",
        cache, stats.tilesCreated, stats.tilesPeak, static_cast<long long>(stats.memoryUsed),
        static_cast<long long>(stats.bytesRead));
    EXPECT_GT(stats.tilesCreated, stats.tilesPeak);  // tiles were evicted and read again
    EXPECT_GT(stats.bytesRead, int64_t(32) << 20);   // more than the whole image, read twice
    // OIIO frees tiles once the bound is passed: a tile's worth over it at most.
    EXPECT_LE(stats.memoryUsed, int64_t(cache) + (int64_t(64) * 64 * 4 * 2));
}

void expectBadImage(const testing::TempDir& dir, const std::string& bytes, const std::string& name,
                    const std::string& what, int64_t maxPixels = int64_t(1) << 30) {
    TextureStore::Options o = storeIn(dir);
    o.maxPixels = maxPixels;
    TextureStore store(o);
    try {
        store.add(bytes, TextureEncoding::Srgb, name, "/materials/m/base_color_texture");
        FAIL() << "no error for " << name;
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), "/materials/m/base_color_texture");
        EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
    }
}

std::string fileBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(TextureStore, BadImagesAreErrorsAtTheirPath) {
    testing::TempDir dir;
    expectBadImage(dir, "not an image at all", "garbage.png", "cannot read image garbage.png");
    expectBadImage(dir, "", "empty.png", "cannot read image empty.png");
    testing::writeTextureImage(dir.path() / "nan.exr", 4, 4, 3, [](int x, int y, int) {
        return x == 2 && y == 1 ? std::nanf("") : 0.5f;
    });
    expectBadImage(dir, fileBytes(dir.path() / "nan.exr"), "nan.exr",
                   "texel (2, 1) is negative or not finite");
    testing::writeTextureImage(dir.path() / "big.png", 64, 64, 3,
                               [](int, int, int) { return 1.0f; });
    expectBadImage(dir, fileBytes(dir.path() / "big.png"), "big.png",
                   "is 64 x 64 pixels, over the limit of 1000", 1000);
    testing::writeTextureImage(dir.path() / "five.exr", 2, 2, 5,
                               [](int, int, int) { return 1.0f; });
    expectBadImage(dir, fileBytes(dir.path() / "five.exr"), "five.exr",
                   "has 5 channels; a texture has 1 to 4");
}

}  // namespace
}  // namespace caustic
