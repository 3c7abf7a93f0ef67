#include "textures/texture_store.h"

#include <OpenImageIO/color.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/hash.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace caustic {

namespace fs = std::filesystem;

namespace {

std::string hex(uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

fs::path defaultDirectory() {
    std::error_code ec;
    fs::path tmp = fs::temp_directory_path(ec);
    return (ec ? fs::path("/tmp") : tmp) / "caustic-textures";
}

}  // namespace

TextureStore::TextureStore(const Options& options) : options_(options) {
    if (options_.directory.empty()) options_.directory = defaultDirectory();
        // A store of its own, not OIIO's process-wide one: its cache bound is this store's alone.
        // OpenImageIO 3 hands out a shared_ptr; 2.x a pointer to give back to destroy().
#if OIIO_VERSION_MAJOR >= 3
    system_ = OIIO::TextureSystem::create(/*shared=*/false);
#else
    system_.reset(OIIO::TextureSystem::create(/*shared=*/false),
                  [](OIIO::TextureSystem* system) { OIIO::TextureSystem::destroy(system); });
#endif
    const float megabytes = float(double(options_.cacheBytes) / double(1 << 20));
    system_->attribute("max_memory_MB", std::max(megabytes, 1.0f));
    // Prepared textures are tiled and carry their MIP levels: nothing is made on the fly.
    system_->attribute("autotile", 0);
    system_->attribute("automip", 0);
}

TextureStore::~TextureStore() = default;

const TextureStore::Image& TextureStore::addFile(const fs::path& file, TextureEncoding encoding,
                                                 const std::string& path) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream bytes;
    if (!(in && (bytes << in.rdbuf())))
        throw InputError(path, "cannot read image " + file.filename().string());
    return add(bytes.str(), encoding, file.filename().string(), path);
}

const TextureStore::Image& TextureStore::add(std::string_view bytes, TextureEncoding encoding,
                                             const std::string& name, const std::string& path) {
    const std::string key = hex(OIIO::xxhash::XXH64(bytes.data(), bytes.size(), 0)) +
                            (encoding == TextureEncoding::Srgb ? "-srgb" : "-linear");
    auto known = [&]() -> const Image* {
        for (const auto& image : images_)
            if (image->key == key) return image.get();
        return nullptr;
    };
    {
        std::lock_guard lock(mutex_);
        if (const Image* image = known()) return *image;
    }
    // Prepared outside the lock: reading and MIP-mapping a large image takes a while.
    auto image = std::make_unique<Image>();
    image->key = key;
    image->file = prepare(bytes, encoding, name, path, key, *image);
    image->handle = system_->get_texture_handle(OIIO::ustring(image->file));
    std::lock_guard lock(mutex_);
    if (const Image* same = known()) return *same;
    images_.push_back(std::move(image));
    return *images_.back();
}

