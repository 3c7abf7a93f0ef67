// The kd-trees the accelerator tests build: the default one, and the finest the SAH builds (every
// primitive one test, pbrt-v3's costs: on the bunny 18 times the default's nodes and 27 levels
// against 18), whose many planes put more rays in, along and through split planes.
#pragma once

#include <string>
#include <vector>

#include "accel/kdtree/kdtree.h"

namespace caustic::testing {

struct KdTreeVariant {
    std::string name;
    KdTreeOptions options;
};

inline std::vector<KdTreeVariant> kdTreeVariants() {
    return {{"default kd-tree", KdTreeOptions{}},
            {"finest kd-tree",
             KdTreeOptions{.intersectCost = 1.5f, .leafBlock = 1, .emptyBonus = 0.3f}}};
}

}  // namespace caustic::testing
