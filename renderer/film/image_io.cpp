#include "film/image_io.h"

#include <unistd.h>

#include <atomic>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace caustic {

namespace fs = std::filesystem;

float srgbEncode(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

std::string encodeImage(const RgbImage& image, const std::string& format, double exposure) {
    if (format != "exr" && format != "png")
        throw std::runtime_error("unsupported image type \"" + format + "\" (use png or exr)");
    auto out = OIIO::ImageOutput::create(format);
    if (!out)
        throw std::runtime_error("OpenImageIO cannot write " + format + ": " + OIIO::geterror());
    // Written to memory through an I/O proxy (OpenImageIO 2.2 on).
    OIIO::Filesystem::IOVecOutput memory;
    void* proxy = &memory;
    bool ok;
    if (format == "exr") {
        OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT);
        spec.attribute("compression", "zip");
        // OpenImageIO stamps an EXR with the time of writing (capDate) unless DateTime is given:
        // an empty one keeps the file a function of its pixels, so that equal renders give equal
        // files wherever they were written.
        spec.attribute("DateTime", "");
        spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
        ok = out->open("image.exr", spec) &&
             out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
    } else {
        auto scale = static_cast<float>(std::exp2(exposure));
        std::vector<unsigned char> bytes(image.pixels.size());
        for (size_t i = 0; i < bytes.size(); ++i)
            bytes[i] = static_cast<unsigned char>(
                std::lround(255.0f * srgbEncode(scale * image.pixels[i])));
        OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
        spec.attribute("oiio:ColorSpace", "sRGB");
        spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
        ok = out->open("image.png", spec) && out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
    }
    ok = out->close() && ok;
    if (!ok) throw std::runtime_error("cannot encode a " + format + " image: " + out->geterror());
    const std::vector<unsigned char>& bytes = memory.buffer();
    return std::string(bytes.begin(), bytes.end());
}

void writeImage(const fs::path& file, const RgbImage& image, double exposure) {
    std::string ext = file.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".exr" && ext != ".png")
        throw std::runtime_error("unsupported image type \"" + ext + "\" for " + file.string() +
                                 " (use .png or .exr)");
    const std::string bytes = encodeImage(image, ext.substr(1), exposure);
    // A name of its own per call, so that two writers of one file (two attempts of a server job)
    // never write into each other's temporary file; the renames are atomic.
    static std::atomic<uint64_t> counter{0};
    fs::path tmp = file;
    tmp += ".tmp" + std::to_string(::getpid()) + "." + std::to_string(counter++);
    {
        std::ofstream out(tmp, std::ios::binary);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.close();
        if (!out) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw std::runtime_error("cannot write " + file.string());
        }
    }
    fs::rename(tmp, file);
}

namespace {

// With `memory`, the image is read from it and `file` only names it (its extension tells OIIO the
// format).
std::unique_ptr<OIIO::ImageInput> openImage(const fs::path& file, int64_t maxPixels,
                                            OIIO::Filesystem::IOProxy* memory = nullptr) {
    auto in = OIIO::ImageInput::open(file.string(), nullptr, memory);
    if (!in)
        throw std::runtime_error("cannot read " + file.filename().string() + ": " +
                                 OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1)
        throw std::runtime_error(file.filename().string() + " holds no pixels");
    if (maxPixels > 0 && int64_t(spec.width) * spec.height > maxPixels)
        throw std::runtime_error(file.filename().string() + " is " + std::to_string(spec.width) +
                                 " x " + std::to_string(spec.height) +
                                 " pixels, over the limit of " + std::to_string(maxPixels));
    return in;
}

}  // namespace

ImageSize readImageSize(const fs::path& file, int64_t maxPixels) {
    auto in = openImage(file, maxPixels);
    return ImageSize{in->spec().width, in->spec().height};
}

ImageSize readImageSize(std::string_view bytes, const std::string& name, int64_t maxPixels) {
    OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
    auto in = openImage(name, maxPixels, &memory);
    return ImageSize{in->spec().width, in->spec().height};
}

RgbImage readImage(const fs::path& file, int64_t maxPixels) {
    auto in = openImage(file, maxPixels);
    const OIIO::ImageSpec& spec = in->spec();
    RgbImage image{spec.width, spec.height, {}};
    std::vector<float> all(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()))
        throw std::runtime_error("cannot read " + file.filename().string() + ": " + in->geterror());
    image.pixels.resize(size_t(spec.width) * spec.height * 3);
    for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
        for (int c = 0; c < 3; ++c)
            image.pixels[3 * p + c] = all[p * spec.nchannels + std::min(c, spec.nchannels - 1)];
    return image;
}

}  // namespace caustic
