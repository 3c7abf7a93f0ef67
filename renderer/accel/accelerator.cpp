#include "accel/accelerator.h"

#include "accel/bruteforce.h"
#include "accel/embree.h"
#include "accel/kdtree/kdtree.h"
#include "core/error.h"

namespace caustic {

const std::vector<std::string>& acceleratorNames() {
    static const std::vector<std::string> names{"kdtree", "embree", "bruteforce"};
    return names;
}

std::unique_ptr<Accelerator> createAccelerator(const std::string& name, const Geometry& geometry) {
    if (name == "bruteforce") return std::make_unique<BruteForceAccel>(geometry);
    if (name == "kdtree") return std::make_unique<KdTreeAccel>(geometry);
    if (name == "embree") return std::make_unique<EmbreeAccel>(geometry);
    std::string valid;
    for (const std::string& n : acceleratorNames()) valid += (valid.empty() ? "" : ", ") + n;
    throw InputError("/settings/accelerator",
                     "unknown accelerator \"" + name + "\"; valid: " + valid);
}

}  // namespace caustic
