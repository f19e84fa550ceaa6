// SPDX-License-Identifier: Apache-2.0
// SubdivMesh: the refined state of one mesh prim, rebuilt only when its topology changes.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "delegate/subdiv/subdivTopology.h"

namespace principled::subdiv {

/// Holds a SubdivTopology and its latest RefinedMesh for one prim. update() rebuilds the
/// topology only when topology, tags, point count or build options differ from the last
/// build (SubdivTopology::matches), and otherwise only re-poses. Not thread-safe: one prim,
/// one sync thread.
class SubdivMesh {
  public:
    /// Brings mesh() up to date for these inputs. False with *error when the topology is
    /// unusable (mesh() is then empty). Warnings of a rebuild are in topology()->warnings().
    bool update(const hd::MeshTopology& topology, const hd::SubdivTags& tags,
                const std::vector<glm::vec3>& points, const BuildOptions& options,
                std::string* error);

    const RefinedMesh& mesh() const { return _mesh; }
    const SubdivTopology* topology() const { return _topology.get(); }
    bool rebuiltLastUpdate() const { return _rebuilt; }  ///< false: the last update re-posed
    void clear();

  private:
    std::unique_ptr<SubdivTopology> _topology;
    RefinedMesh _mesh;
    bool _rebuilt = false;
};

}  // namespace principled::subdiv
