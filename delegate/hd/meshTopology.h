// SPDX-License-Identifier: Apache-2.0
// Mesh topology and subdivision tags as a scene delegate reports them (UsdGeomMesh semantics).
#pragma once

#include <vector>

#include "delegate/hd/token.h"

namespace principled::hd {

/// Subdivision rules and sharpness tags (UsdGeomMesh; OpenSubdiv Sdc options).
struct SubdivTags {
    Token interpolateBoundary{"edgeAndCorner"};           ///< none | edgeOnly | edgeAndCorner
    Token faceVaryingLinearInterpolation{"cornersPlus1"};  ///< OpenSubdiv FVarLinearInterpolation
    Token triangleSubdivisionRule{"catmullClark"};         ///< catmullClark | smooth
    std::vector<int> creaseIndices;
    std::vector<int> creaseLengths;
    std::vector<float> creaseSharpnesses;
    std::vector<int> cornerIndices;
    std::vector<float> cornerSharpnesses;
};

/// Polygonal topology. subdivisionScheme defaults to catmullClark as in USD.
struct MeshTopology {
    Token scheme{"catmullClark"};       ///< catmullClark | loop | bilinear | none
    Token orientation{"rightHanded"};   ///< rightHanded | leftHanded
    std::vector<int> faceVertexCounts;
    std::vector<int> faceVertexIndices;
    std::vector<int> holeIndices;
    int refineLevel = -1;  ///< uniform subdivision level for this prim; -1 = the delegate decides
};

}  // namespace principled::hd
