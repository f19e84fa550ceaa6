// SPDX-License-Identifier: Apache-2.0
// UsdGeomMesh subdivision tokens -> OpenSubdiv Sdc scheme and options (private header).
#pragma once

#include <opensubdiv/sdc/options.h>
#include <opensubdiv/sdc/types.h>

#include <string>
#include <vector>

#include "delegate/hd/meshTopology.h"

namespace principled::subdiv {

namespace Sdc = OpenSubdiv::Sdc;

struct SdcSetup {
    Sdc::SchemeType scheme = Sdc::SCHEME_CATMARK;
    Sdc::Options options;
};

/// Maps scheme (catmullClark | loop | bilinear), interpolateBoundary,
/// faceVaryingLinearInterpolation and triangleSubdivisionRule with USD semantics
/// (OpenUSD pxOsd/refinerFactory.cpp), setting every option explicitly because Sdc::Options()
/// defaults (boundary none, fvar all) are not USD's (edgeAndCorner, cornersPlus1).
/// - loop needs all-triangle faces, otherwise a warning and catmullClark;
/// - bilinear forces edgeAndCorner (pxOsd works around an OpenSubdiv 3.0 issue the same way);
/// - an empty token means the USD default; an unknown token is a warning and the default.
/// The caller handles scheme "none" (no subdivision) before calling this.
SdcSetup sdcSetup(const hd::MeshTopology& topology, const hd::SubdivTags& tags,
                  std::vector<std::string>* warnings);

}  // namespace principled::subdiv
