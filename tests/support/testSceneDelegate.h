// SPDX-License-Identifier: Apache-2.0
// TestSceneDelegate: an in-memory scene delegate for tests (like Hydra's Hd_UnitTestDelegate):
// add prims with plain data, edit them, and mark them dirty, with no USD parsing involved.
#pragma once

#include <map>
#include <string>

#include "delegate/hd/renderIndex.h"
#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"

namespace principled::test {

class TestSceneDelegate : public hd::SceneDelegate {
public:
    struct Prim {
        hd::Token type;
        glm::dmat4 transform{1.0};
        bool visible = true;
        hd::MeshTopology topology;
        std::map<hd::Token, hd::Value> values;  // points, radius, displayColor, params...
        std::map<hd::Token, hd::Interpolation> interpolation;
        hd::Path material;
        hd::MaterialNetwork network;
    };

    explicit TestSceneDelegate(hd::RenderIndex* index) : _index(index) {}

    /// A quad of side `size` in the XY plane (normal +Z) centred at the origin.
    void addQuad(const hd::Path& id, float size, const glm::dmat4& xf = glm::dmat4(1.0)) {
        Prim p;
        p.type = hd::tokens::mesh();
        p.transform = xf;
        float h = 0.5f * size;
        p.values[hd::tokens::points()] =
            std::vector<glm::vec3>{{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
        p.topology.faceVertexCounts = {4};
        p.topology.faceVertexIndices = {0, 1, 2, 3};
        p.topology.scheme = hd::Token("none");
        add(id, std::move(p));
    }
    void addSphere(const hd::Path& id, float radius, const glm::dmat4& xf = glm::dmat4(1.0)) {
        Prim p;
        p.type = hd::tokens::sphere();
        p.transform = xf;
        p.values[hd::tokens::radius()] = radius;
        add(id, std::move(p));
    }
    void addCamera(const hd::Path& id, const glm::dmat4& xf, std::map<hd::Token, hd::Value> params) {
        Prim p;
        p.type = hd::tokens::camera();
        p.transform = xf;
        p.values = std::move(params);
        add(id, std::move(p));
    }
    /// A UsdPreviewSurface material with the given inputs.
    void addMaterial(const hd::Path& id, std::map<hd::Token, hd::Value> inputs) {
        Prim p;
        p.type = hd::tokens::material();
        hd::MaterialNode node;
        node.path = id.appendChild("Surface");
        node.identifier = hd::Token("UsdPreviewSurface");
        node.parameters = std::move(inputs);
        p.network.nodes.push_back(node);
        p.network.surfaceTerminal = node.path;
        add(id, std::move(p));
    }
    void addLight(const hd::Path& id, const hd::Token& type, const glm::dmat4& xf,
                  std::map<hd::Token, hd::Value> params) {
        Prim p;
        p.type = type;
        p.transform = xf;
        p.values = std::move(params);
        add(id, std::move(p));
    }
    void bind(const hd::Path& rprim, const hd::Path& material) { _prims[rprim].material = material; }

    Prim& prim(const hd::Path& id) { return _prims.at(id); }

    // SceneDelegate.
    hd::MeshTopology getMeshTopology(const hd::Path& id) const override { return at(id).topology; }
    hd::SubdivTags getSubdivTags(const hd::Path&) const override { return {}; }
    glm::dmat4 getTransform(const hd::Path& id) const override { return at(id).transform; }
    bool getVisible(const hd::Path& id) const override { return at(id).visible; }
    bool getDoubleSided(const hd::Path&) const override { return false; }
    hd::Value get(const hd::Path& id, const hd::Token& key) const override {
        auto& v = at(id).values;
        auto it = v.find(key);
        return it == v.end() ? hd::Value() : it->second;
    }
    hd::Value getIndexedPrimvar(const hd::Path& id, const hd::Token& key,
                                std::vector<int>* indices) const override {
        indices->clear();
        return get(id, key);
    }
    std::vector<hd::PrimvarDescriptor> getPrimvarDescriptors(const hd::Path& id,
                                                             hd::Interpolation interp) const override {
        std::vector<hd::PrimvarDescriptor> out;
        for (const auto& [name, i] : at(id).interpolation)
            if (i == interp) out.push_back({name, i, hd::Token(), false});
        return out;
    }
    hd::Path getMaterialId(const hd::Path& id) const override { return at(id).material; }
    hd::MaterialNetwork getMaterialResource(const hd::Path& id) const override { return at(id).network; }
    hd::Value getLightParamValue(const hd::Path& id, const hd::Token& p) const override { return get(id, p); }
    hd::Value getCameraParamValue(const hd::Path& id, const hd::Token& p) const override { return get(id, p); }

private:
    void add(const hd::Path& id, Prim p) {
        hd::Token type = p.type;
        _prims[id] = std::move(p);
        bool isR = type == hd::tokens::mesh() || type == hd::tokens::sphere();
        if (isR) _index->insertRprim(type, this, id);
        else _index->insertSprim(type, this, id);
    }
    const Prim& at(const hd::Path& id) const {
        static const Prim empty;
        auto it = _prims.find(id);
        return it == _prims.end() ? empty : it->second;
    }

    hd::RenderIndex* _index;
    std::map<hd::Path, Prim> _prims;
};

/// A translation matrix, for placing test prims.
inline glm::dmat4 translate(double x, double y, double z) {
    glm::dmat4 m(1.0);
    m[3] = glm::dvec4(x, y, z, 1.0);
    return m;
}

}  // namespace principled::test
