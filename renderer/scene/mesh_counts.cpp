#include "scene/mesh_counts.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "core/error.h"

namespace caustic {
namespace fs = std::filesystem;

namespace {

// A byte-at-a-time scanner over OBJ lines (Wavefront OBJ: a keyword, then fields separated by
// spaces or tabs). It keeps its state between blocks, so that a line may span any number of them
// and memory stays constant whatever the file holds.
class ObjScanner {
public:
    void scan(const char* p, const char* end) {
        while (p < end) {
            if (state_ == State::SkipLine) {
                const void* nl = std::memchr(p, '\n', size_t(end - p));
                if (!nl) return;
                p = static_cast<const char*>(nl) + 1;
                state_ = State::LineStart;
                continue;
            }
            step(*p++);
        }
    }
    // Ends a face left open by a file without a final newline.
    MeshCounts finish() {
        if (state_ == State::FaceGap || state_ == State::FaceToken) endFace();
        return counts_;
    }

private:
    enum class State { LineStart, AfterV, AfterF, FaceGap, FaceToken, SkipLine };

    static bool space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

    void endFace() {
        if (corners_ >= 3) counts_.triangles += corners_ - 2;
        state_ = State::LineStart;
    }

    void step(char c) {
        switch (state_) {
            case State::LineStart:
                if (c == 'v' || c == 'f')
                    state_ = c == 'v' ? State::AfterV : State::AfterF;
                else if (!space(c) && c != '\n')
                    state_ = State::SkipLine;
                return;
            case State::AfterV:  // "v x y z"; "vn", "vt" and "vp" are other records
                if (space(c)) ++counts_.vertices;
                if (c == 'n') counts_.normals = true;
                if (c == 't') counts_.texcoords = true;
                state_ = c == '\n' ? State::LineStart : State::SkipLine;
                return;
            case State::AfterF:
                corners_ = 0;
                state_ = space(c) ? State::FaceGap : c == '\n' ? State::LineStart : State::SkipLine;
                return;
            case State::FaceGap:
            case State::FaceToken:
                if (c == '\n')
                    endFace();
                else if (space(c))
                    state_ = State::FaceGap;
                else if (state_ == State::FaceGap)
                    ++corners_, state_ = State::FaceToken;
                return;
            case State::SkipLine:
                if (c == '\n') state_ = State::LineStart;
                return;
        }
    }

    State state_ = State::LineStart;
    uint64_t corners_ = 0;
    MeshCounts counts_;
};

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

MeshCounts countObj(const fs::path& file, const std::string& path) {
    const std::string name = file.filename().string();
    std::unique_ptr<std::FILE, FileCloser> in(std::fopen(file.c_str(), "rb"));
    if (!in) throw InputError(path, "cannot read OBJ file " + name + ": " + std::strerror(errno));
    ObjScanner scanner;
    std::vector<char> block(size_t(1) << 20);
    while (size_t n = std::fread(block.data(), 1, block.size(), in.get()))
        scanner.scan(block.data(), block.data() + n);
    if (std::ferror(in.get())) throw InputError(path, "cannot read OBJ file " + name);
    MeshCounts counts = scanner.finish();
    if (counts.triangles == 0) throw InputError(path, name + " has no faces");
    // A face of k corners makes k - 2 triangles: at most 3 corners a triangle.
    if (counts.normals) counts.vertices = std::max(counts.vertices, 3 * counts.triangles);
    return counts;
}

MeshCounts MeshCountCache::counts(const fs::path& file, const std::string& path) {
    std::error_code ec;
    const fs::path key = fs::canonical(file, ec);
    const uintmax_t size = fs::file_size(key, ec);
    const fs::file_time_type modified = fs::last_write_time(key, ec);
    // A file that cannot be examined is not cached: countObj reports why it cannot be read.
    if (ec) return countObj(file, path);
    {
        std::lock_guard lock(mutex_);
        auto it = entries_.find(key.string());
        if (it != entries_.end() && it->second.size == size && it->second.modified == modified)
            return it->second.counts;
    }
    // Scanned outside the lock: a large file must not hold up requests for other files.
    ++scans_;
    MeshCounts counts = countObj(key, path);
    std::lock_guard lock(mutex_);
    entries_[key.string()] = Entry{size, modified, counts};
    return counts;
}

}  // namespace caustic
