// Ray casting (Appel 1968): the first hit's emission plus direct light, with hard shadows from
// point lights. No reflection or refraction: specular surfaces show only what they emit.
#pragma once

#include "integrators/integrator.h"

namespace caustic {

class RayCastIntegrator final : public Integrator {
public:
    using Integrator::Integrator;
    Color Li(const Ray& ray, SampleContext& ctx) const override;
};

}  // namespace caustic
