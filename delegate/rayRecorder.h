// SPDX-License-Identifier: Apache-2.0
// RayRecorder: receives every ray the integrator casts, so the same rays can be replayed
// through Embree alone (the "physical limit" measurement in bench/).
#pragma once

#include <glm/glm.hpp>

namespace principled::embree {

class RayRecorder {
public:
    virtual ~RayRecorder() = default;
    /// Called from render threads concurrently; implementations keep per-thread storage.
    virtual void record(const glm::vec3& origin, const glm::vec3& direction, float tnear,
                        float tfar, bool shadow) = 0;
};

}  // namespace principled::embree
