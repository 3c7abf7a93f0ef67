#include "film/film.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <string>

#include "film/image_io.h"

namespace caustic {

TEST(Film, MeanAndStandardErrorOfPasses) {
    Film film(2, 1);
    // Pixel 0 sees 1, 2, 3, 6: mean 3, sample variance (4+1+0+9)/3 = 14/3, standard error
    // sqrt(14/3/4).
    for (float v : {1.0f, 2.0f, 3.0f, 6.0f}) film.addPass({Color(v, 2 * v, 0), Color(5)});
    EXPECT_EQ(film.passes(), 4);
    EXPECT_FLOAT_EQ(film.mean(0, 0).r, 3.0f);
    EXPECT_FLOAT_EQ(film.mean(0, 0).g, 6.0f);
    EXPECT_FLOAT_EQ(film.standardError(0, 0).r, std::sqrt(14.0f / 3.0f / 4.0f));
    EXPECT_FLOAT_EQ(film.standardError(0, 0).g, 2.0f * std::sqrt(14.0f / 3.0f / 4.0f));
    EXPECT_EQ(film.standardError(1, 0), Color(0.0f));
    EXPECT_EQ(film.mean(1, 0), Color(5.0f));
}

TEST(Film, RelativeErrorIsUndefinedBeforeTwoPasses) {
    Film film(1, 1);
    EXPECT_TRUE(std::isnan(film.relativeError()));
    film.addPass({Color(1)});
    EXPECT_TRUE(std::isnan(film.relativeError()));
    film.addPass({Color(3)});
    // mean 2, se = sqrt(2/2) = 1 per channel: sqrt(3 * 1 / (3 * 4)) = 0.5.
    EXPECT_DOUBLE_EQ(film.relativeError(), 0.5);
}

TEST(Film, MergeEqualsAddingThePassesInOneFilm) {
    Film all(3, 2), a(3, 2), b(3, 2);
    for (int p = 0; p < 6; ++p) {
        std::vector<Color> pass(6);
        for (int i = 0; i < 6; ++i)
            pass[size_t(i)] = Color(float(p * i), float(p + i), 1.0f / float(p + 1));
        uint64_t dropped = p == 0 ? 2 : (p == 5 ? 3 : 0);
        all.addPass(p, pass, dropped);
        (p < 4 ? a : b).addPass(p, pass, dropped);
    }
    a.merge(b);
    EXPECT_EQ(a.passes(), 6);
    EXPECT_EQ(a.droppedSamples(), 5u);
    EXPECT_EQ(a.sums(), all.sums());
    EXPECT_EQ(a.sumsOfSquares(), all.sumsOfSquares());
    EXPECT_TRUE(a == all);
}

TEST(Film, BytesReproduceTheFilm) {
    Film film(2, 2);
    film.addPass(0, std::vector<Color>(4, Color(1, 2, 3)), 3);
    film.addPass(1, std::vector<Color>(4, Color(3, 2, 1)), 4);
    std::string bytes = film.toBytes();
    std::unique_ptr<Film> copy = Film::fromBytes(bytes, 2, 2);
    ASSERT_TRUE(copy);
    EXPECT_TRUE(*copy == film);
    EXPECT_EQ(copy->meanRgb(), film.meanRgb());
    EXPECT_EQ(copy->relativeError(), film.relativeError());
    EXPECT_EQ(copy->droppedSamples(), 7u);
    EXPECT_EQ(copy->passSet().toString(), "0-1");
    // Torn, foreign or mis-sized bytes are no film.
    EXPECT_FALSE(Film::fromBytes(bytes.substr(0, bytes.size() - 1), 2, 2));
    EXPECT_FALSE(Film::fromBytes(bytes + "x", 2, 2));
    EXPECT_FALSE(Film::fromBytes(bytes, 2, 3));
    EXPECT_FALSE(Film::fromBytes("CAUSTIC1", 2, 2));
    EXPECT_FALSE(Film::fromBytes("", 2, 2));
}

TEST(Film, TheBiasLayerAddsTheBiasToTheError) {
    // One pixel, passes 1 and 3 (mean 2, noise^2 = se^2 = 1 a channel), each estimating its bias
    // as 1: the bias layer's mean is 1 with no spread, so bias^2 = 1 a channel and the error is
    // sqrt((1 + 1) / 4).
    Film film(1, 1, true);
    EXPECT_TRUE(film.tracksBias());
    EXPECT_EQ(film.passPixels(), 2u);
    EXPECT_THROW(film.addPass({Color(1)}), std::invalid_argument);  // no bias half
    film.addPass({Color(1), Color(1)});
    film.addPass({Color(3), Color(1)});
    EXPECT_EQ(film.mean(0, 0), Color(2));
    EXPECT_EQ(film.bias(0, 0), Color(1));
    EXPECT_EQ(film.meanRgb(), std::vector<float>(3, 2.0f));
    EXPECT_EQ(film.biasRgb(), std::vector<float>(3, 1.0f));
    EXPECT_DOUBLE_EQ(film.relativeNoise(), 0.5);
    EXPECT_DOUBLE_EQ(film.relativeBias(), 0.5);
    EXPECT_DOUBLE_EQ(film.relativeError(), std::sqrt(0.5));
    // A bias estimate that is noise alone counts for nothing once its own noise is taken out:
    // +-1 about 0 has mean 0, so 0 - se^2 < 0 comes out as no bias.
    Film noisy(1, 1, true);
    noisy.addPass({Color(1), Color(1)});
    noisy.addPass({Color(3), Color(-1)});
    EXPECT_DOUBLE_EQ(noisy.relativeBias(), 0.0);
    EXPECT_DOUBLE_EQ(noisy.relativeError(), 0.5);
    // The layer travels with the film, and only films alike merge.
    std::unique_ptr<Film> copy = Film::fromBytes(film.toBytes(), 1, 1);
    ASSERT_TRUE(copy);
    EXPECT_TRUE(*copy == film);
    EXPECT_TRUE(copy->tracksBias());
    EXPECT_EQ(copy->relativeError(), film.relativeError());
    Film plain(1, 1);
    plain.addPass(5, {Color(1)});
    EXPECT_THROW(film.merge(plain), std::invalid_argument);
    EXPECT_THROW(plain.addPass(6, {Color(1), Color(1)}), std::invalid_argument);
    EXPECT_FALSE(Film::fromBytes(plain.toBytes(), 1, 1)->tracksBias());
    EXPECT_EQ(Film::bytesFor(4, 4, true), 2 * Film::bytesFor(4, 4));
}

// decode(encode(f)) == f for the values that test each part of the encoding: zero, the smallest
// quantum, negative sums (zigzag), values at the clamp (sums near 2^105 over many passes, squares
// beyond 128 bits), NaN and infinities (counted, stored as 0 or clamped).
TEST(Film, BytesAreExactAtTheExtremes) {
    const int w = 7, h = 5;
    Film film(w, h);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const float special[] = {0.0f,
                             0x1p-60f,
                             -0x1p-60f,
                             0x1p-27f,
                             -3.5f,
                             1e-20f,
                             0x1.fffffep34f,
                             -0x1.fffffep34f,
                             1e30f,
                             -std::numeric_limits<float>::infinity(),
                             std::numeric_limits<float>::quiet_NaN(),
                             1234.5f,
                             0x1p13f};
    for (int pass = 0; pass < 40; ++pass) {
        std::vector<Color> image(size_t(w) * h);
        for (size_t i = 0; i < image.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                const size_t k = (i * 3 + size_t(c) + size_t(pass)) % (std::size(special) + 3);
                image[i][c] =
                    k < std::size(special) ? special[k] : u(rng) * std::pow(10.0f, 4 * u(rng));
            }
        film.addPass(pass * 3, image, uint64_t(pass));
    }
    const std::string bytes = film.toBytes();
    std::unique_ptr<Film> copy = Film::fromBytes(bytes, w, h);
    ASSERT_TRUE(copy);
    EXPECT_TRUE(*copy == film);
    EXPECT_EQ(copy->passSet().toString(), film.passSet().toString());
    EXPECT_EQ(copy->clampedValues(), film.clampedValues());
    // A damaged film is refused, never read as another: the accumulators are compressed with a
    // checksum. A bit flipped past the ranges gives no film, or (a flag zstd ignores) the same
    // one; flipped in the header or ranges, another film or none, never a crash.
    const size_t frame = 40 + 8 * film.passSet().ranges().size() + 8;
    int refused = 0;
    for (size_t at = 0; at < bytes.size(); ++at) {
        std::string torn = bytes;
        torn[at] = char(torn[at] ^ 0x10);
        std::unique_ptr<Film> other = Film::fromBytes(torn, w, h);
        if (!other) ++refused;
        if (other && at >= frame) {
            EXPECT_TRUE(*other == film) << "byte " << at;
        }
    }
    EXPECT_GT(refused, int(bytes.size() - frame) * 9 / 10);
}

// A rendered-like film (smooth values with noise, a few fireflies) takes well under the memory's
// 120 bytes a pixel.
TEST(Film, BytesAreCompact) {
    const int w = 64, h = 64;
    Film film(w, h);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int pass = 0; pass < 8; ++pass) {
        std::vector<Color> image(size_t(w) * h);
        for (Color& c : image)
            for (int k = 0; k < 3; ++k)
                c[k] = u(rng) < 0.01f ? 100.0f * u(rng) : 0.5f * u(rng) * u(rng);
        film.addPass(pass, image);
    }
    const std::string bytes = film.toBytes();
    EXPECT_LT(bytes.size(), film.memoryBytes() / 2) << bytes.size() << " bytes";
    ASSERT_TRUE(Film::fromBytes(bytes, w, h));
    EXPECT_TRUE(*Film::fromBytes(bytes, w, h) == film);
}

