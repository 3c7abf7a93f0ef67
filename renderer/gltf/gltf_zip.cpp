#include "gltf/gltf_zip.h"

#include <zip.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace caustic {
namespace {

struct ArchiveCloser {
    void operator()(zip_t* z) const { zip_discard(z); }
};
struct FileCloser {
    void operator()(zip_file_t* f) const { zip_fclose(f); }
};
using Archive = std::unique_ptr<zip_t, ArchiveCloser>;

// A name is confined to the archive: relative, with no "..", "." or empty part, no backslash
// (a Windows separator), no drive letter, no control byte.
bool confined(const std::string& name) {
    if (name.empty() || name.front() == '/' || name.find('\\') != std::string::npos ||
        (name.size() >= 2 && name[1] == ':'))
        return false;
    for (unsigned char c : name)
        if (c < 0x20 || c == 0x7F) return false;
    size_t start = 0;
    while (start <= name.size()) {
        size_t end = name.find('/', start);
        if (end == std::string::npos) end = name.size();
        const std::string part = name.substr(start, end - start);
        // A trailing "/" (a folder entry) leaves an empty last part, which is fine.
        if (part == ".." || part == "." || (part.empty() && end != name.size())) return false;
        start = end + 1;
    }
    return true;
}

// "a/b/../c" is not accepted anywhere, so joining is concatenation: the .gltf's folder and a URI
// that must itself be confined.
std::string folderOf(const std::string& name) {
    const size_t slash = name.rfind('/');
    return slash == std::string::npos ? std::string() : name.substr(0, slash + 1);
}

class ZipReader {
public:
    ZipReader(std::string_view bytes, const ZipLimits& limits, const MeshErrors& errors)
        : limits_(limits), errors_(errors) {
        zip_error_t error;
        zip_error_init(&error);
        zip_source_t* source = zip_source_buffer_create(bytes.data(), bytes.size(), 0, &error);
        if (source)
            archive_.reset(zip_open_from_source(source, ZIP_RDONLY | ZIP_CHECKCONS, &error));
        if (!archive_) {
            if (source) zip_source_free(source);
            const std::string why = zip_error_strerror(&error);
            zip_error_fini(&error);
            errors_.fail("not a zip archive libzip reads (" + why + ")");
        }
        zip_error_fini(&error);
        index();
    }

    const std::string& gltfName() const { return gltf_; }

    // The entry's bytes, held to its declared size and the limits as it is read; nothing when the
    // archive has no such file.
    std::optional<std::string> read(const std::string& name) {
        auto it = entries_.find(name);
        if (it == entries_.end()) return std::nullopt;
        const Entry& e = it->second;
        std::unique_ptr<zip_file_t, FileCloser> file(zip_fopen_index(archive_.get(), e.index, 0));
        if (!file)
            errors_.fail(name + ": cannot be read from the archive (" +
                         zip_strerror(archive_.get()) + ")");
        std::string out;
        out.resize(size_t(e.size));
        uint64_t got = 0;
        while (got < e.size) {
            const zip_int64_t n = zip_fread(file.get(), out.data() + got, e.size - got);
            if (n < 0)
                errors_.fail(name + ": does not decompress (" + zip_file_strerror(file.get()) +
                             ")");
            if (n == 0) break;
            got += uint64_t(n);
        }
        char extra;
        if (got != e.size || zip_fread(file.get(), &extra, 1) != 0)
            errors_.fail(name + ": its data does not have the size the archive's directory says");
        read_ += e.size;
        if (read_ > limits_.maxTotalBytes)
            errors_.fail("the files read expand to more than " +
                         std::to_string(limits_.maxTotalBytes) + " bytes");
        return out;
    }

private:
    struct Entry {
        zip_uint64_t index;
        uint64_t size;
    };

    void index() {
        const zip_int64_t count = zip_get_num_entries(archive_.get(), 0);
        if (count < 0) errors_.fail("the archive's directory cannot be read");
        if (uint64_t(count) > limits_.maxEntries)
            errors_.fail(std::to_string(count) + " entries; at most " +
                         std::to_string(limits_.maxEntries) + " are read");
        uint64_t total = 0;
        std::vector<std::string> gltfs;
        for (zip_int64_t i = 0; i < count; ++i) {
            zip_stat_t st;
            if (zip_stat_index(archive_.get(), zip_uint64_t(i), 0, &st) != 0 ||
                !(st.valid & ZIP_STAT_NAME) || !(st.valid & ZIP_STAT_SIZE))
                errors_.fail("entry " + std::to_string(i) + ": its directory record is unreadable");
            const std::string name = st.name;
            if (!confined(name))
                errors_.fail("entry \"" + name.substr(0, 200) +
                             "\": a name must stay inside the archive (relative, without \"..\")");
            if (!name.empty() && name.back() == '/') continue;  // a folder
            if (st.size > limits_.maxEntryBytes)
                errors_.fail(name + ": " + std::to_string(st.size) +
                             " bytes uncompressed; at most " +
                             std::to_string(limits_.maxEntryBytes) + " a file");
            if ((st.valid & ZIP_STAT_COMP_SIZE) && st.size > 1024 &&
                st.size / std::max<uint64_t>(st.comp_size, 1) > limits_.maxRatio)
                errors_.fail(name + ": compressed " +
                             std::to_string(st.size / std::max<uint64_t>(st.comp_size, 1)) +
                             " to 1; at most " + std::to_string(limits_.maxRatio) +
                             " to 1 is read (a zip bomb?)");
            total += st.size;
            if (total > limits_.maxTotalBytes)
                errors_.fail("the entries expand to more than " +
                             std::to_string(limits_.maxTotalBytes) + " bytes");
            entries_[name] = {zip_uint64_t(i), st.size};
            if (name.size() > 5 && name.compare(name.size() - 5, 5, ".gltf") == 0)
                gltfs.push_back(name);
        }
        if (gltfs.empty()) errors_.fail("holds no .gltf file");
        if (gltfs.size() > 1)
            errors_.fail("holds more than one .gltf (\"" + gltfs[0] + "\", \"" + gltfs[1] +
                         "\"); zip one model at a time");
        gltf_ = gltfs[0];
    }

    const ZipLimits& limits_;
    const MeshErrors& errors_;
    Archive archive_;
    std::map<std::string, Entry> entries_;
    std::string gltf_;
    uint64_t read_ = 0;
};

}  // namespace

GltfFile loadGltfUpload(std::string_view bytes, MeshFormat format, const MeshErrors& errors) {
    return format == MeshFormat::GltfZip ? loadGltfZip(bytes, ZipLimits{}, errors)
                                         : loadGlbModel(bytes, errors);
}

GltfFile loadGltfZip(std::string_view bytes, const ZipLimits& limits, const MeshErrors& errors) {
    ZipReader zip(bytes, limits, errors);
    const std::string gltf = zip.gltfName();
    const std::string folder = folderOf(gltf);
    const std::string json = *zip.read(gltf);
    GltfFileReader files = [&](const std::string& uri) -> std::optional<std::string> {
        const std::string& name = uri;  // tinygltf percent-decodes a URI before asking
        if (!confined(name) || name.back() == '/')
            errors.fail("the URI \"" + uri.substr(0, 200) +
                        "\" leaves the .gltf's folder in the archive (or is absolute)");
        return zip.read(folder + name);
    };
    return loadGltfModel(json, files, errors);
}

}  // namespace caustic
