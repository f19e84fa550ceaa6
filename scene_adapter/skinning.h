// SPDX-License-Identifier: Apache-2.0
// UsdSkel linear blend skinning: a Mesh bound to a Skeleton (SkelBindingAPI) drawn in the pose
// of its animation at the delegate's time.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

namespace principled::usd {
class Stage;
class Prim;
}  // namespace principled::usd

namespace principled::adapter {

/// The posed mesh: points (and normals, when authored per point or per corner) in the bound
/// Skeleton's space, and that space's world transform, which replaces the mesh's own (UsdSkel
/// ignores a skinned prim's transform).
struct SkinnedMesh {
    std::vector<glm::vec3> points;
    std::vector<glm::vec3> normals;  ///< empty when the mesh has none (or not per point/corner)
    glm::dmat4 world{1.0};
    std::string skeleton;  ///< path of the bound Skeleton
    /// Skinned by joints (world is the skeleton's); false: blend shapes alone (world is the
    /// mesh's own).
    bool inSkeletonSpace = true;
};

/// A Skeleton's pose at one time: the skinning transform J_j * inverse(B_j) of each joint, and
/// the Skeleton's world transform; or why it cannot pose (error).
struct SkeletonPose {
    std::vector<std::string> joints;
    std::vector<glm::dmat4> skinning;
    std::unordered_map<std::string, double> blendShapeWeights;  ///< the animation's, by name
    glm::dmat4 world{1.0};
    std::string error;
};
/// Poses computed once per Skeleton path (for one time; clear it when the stage or time changes).
using SkeletonPoseCache = std::unordered_map<std::string, std::shared_ptr<const SkeletonPose>>;

/// Skins `mesh` at `time` when it lies under a SkelRoot and is bound (skel:skeleton on it or an
/// ancestor up to the SkelRoot) to an active Skeleton, with joint influences
/// (primvars:skel:jointIndices/jointWeights, vertex or constant, inherited the same way). Per
/// point, column-vector convention:
///   p_world = S * sum_i w_i * J_i * inverse(B_i) * G * p     (UsdSkel "Skinning a Prim": LBS)
/// S the Skeleton's world transform, J_i joint i's skeleton-space transform (an active
/// SkelAnimation bound by skel:animationSource, else restTransforms, else the bind pose,
/// composed down the joint paths), B_i its bindTransforms entry, G
/// primvars:skel:geomBindTransform (inherited; identity if none), w_i normalised.
/// Normals: the inverse transpose of each point's blended matrix, normalised.
/// Blend shapes (skel:blendShapes names, skel:blendShapeTargets BlendShape prims) add
/// weight * offsets (pointIndices when sparse; normalOffsets to normals) before skinning, the
/// weights from the animation's blendShapes / blendShapeWeights by name (0 when absent). A mesh
/// with blend shapes and no joint influences keeps its own transform and is not skinned.
/// std::nullopt when the mesh is not skinned; malformed data (sizes that do not match, unknown
/// joints, a missing or inactive skeleton) adds a warning (about the mesh, without its path)
/// and leaves the mesh as authored. Inbetween shapes blend piecewise linearly by weight. Not
/// done: dual-quaternion skinning
/// (skel:skinningMethod), skinned prims inside instances or PointInstancer prototypes.
std::optional<SkinnedMesh> skinMesh(const usd::Stage& stage, const usd::Prim& mesh, double time,
                                    std::vector<std::string>* warnings, SkeletonPoseCache* cache = nullptr);

/// The world transform of `prim` at `time` (its xformOps and its ancestors').
glm::dmat4 worldTransform(const usd::Prim& prim, double time);

}  // namespace principled::adapter
