// SPDX-License-Identifier: Apache-2.0
// PointInstancer support: the per-instance transforms of one prototype rprim, and the set of
// top-level Embree instances that draw its single bottom-level scene. A million instances of
// one mesh cost one BLAS plus one instance geometry and one InstanceRecord each.
#pragma once

#include <string>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "delegate/hd/path.h"
#include "delegate/instancerPrimvars.h"
#include "delegate/sceneData.h"

namespace principled::hd {
class SceneDelegate;
}

namespace principled::embree {

/// The placement of one instance: instancer * T(position) * R(orientation) * S(scale) *
/// prototype (UsdGeomPointInstancer::ComputeInstanceTransformsAtTime; cycles-peer.md).
/// rotation is (real, i, j, k) as USD writes quaternions; it is normalised here.
glm::mat4 instanceTransform(const glm::mat4& instancer, const glm::vec3& position,
                            const glm::vec4& rotation, const glm::vec3& scale,
                            const glm::mat4& prototype);

/// The instances drawing prototype rprim `prototypeId` of `instancerId`, from the scene
/// delegate's instancer arrays. Arrays of the wrong length are ignored (a warning each). With
/// a cache, the instancer's per-instance primvars are read once for all its prototypes.
std::vector<InstanceRecord> computeInstances(const hd::SceneDelegate* delegate,
                                             const hd::Path& instancerId,
                                             const hd::Path& prototypeId,
                                             const glm::mat4& prototypeTransform,
                                             std::vector<std::string>* warnings,
                                             InstancerPrimvarCache* primvarCache = nullptr);

/// Top-level Embree instances sharing one BLAS. Not thread-safe itself; distinct sets may be
/// rebuilt in parallel (rtcAttachGeometry is thread-safe).
class InstanceSet {
public:
    InstanceSet() = default;
    ~InstanceSet() { release(); }
    InstanceSet(const InstanceSet&) = delete;
    InstanceSet& operator=(const InstanceSet&) = delete;

    /// Replaces the instances: one Embree instance of `blas` per record.
    void rebuild(RTCDevice device, RTCScene top, RTCScene blas, void* userData,
                 std::vector<InstanceRecord> records);
    void release();

    const std::vector<InstanceRecord>& records() const { return _records; }
    const std::vector<unsigned>& geomIds() const { return _geomIds; }

private:
    RTCScene _top = nullptr;
    std::vector<RTCGeometry> _geoms;
    std::vector<unsigned> _geomIds;
    std::vector<InstanceRecord> _records;
};

}  // namespace principled::embree
