// SPDX-License-Identifier: Apache-2.0
// USD crease chains and corners -> per-edge and per-vertex sharpness, validated.
#pragma once

#include <string>
#include <vector>

#include "delegate/hd/meshTopology.h"

namespace principled::subdiv {

/// Sharpness as OpenSubdiv's TopologyDescriptor takes it: one entry per edge (vertex pair)
/// and per corner vertex. 10 is infinitely sharp in both USD and Sdc
/// (Sdc::Crease::SHARPNESS_INFINITE).
struct SharpnessTags {
    std::vector<int> edgeVertices;  ///< 2 per edge
    std::vector<float> edgeSharpness;
    std::vector<int> cornerVertices;
    std::vector<float> cornerSharpness;
};

/// Splits each crease chain (creaseLengths[i] consecutive creaseIndices) into its edges.
/// creaseSharpnesses holds one value per crease when its size equals creaseLengths.size(),
/// else one per edge when it equals sum(creaseLengths[i] - 1) (UsdGeomMesh). Bad tags are
/// dropped with a warning (the mesh still refines): chains shorter than 2, indices outside
/// [0, pointCount), size mismatches, negative or NaN sharpness.
SharpnessTags sharpnessTags(const hd::SubdivTags& tags, size_t pointCount,
                            std::vector<std::string>* warnings);

}  // namespace principled::subdiv
