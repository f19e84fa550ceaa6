// SPDX-License-Identifier: Apache-2.0
// The sampling distributions of a lat-long dome texture (EnvironmentMap, delegate/sceneData.h):
// the plain one by luminance x sin(theta), and the MIS-compensated one that next-event
// estimation uses when MIS pairs it with BSDF sampling.
#pragma once

#include <vector>

#include "delegate/sceneData.h"

namespace principled::embree {

/// Per texel of env (row-major, row 0 at the +Y pole): luminance x sin(theta) of its row centre
/// (Pharr et al. 2023, PBR 4th ed., §12.5.2).
std::vector<float> environmentWeights(const EnvironmentMap& env);

/// Marks env as a lat-long map and builds its compensated distribution from env.texels:
/// max(0, luminance - mean) x sin(theta), the mean taken over the sphere (Karlik et al. 2019,
/// "MIS compensation", eq. 8 with the map's mean). Left empty when less than 1e-3 of the
/// weight lies above the mean (a near-constant map). The plain distribution is built on first
/// use (EnvironmentMap::plain()).
void prepareEnvironmentSampling(EnvironmentMap& env);

}  // namespace principled::embree
