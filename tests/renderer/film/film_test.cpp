#include "film/film.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
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
