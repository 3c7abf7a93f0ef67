// What the mesh file tests share: a bad file must be an InputError at the shape's path whose
// message names the file and then what is wrong ("bunny.obj: line 4: ...").
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/mesh_file.h"

namespace caustic::testing {

inline const std::string kMeshPath = "/shapes/0/asset";

inline void expectMeshError(const std::string& bytes, MeshFormat format, const std::string& name,
                            const std::string& message) {
    try {
        parseMeshBytes(bytes, format, MeshTransform{}, name, kMeshPath);
        ADD_FAILURE() << "loaded; expected \"" << message << "\"";
    } catch (const InputError& e) {
        EXPECT_EQ(e.path(), kMeshPath);
        EXPECT_EQ(e.message(), name + ": " + message);
    }
}

}  // namespace caustic::testing

// Each use is one bad file; the trace names the line of the case that failed.
#define EXPECT_MESH_ERROR(bytes, format, name, message)                          \
    do {                                                                         \
        SCOPED_TRACE(message);                                                   \
        caustic::testing::expectMeshError((bytes), (format), (name), (message)); \
    } while (0)
