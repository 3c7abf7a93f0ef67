// Scene::shade's textured case: the texture frame and the footprint at a point, then the material
// its textures make there.
#include "scene/scene.h"
#include "textures/texture_slot.h"

namespace caustic {

const Material& Scene::shadeTextured(const Material& m, SurfaceInteraction& si,
                                     MaterialScratch& scratch, float footprintScale) const {
    TexturePoint point;
    point.frame = geometry.textureFrame(si);
    point.n = si.n;
    Vec3 dpdx, dpdy;
    camera.approximateDpDxy(si.p, si.n, footprintScale, dpdx, dpdy);
    point.query = footprintQuery(point.frame, dpdx, dpdy);
    return m.atPoint(point, si.ns, scratch);
}

}  // namespace caustic
