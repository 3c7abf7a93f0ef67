// A whole scene document scaled and moved: p -> s p + t, with the same t on every axis. Shared by
// the scale invariance test (which compares the images) and the extremes test (which renders the
// tiny, huge and far scenes with every integrator).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace caustic::testing {

/// The point `p` (a JSON array of 3 numbers) under p -> s p + t.
inline nlohmann::json transformedPoint(const nlohmann::json& p, double s, double t) {
    return nlohmann::json::array(
        {s * p[0].get<double>() + t, s * p[1].get<double>() + t, s * p[2].get<double>() + t});
}

/// The vector `v` (a JSON array of 3 numbers) times `s`.
inline nlohmann::json scaledVector(const nlohmann::json& v, double s) {
    return nlohmann::json::array(
        {s * v[0].get<double>(), s * v[1].get<double>(), s * v[2].get<double>()});
}

/// The scene document `doc` under p -> s p + t, computed in double and rounded to float once, by
/// the loader. Positions map as points, edge vectors and radii scale by s, directions (up) and
/// angles (fov) stay. Radiance (emission, background) is invariant; a point light's intensity
/// scales by s^2 so that its irradiance I cos(theta) / d^2 is unchanged.
inline nlohmann::json transformedScene(nlohmann::json doc, double s, double t) {
    using nlohmann::json;
    json& camera = doc["camera"];
    camera["position"] = transformedPoint(camera["position"], s, t);
    camera["look_at"] = transformedPoint(camera["look_at"], s, t);
    for (json& shape : doc["shapes"]) {
        std::string type = shape["type"].get<std::string>();
        if (type == "sphere") {
            shape["center"] = transformedPoint(shape["center"], s, t);
            shape["radius"] = s * shape["radius"].get<double>();
        } else if (type == "quad") {
            shape["origin"] = transformedPoint(shape["origin"], s, t);
            shape["u"] = scaledVector(shape["u"], s);
            shape["v"] = scaledVector(shape["v"], s);
        } else if (type == "triangle") {
            for (json& p : shape["vertices"]) p = transformedPoint(p, s, t);
        } else {
            // A mesh maps p to R(S p) + T; composed with this: scale s S, translation s T + t.
            json& m = shape["transform"];
            json scale = m.contains("scale") ? m["scale"] : json(1.0);
            m["scale"] = scale.is_number() ? json(s * scale.get<double>()) : scaledVector(scale, s);
            json translate = m.contains("translate") ? m["translate"] : json::array({0, 0, 0});
            m["translate"] = transformedPoint(translate, s, t);
        }
    }
    if (doc.contains("lights")) {
        for (json& light : doc["lights"]) {
            light["position"] = transformedPoint(light["position"], s, t);
            light["intensity"] = scaledVector(light["intensity"], s * s);
        }
    }
    return doc;
}

}  // namespace caustic::testing
