// libFuzzer target: render settings as a scene's "settings" object or a job's (parseSettings),
// and as the CLI's --set values (parseSettingValue, then each setting in turn). Accepted settings
// must print (toJson) as settings that parse back to the same.
#include "core/error.h"
#include "fuzz/fuzz_support.h"
#include "render/settings.h"

using namespace caustic;

namespace {

// Parses `settings`; when they are valid, checks that their JSON parses back unchanged.
void parseAndRoundTrip(const Json& settings) {
    RenderSettings parsed;
    try {
        parsed = parseSettings(settings);
    } catch (const InputError&) {
        return;
    }
    Json printed = parsed.toJson();
    try {
        if (parseSettings(printed).toJson() != printed)
            fuzz::fail("settings change when printed and parsed again: " + printed.dump());
    } catch (const InputError& e) {
        fuzz::fail("printed settings " + printed.dump() + " are refused: " + e.what());
    }
    parsed.resolvedSppPerPass();
    parsed.memoryLimitBytes();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::useOneThread();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Json value = parseSettingValue(fuzz::text(data, size));
    if (value.is_object()) {
        parseAndRoundTrip(mergeSettings(Json::object(), value));
        return 0;
    }
    // A single value, as `--set name=value` would give it to each setting.
    static const Json schema = settingsSchemaJson();
    for (auto it = schema.begin(); it != schema.end(); ++it)
        parseAndRoundTrip(Json{{it.key(), value}});
    return 0;
}
