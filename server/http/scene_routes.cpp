// The example scenes, the settings table and the OpenAPI document: read-only resources.
#include <algorithm>
#include <fstream>

#include "http/openapi.h"
#include "http/problem.h"
#include "http/routes.h"
#include "jobs/submission.h"
#include "render/settings.h"

namespace caustic::server {
namespace {

// An example scene's file as written (its layout and key order, for an editor): the JSON that a job
// naming the scene renders.
void sendExampleScene(ApiContext& api, const httplib::Request& req, httplib::Response& res) {
    const std::string name = req.matches[1];
    const std::vector<std::string> names = exampleSceneNames(api.config.scenesDir);
    if (std::find(names.begin(), names.end(), name) == names.end())
        return sendProblem(res, 404, "no example scene \"" + name + "\"");
    std::ifstream in(api.config.scenesDir / (name + ".json"), std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!Json::accept(text))
        return sendProblem(res, 500, "the example scene \"" + name + "\" is not valid JSON");
    res.set_content(text, "application/json");
}

}  // namespace

void registerSceneRoutes(httplib::Server& http, ApiContext& api) {
    http.Get("/api/openapi.json", [](const httplib::Request&, httplib::Response& res) {
        res.set_content(openApiDocument(), "application/json");
    });
    http.Get("/api/settings", [](const httplib::Request&, httplib::Response& res) {
        sendJson(res, 200, settingsSchemaJson());
    });
    http.Get("/api/scenes", [&api](const httplib::Request&, httplib::Response& res) {
        sendJson(res, 200, {{"scenes", exampleSceneNames(api.config.scenesDir)}});
    });
    http.Get("/api/scenes/([^/]+)", [&api](const httplib::Request& req, httplib::Response& res) {
        sendExampleScene(api, req, res);
    });
}

}  // namespace caustic::server
