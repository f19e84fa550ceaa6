// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/subdivMesh.h"

namespace principled::subdiv {

bool SubdivMesh::update(const hd::MeshTopology& topology, const hd::SubdivTags& tags,
                        const std::vector<glm::vec3>& points, const BuildOptions& options,
                        std::string* error) {
    _rebuilt = !_topology || !_topology->matches(topology, tags, points.size(), options);
    if (_rebuilt) {
        _topology = SubdivTopology::create(topology, tags, points.size(), options, error);
        if (!_topology) {
            clear();
            return false;
        }
    }
    if (!_topology->refine(points, &_mesh, error)) {
        clear();
        return false;
    }
    return true;
}

void SubdivMesh::clear() {
    _topology.reset();
    _mesh = RefinedMesh();
}

}  // namespace principled::subdiv
