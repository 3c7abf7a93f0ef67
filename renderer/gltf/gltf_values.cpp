#include "gltf/gltf_values.h"

#include <cmath>
#include <sstream>

namespace caustic {
namespace {

const Json kEmptyObject = Json::object();
const Json kEmptyArray = Json::array();

std::string shown(double v) {
    std::ostringstream text;
    text << v;
    return text.str();
}

}  // namespace

std::string percentDecoded(const std::string& uri) {
    std::string out;
    auto hex = [](char c) {
        return c >= '0' && c <= '9'   ? c - '0'
               : c >= 'a' && c <= 'f' ? c - 'a' + 10
               : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                      : -1;
    };
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out += char(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

const Json& GltfValues::object(const Json& o, const std::string& key, const std::string& at) const {
    auto it = o.find(key);
    if (it == o.end()) return kEmptyObject;
    if (!it->is_object()) fail(at + ": " + key + " is not an object");
    return *it;
}

const Json& GltfValues::array(const Json& o, const std::string& key, const std::string& at) const {
    auto it = o.find(key);
    if (it == o.end()) return kEmptyArray;
    if (!it->is_array()) fail(at + ": " + key + " is not an array");
    return *it;
}

double GltfValues::checked(const Json& v, const std::string& what, double lo, double hi) const {
    if (!v.is_number()) fail(what + " is not a number");
    const double x = v.get<double>();
    if (!(x >= lo && x <= hi))
        fail(what + " is " + shown(x) + ", not in [" + shown(lo) + ", " +
             (std::isinf(hi) ? std::string("inf") : shown(hi)) + "]");
    return x;
}

double GltfValues::number(const Json& o, const std::string& key, double fallback, double lo,
                          double hi, const std::string& at) const {
    auto it = o.find(key);
    return it == o.end() ? fallback : checked(*it, at + ": " + key, lo, hi);
}

std::vector<double> GltfValues::numbers(const Json& o, const std::string& key, size_t n,
                                        std::vector<double> fallback, double lo, double hi,
                                        const std::string& at) const {
    auto it = o.find(key);
    if (it == o.end()) return fallback;
    if (!it->is_array() || it->size() != n)
        fail(at + ": " + key + " is not an array of " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (size_t i = 0; i < n; ++i)
        out.push_back(checked((*it)[i], at + ": " + key + "[" + std::to_string(i) + "]", lo, hi));
    return out;
}

int GltfValues::index(const Json& o, const std::string& key, size_t count,
                      const std::string& at) const {
    auto it = o.find(key);
    if (it == o.end()) return -1;
    if (!it->is_number_integer() || it->get<int64_t>() < 0 || it->get<int64_t>() >= int64_t(count))
        fail(at + ": " + key + " " + it->dump().substr(0, 40) + " does not exist (" +
             std::to_string(count) + ")");
    return it->get<int>();
}

std::string GltfValues::string(const Json& o, const std::string& key, const std::string& fallback,
                               const std::string& at) const {
    auto it = o.find(key);
    if (it == o.end()) return fallback;
    if (!it->is_string()) fail(at + ": " + key + " is not a string");
    return it->get<std::string>();
}

}  // namespace caustic