std::string TextureStore::prepare(std::string_view bytes, TextureEncoding encoding,
                                  const std::string& name, const std::string& path,
                                  const std::string& key, Image& entry) const {
    OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
    auto in = OIIO::ImageInput::open(name, nullptr, &memory);
    if (!in) {
        std::string why = OIIO::geterror();
        throw InputError(path, "cannot read image " + name + (why.empty() ? "" : ": " + why));
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.depth != 1)
        throw InputError(path, "image " + name + " holds no pixels");
    if (int64_t(spec.width) * spec.height > options_.maxPixels)
        throw InputError(path, "image " + name + " is " + std::to_string(spec.width) + " x " +
                                   std::to_string(spec.height) + " pixels, over the limit of " +
                                   std::to_string(options_.maxPixels));
    if (spec.nchannels > 4)
        throw InputError(path, "image " + name + " has " + std::to_string(spec.nchannels) +
                                   " channels; a texture has 1 to 4");
    entry.channels = spec.nchannels;
    entry.width = spec.width;
    entry.height = spec.height;
    OIIO::ImageSpec floatSpec(spec.width, spec.height, spec.nchannels, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf image(floatSpec);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.localpixels()))
        throw InputError(path, "cannot read image " + name + ": " + in->geterror());

    const bool floatingPoint = spec.format.is_floating_point();
    const int colorChannels = std::min(spec.nchannels, 3);
    auto* pixels = static_cast<float*>(image.localpixels());
    const size_t texels = size_t(spec.width) * size_t(spec.height);
    for (size_t i = 0; i < texels; ++i) {
        float* texel = pixels + i * size_t(spec.nchannels);
        for (int c = 0; c < spec.nchannels; ++c) {
            if (!(texel[c] >= 0.0f && texel[c] < kInfinity))
                throw InputError(path, "image " + name + ": texel (" +
                                           std::to_string(i % size_t(spec.width)) + ", " +
                                           std::to_string(i / size_t(spec.width)) +
                                           ") is negative or not finite");
            // sRGB decoding of the colour channels (IEC 61966-2-1); alpha is linear.
            if (encoding == TextureEncoding::Srgb && !floatingPoint && c < colorChannels)
                texel[c] = OIIO::sRGB_to_linear(texel[c]);
        }
    }

    std::error_code ec;
    fs::create_directories(options_.directory, ec);
    const fs::path file = options_.directory / (key + ".exr");
    if (fs::exists(file, ec)) return file.string();
    // Written under a name of this process's and renamed: a reader never sees half a file, and
    // two workers preparing the same image each write a whole one.
    const fs::path partial =
        options_.directory / (key + "." + std::to_string(::getpid()) + "." +
                              hex(uint64_t(reinterpret_cast<uintptr_t>(&entry))) + ".part.exr");
    OIIO::ImageSpec config;
    config.format = OIIO::TypeDesc::HALF;
    config.tile_width = config.tile_height = 64;
    config.attribute("wrapmodes", "periodic,periodic");
    config.attribute("compression", "zip");
    std::ostringstream log;
    if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, image,
                                          partial.string(), config, &log)) {
        fs::remove(partial, ec);
        throw InputError(path, "cannot prepare image " + name +
                                   " as a texture: " + OIIO::geterror() + log.str());
    }
    fs::rename(partial, file, ec);
    if (ec) throw InputError(path, "cannot store the prepared texture: " + ec.message());
    return file.string();
}

void TextureStore::lookup(const Image& image, const TextureQuery& q, TextureFilter filter,
                          int first, int count, float* out) const {
    OIIO::TextureOpt opt;
    opt.swrap = opt.twrap = OIIO::TextureOpt::WrapPeriodic;
    opt.firstchannel = first;
    opt.interpmode = OIIO::TextureOpt::InterpBilinear;
    switch (filter) {
        case TextureFilter::Anisotropic:
            opt.mipmode = OIIO::TextureOpt::MipModeAniso;
            // At most 8 probes along the footprint's major axis, as pbrt-v4's MIPMap
            // (maxAnisotropy 8), and its minor axis as given rather than widened (OIIO's
            // conservative filter): 13% less render time on bench/texture_share.py's scene, the
            // far checkered plane's RMSE unchanged (texture_filtering_test).
            opt.anisotropic = 8;
            opt.conservative_filter = false;
            break;
        case TextureFilter::Trilinear:
            opt.mipmode = OIIO::TextureOpt::MipModeTrilinear;
            break;
        case TextureFilter::Nearest:
            opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
            opt.interpmode = OIIO::TextureOpt::InterpClosest;
            break;
    }
    // Channels past the image's: 0, but 1 for alpha.
    const float fill[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    opt.fill = 0.0f;
    opt.missingcolor = nullptr;
    auto* texture = static_cast<OIIO::TextureSystem::TextureHandle*>(image.handle);
    if (!system_->texture(texture, system_->get_perthread_info(), opt, q.st.x, q.st.y, q.dstdx.x,
                          q.dstdx.y, q.dstdy.x, q.dstdy.y, count, out))
        std::fill(out, out + count, 0.0f);
    for (int c = std::max(0, image.channels - first); c < count; ++c) out[c] = fill[first + c];
}

TextureStore::Stats TextureStore::stats() const {
    Stats s;
    long long value = 0;
    if (system_->getattribute("stat:cache_memory_used", OIIO::TypeDesc::INT64, &value))
        s.memoryUsed = value;
    if (system_->getattribute("stat:bytes_read", OIIO::TypeDesc::INT64, &value))
        s.bytesRead = value;
    system_->getattribute("stat:tiles_created", s.tilesCreated);
    system_->getattribute("stat:tiles_peak", s.tilesPeak);
    return s;
}

}  // namespace caustic
