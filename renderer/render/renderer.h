// One whole render: a render session (render/render_session.h) rendering every pass of the spp
// budget, from a checkpoint if there is one, stopped by the time limit, target error or
// cancellation, with the stats of what it cost. Pixel samples are seeded from (seed, pass, pixel,
// sample), so the image is bit-identical for any thread count and any split of its passes.
#pragma once

#include <memory>

#include "film/film.h"
#include "render/render_session.h"
#include "render/render_stats.h"
#include "render/settings.h"
#include "scene/scene.h"

namespace caustic {

struct RenderResult {
    std::unique_ptr<Film> film;
    RenderStats stats;
};

/// Renders every pass of `session`'s budget onto `film` (a checkpoint of the same scene and
/// settings, or an empty film): the render goes on from film.passSet().end(), and its image is
/// bit-identical to an uninterrupted render's. The time limit counts from this call.
RenderStats renderPasses(RenderSession& session, Film& film, const RenderCallbacks& callbacks = {});

/// Renders `scene` with `settings` from scratch. Throws InputError for settings the scene cannot
/// use, RenderCancelled when cancelled (or past a strict time limit) before the first pass.
RenderResult render(const Scene& scene, const RenderSettings& settings,
                    const RenderCallbacks& callbacks = {});

}  // namespace caustic
