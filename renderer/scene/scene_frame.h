// The frame scene positions are read in (scene loader internals).
#pragma once

#include <cmath>
#include <string>

#include "core/error.h"
#include "scene/json_reader.h"

namespace caustic {

/// Positions are stored relative to the camera: the loader subtracts the camera's position in
/// double before anything is rounded to float. Rendering is invariant under translation, and a
/// scene 1e5 from the origin then keeps every bit of precision near the camera (camera-relative
/// rendering), where a float at 1e5 would hold positions only to 0.008.
struct Frame {
    DVec3 origin{0.0};

    Vec3 point(const Json& j, const std::string& path) const {
        DVec3 p = readDVec3(j, path) - origin;
        for (int i = 0; i < 3; ++i)
            if (!(std::abs(p[i]) <= 3.0e38))
                throw InputError(
                    jsonPointer(path, size_t(i)),
                    "is out of the range of a float (|x| <= 3e38) relative to the camera");
        return Vec3(p);
    }
    Vec3 point(JsonObject& o, const std::string& key) const {
        return point(o.require(key), o.pathOf(key));
    }
};

}  // namespace caustic
