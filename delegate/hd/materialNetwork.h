// SPDX-License-Identifier: Apache-2.0
// MaterialNetwork: a shading network (nodes, parameters, connections) as the scene delegate
// reports it for a material sprim. The render delegate maps it to its shading model.
#pragma once

#include <map>
#include <string>
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
    std::string where;  ///< where it was authored ("file:line:col") for messages; may be empty
    /// Authored input values; an input's colour-space metadata, when authored, is the token
    /// parameter "colorSpace:<input>" (as UsdImaging passes it to Hydra).
    std::map<Token, Value> parameters;
    std::map<Token, std::vector<MaterialConnection>> inputConnections;
};

struct MaterialNetwork {
    std::vector<MaterialNode> nodes;  ///< upstream nodes first
    /// The node feeding outputs:surface, else outputs:mtlx:surface (empty if none).
    Path surfaceTerminal;
    /// What the scene delegate could not follow while gathering the network (a connection
    /// cycle, say), one line each, "where: what"; the material reports them.
    std::vector<std::string> problems;

    const MaterialNode* node(const Path& p) const {
        for (const auto& n : nodes)
            if (n.path == p) return &n;
        return nullptr;
    }
};

}  // namespace principled::hd
