// SPDX-License-Identifier: Apache-2.0
// MaterialNetwork: a shading network (nodes, parameters, connections) as the scene delegate
// reports it for a material sprim. The render delegate maps it to its shading model.
#pragma once

#include <map>
#include <vector>

#include "delegate/hd/path.h"
#include "delegate/hd/token.h"
#include "delegate/hd/value.h"

namespace principled::hd {

struct MaterialConnection {
    Path upstreamNode;
    Token upstreamOutput;  ///< e.g. "rgb", "r", "result"
};

struct MaterialNode {
    Path path;
    Token identifier;  ///< info:id, e.g. "UsdPreviewSurface", "UsdUVTexture"
    std::map<Token, Value> parameters;                            ///< authored input values
    std::map<Token, std::vector<MaterialConnection>> inputConnections;
};

struct MaterialNetwork {
    std::vector<MaterialNode> nodes;  ///< upstream nodes first
    Path surfaceTerminal;             ///< the node feeding outputs:surface (empty if none)

    const MaterialNode* node(const Path& p) const {
        for (const auto& n : nodes)
            if (n.path == p) return &n;
        return nullptr;
    }
};

}  // namespace principled::hd
