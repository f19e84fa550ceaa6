// SPDX-License-Identifier: Apache-2.0
// Sampling and intersecting the lights of a scene snapshot: next-event estimation picks a point
// or direction on a light; rays that reach a light find it here (lights are not Embree geometry).
#pragma once

#include <glm/glm.hpp>

#include "delegate/sceneData.h"

namespace principled::embree {

struct LightSample {
    glm::vec3 wi{0.0f};      ///< unit direction from the shading point toward the light
    glm::vec3 Li{0.0f};      ///< radiance arriving (irradiance for a delta light)
    float pdf = 0.0f;        ///< solid-angle pdf (1 for delta lights)
    float distance = 1e30f;  ///< to the sampled point (1e30 for distant and dome lights)
    bool delta = false;
    /// Mesh lights: the sampled triangle (GeometryRecord::triangles index) and the barycentrics
    /// of its corners 1 and 2 at the sampled point (textured emission is evaluated there).
    int meshTriangle = -1;
    glm::vec2 bary{0.0f};
};

/// Samples light `l` as seen from point p with geometric normal ng (used by the dome's cosine
/// fallback). Returns false when the light cannot contribute (behind a one-sided emitter, p inside
/// a sphere light...). misCompensation: a textured dome samples its MIS-compensated distribution
/// (EnvironmentMap::compensated), for callers that combine the sample with BSDF sampling by MIS.
bool sampleLight(const LightRecord& l, const glm::vec3& p, const glm::vec3& ng, const glm::vec2& u,
                 LightSample* out, bool misCompensation = false);

/// For a ray from o along unit d whose nearest geometry is at tmax: if it reaches the emitting
/// surface of area light l first, returns its radiance and the solid-angle pdf sampleLight()
/// would have produced this direction with (prevNg: normal at o, for the dome fallback).
bool intersectAreaLight(const LightRecord& l, const glm::vec3& o, const glm::vec3& d, float tmax,
                        glm::vec3* Le, float* pdf);

/// Radiance of an escaped ray along d from environment light l (dome or distant disc), and the
/// pdf sampleLight() gives that direction from point `origin` with normal ng (with the same
/// misCompensation; a dome with portals mixes in their density at origin). pdf may be null when
/// the caller does not weigh the hit (camera rays, after a delta bounce): the portal density is
/// then not computed.
bool environmentRadiance(const LightRecord& l, const glm::vec3& origin, const glm::vec3& d, const glm::vec3& ng,
                         glm::vec3* Le, float* pdf, bool misCompensation = false);

bool isAreaLight(const LightRecord& l);

/// The radius of a sphere around l.center that holds the whole emitter (sphere, rect, disk,
/// cylinder, mesh); 0 for point, distant and dome lights; infinite for a rect or disk whose axes a
/// shearing transform left oblique (no finite sphere holds what intersectAreaLight() accepts).
float lightBoundingRadius(const LightRecord& l);

/// A point of area light l (sphere, rect, disk, cylinder, mesh) uniform in its area from two
/// uniform numbers, with the light's outward (emitting) normal there (a mesh light's triangle
/// normal: it emits from both sides); false for other kinds. The rect, disk, cylinder and mesh
/// points are the ones sampleLight()'s area sampling uses for the same numbers.
bool lightSurfacePoint(const LightRecord& l, const glm::vec2& u, glm::vec3* p, glm::vec3* n);

/// Radiance that area light l (sphere, rect, disk, cylinder) emits from its surface point q
/// along unit direction d, shaping and rect texture included: what intersectAreaLight() returns
/// for a ray that reaches q travelling along -d. q must lie on the light; the caller checks
/// that d leaves the emitting side.
glm::vec3 emittedRadiance(const LightRecord& l, const glm::vec3& q, const glm::vec3& d);

/// Solid-angle pdf with which sampleLight() picks a point of mesh light l, from `origin`, seen at
/// `distance` under the cosine `cosLight` (its surface normal against the direction).
float meshLightPdf(const LightRecord& l, const glm::vec3& origin, float distance, float cosLight);

/// Lat-long mapping of a direction in the dome's frame (USD/OpenEXR convention: u = 0.5 -
/// atan2(x, z) / 2pi, v measured from the +Y pole).
glm::vec2 directionToLatLong(const glm::vec3& d);
glm::vec3 latLongToDirection(const glm::vec2& uv);

}  // namespace principled::embree
