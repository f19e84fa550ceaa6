// SPDX-License-Identifier: Apache-2.0
// Turns a uniformly refined Far::TopologyRefiner into Stencils: refinement stencils from the
// coarse cage to the last level, and limit masks from the last level to the limit surface.
// Private to principled_subdiv (the only place that includes OpenSubdiv headers).
#pragma once

#include <opensubdiv/far/topologyRefiner.h>

#include "delegate/subdiv/stencils.h"

namespace principled::subdiv {

namespace Far = OpenSubdiv::Far;

enum class Interpolation { Vertex, Varying, FaceVarying };

/// Stencils from coarse elements (vertices or face-varying values of `channel`) to the elements
/// of the refiner's last level, through Far::StencilTableFactory (last level only).
Stencils refinementStencils(const Far::TopologyRefiner& refiner, Interpolation mode,
                            int channel = 0);

/// The same refinement as a chain of local tables, one per level: table l-1 maps level l-1
/// elements to level l elements (a handful of weights per row, against ~18 per row for the
/// flattened Far table). Recorded by running PrimvarRefiner::Interpolate* on symbolic values.
std::vector<Stencils> levelStencils(const Far::TopologyRefiner& refiner, Interpolation mode,
                                    int channel = 0);

/// Limit masks over the last level's vertices: position, and the two tangents whose cross
/// product is the surface normal. Built once by running PrimvarRefiner::Limit on symbolic
/// values, so that re-posing needs no refiner. Needs fullTopologyInLastLevel.
struct LimitMasks {
    Stencils position;
    Stencils tangentU;
    Stencils tangentV;
};
LimitMasks vertexLimitMasks(const Far::TopologyRefiner& refiner);

/// Limit masks over the last level's face-varying values of `channel` (identity rows for
/// linearly interpolated values).
Stencils faceVaryingLimitMasks(const Far::TopologyRefiner& refiner, int channel);

}  // namespace principled::subdiv