TEST(ImageIo, ExrRoundTripIsExactAndPngIsSrgbEncoded) {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("caustic-film-test-" + std::to_string(getpid()));
    fs::create_directories(dir);
    RgbImage image{3, 1, {0.0f, 0.5f, 1.0f, 0.0031308f, 0.18f, 4.0f, 1e-3f, 0.25f, 0.75f}};
    writeImage(dir / "a.exr", image);
    EXPECT_EQ(readImage(dir / "a.exr").pixels, image.pixels);
    EXPECT_FALSE(fs::exists(dir / "a.exr.tmp"));

    writeImage(dir / "a.png", image, /*exposure=*/1.0);
    RgbImage png = readImage(dir / "a.png");
    ASSERT_EQ(png.pixels.size(), image.pixels.size());
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        float expected = std::round(255.0f * srgbEncode(2.0f * image.pixels[i])) / 255.0f;
        EXPECT_NEAR(png.pixels[i], expected, 1e-6f) << i;
    }
    EXPECT_THROW(writeImage(dir / "a.jpg", image), std::runtime_error);
    fs::remove_all(dir);
}

// Images kept in a database are encoded in memory: the very bytes of the file, every time.
TEST(ImageIo, EncodedImagesAreTheFilesBytes) {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("caustic-encode-test-" + std::to_string(getpid()));
    fs::create_directories(dir);
    RgbImage image{2, 2, {0.1f, 0.2f, 0.3f, 1.0f, 0.0f, 0.5f, 2.0f, 0.25f, 0.75f, 0, 0, 1e-3f}};
    for (const char* format : {"exr", "png"}) {
        const fs::path file = dir / (std::string("a.") + format);
        writeImage(file, image, 0.5);
        std::ifstream in(file, std::ios::binary);
        std::string onDisk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::string encoded = encodeImage(image, format, 0.5);
        EXPECT_EQ(encoded, onDisk) << format;
        EXPECT_EQ(encodeImage(image, format, 0.5), encoded) << format;
    }
    EXPECT_THROW(encodeImage(image, "tif"), std::runtime_error);
    fs::remove_all(dir);
}

TEST(ImageIo, SrgbEncodingMatchesTheStandard) {
    EXPECT_FLOAT_EQ(srgbEncode(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgbEncode(1.0f), 1.0f);
    EXPECT_FLOAT_EQ(srgbEncode(0.0031308f), 12.92f * 0.0031308f);
    EXPECT_NEAR(srgbEncode(0.18f), 0.4613561f, 1e-6f);  // IEC 61966-2-1
    EXPECT_FLOAT_EQ(srgbEncode(2.0f), 1.0f);
    EXPECT_FLOAT_EQ(srgbEncode(-1.0f), 0.0f);
}

}  // namespace caustic
