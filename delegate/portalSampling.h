// SPDX-License-Identifier: Apache-2.0
// PortalSet: UsdLux PortalLight rectangles (windows, doors) through which a dome light reaches
// an interior. They guide the dome's next-event estimation and change nothing else: a point
// that sees the sky through portals samples directions through them as one strategy of a
// mixture with the dome's own distribution, and the escaped-ray MIS weight uses the same mixture
// density, so the image converges to what it is without portals (as in Cycles, where portals are
// a sampling aid). Points on the outer side of every portal sample the dome alone.
//
// A portal passes light along `normal` (its local -Z, UsdLuxPortalLight); the point receives
// through it when it lies on that side. Each portal visible from p weighs the solid angle it
// subtends there; one is picked in proportion and a direction drawn uniformly in its solid angle
// (delegate/sphericalRectangle.h), so a direction through k portals has density k / (sum of the
// solid angles).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace principled::embree {

struct Portal {
    glm::vec3 center{0.0f};
    glm::vec3 axisU{0.0f}, axisV{0.0f};  ///< half extents, perpendicular
    glm::vec3 normal{0, 0, -1};          ///< unit: the direction light travels through it
    float area = 0.0f;
};

struct PortalView;  // portalSampling.cpp

class PortalSet {
public:
    explicit PortalSet(std::vector<Portal> portals);

    bool empty() const { return _portals.empty(); }
    size_t size() const { return _portals.size(); }
    /// The summed weight of the portals p receives through; 0 when it receives through none.
    float weight(const glm::vec3& p) const;
    /// A direction from p through a portal from two uniform numbers (u.x picks the portal and,
    /// rescaled, places the point with u.y); false when p receives through none. *pdf is
    /// pdf(p, wi).
    bool sample(const glm::vec3& p, const glm::vec2& u, glm::vec3* wi, float* pdf) const;
    /// Solid-angle density with which sample() at p produces unit direction wi (summed over the
    /// portals the ray crosses).
    float pdf(const glm::vec3& p, const glm::vec3& wi) const;

private:
    /// The portals' solid angles and spherical rectangles at p (cached per thread for the last
    /// point asked about).
    const PortalView& view(const glm::vec3& p) const;
    uint64_t _id = 0;
    std::vector<Portal> _portals;
};

}  // namespace principled::embree
