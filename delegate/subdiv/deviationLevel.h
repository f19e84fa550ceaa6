// SPDX-License-Identifier: Apache-2.0
// Subdivision level from how far the limit surface strays from the cage, on screen.
#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "delegate/hd/meshTopology.h"
#include "delegate/subdiv/adaptiveLevel.h"

namespace principled::subdiv {

/// The level (before the ceiling) at which the refined mesh lies within `tolerancePixels` of
/// its limit surface on screen, as an estimate:
///   d(v)  = v_limit - v per cage vertex. Interior: the part along the area-weighted vertex
///           normal (a slide within the tangent plane leaves the same picture) of
///           (2/9)(mean edge neighbour - v) + (4/9)(mean incident face centroid - v), which is
///           the bicubic B-spline limit mask (1, 4, 16) / 36 of a regular vertex (Halstead,
///           Kass & DeRose 1993, "Efficient, fair interpolation using Catmull-Clark surfaces",
///           appendix A) with the diagonal vertices written through the face centroids.
///           Boundary: (1/3)((b0 + b1)/2 - v), the cubic B-spline curve's limit mask
///           (1, 4, 1) / 6; 0 at a boundary corner under edgeAndCorner (kept sharp);
///   px(v) = |d(v)| * H / (2 D(v) tan(fov/2)), D(v) the nearest incident face's bounding
///           sphere distance (floored at 1e-3 of its radius), so a face passing near the
///           camera counts as near;
///   face  = for a polygon of 4+ corners, the largest corner height over the plane through its
///           centroid (Newell normal) in pixels at the face's distance: a twisted quad, a
///           saddle or a bent n-gon strays from its fan triangles whatever its corners do;
///   level = 0.5 log2(max(px, face) / tolerance)   (both shrink about 4x per uniform level).
/// -inf when the cage is its own limit (flat regular grids, flat triangles with sharp corners):
/// such a mesh needs no refinement. +inf where the inputs do not allow an estimate (a
/// boundary under interpolateBoundary "none", whose limit drops the boundary faces; degenerate
/// input): callers then keep the edge-length metric. Creases are not modelled (a crease keeps
/// the surface nearer the cage, so the estimate errs toward more refinement).
float deviationLevel(const std::vector<glm::vec3>& worldPoints, const hd::MeshTopology& topology,
                     const hd::SubdivTags& tags, const ScreenMetric& view, float tolerancePixels);

/// Whether a primvar (components per value; indices per face corner into the values: the
/// topology's own for vertex primvars, the channel's for face-varying ones) already equals its
/// own limit under the smooth rules, within relativeTolerance of its value range: linear data
/// over a regular grid does, a painted colour or a stretched UV layout does not. Only then do
/// the cage and the refined surface carry the same values, and deviationLevel() alone may
/// decide the level. sharpCorners: corners of the value topology keep their values.
bool valuesFollowTheCage(const std::vector<float>& values, int components, const hd::MeshTopology& topology,
                         const std::vector<int>& indices, bool sharpCorners, double relativeTolerance);

}  // namespace principled::subdiv
