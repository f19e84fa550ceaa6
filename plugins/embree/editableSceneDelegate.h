// SPDX-License-Identifier: Apache-2.0
// EditableSceneDelegate: the USD scene adapter plus a layer of host edits. The composed stage
// is immutable, so edits are kept as overrides this delegate answers before the adapter, and
// each edit marks exactly the dirty bits Hydra would (material params, light params, points,
// primvars, transforms). Prims are inserted with this delegate as their scene delegate.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "delegate/hd/renderIndex.h"
#include "delegate/hd/sceneDelegate.h"
#include "scene_adapter/usdSceneDelegate.h"

namespace principled::plugins {

/// What a host edit did.
struct EditResult {
    enum class Code { Applied, NotFound, Unsupported, BadValue } code = Code::Applied;
    std::string message;  ///< why it was not applied
};

/// A value a host writes: numbers (scalars, tuples, matrices, flat arrays) or a string.
struct EditValue {
    std::vector<double> numbers;
    std::string text;
    bool isText = false;
};

class EditableSceneDelegate : public hd::SceneDelegate {
  public:
    /// The stage must outlive the delegate.
    EditableSceneDelegate(const usd::Stage& stage, const adapter::AdapterOptions& options = {});
    ~EditableSceneDelegate() override;

    /// Inserts the prims the adapter would insert, with this delegate as their scene delegate.
    void populate(hd::RenderIndex* index);
    hd::Path addDefaultCamera(hd::RenderIndex* index, double aspect);
    const std::vector<hd::Path>& cameras() const { return _base.cameras(); }
    const std::vector<std::string>& warnings() const { return _base.warnings(); }

    /// Overrides `attribute` of `primPath` and marks the prims it affects dirty in `index`.
    /// Supported: shader inputs of a bound material network ("inputs:*"), light inputs,
    /// camera parameters, on geometry "points", "normals", "primvars:*", "doubleSided", and
    /// "xformOp:*" values of any prim (setXformOp).
    EditResult setAttribute(hd::RenderIndex* index, const std::string& primPath,
                            const std::string& attribute, const EditValue& value);
    /// Sets one op of the prim's xformOpOrder ("xformOp:translate", "xformOp:rotateXYZ:pivot")
    /// and re-evaluates its local transform; marks like setLocalTransform.
    EditResult setXformOp(hd::RenderIndex* index, const std::string& primPath,
                          const std::string& attribute, const EditValue& value);
    /// Replaces the local transform of `primPath` (USD order: 16 values, translation in
    /// 12..14) and marks every rprim, camera and light at or below it.
    EditResult setLocalTransform(hd::RenderIndex* index, const std::string& primPath,
                                 const double matrix[16]);

    hd::MeshTopology getMeshTopology(const hd::Path& id) const override;
    hd::SubdivTags getSubdivTags(const hd::Path& id) const override;
    glm::dmat4 getTransform(const hd::Path& id) const override;
    bool getVisible(const hd::Path& id) const override;
    bool getDoubleSided(const hd::Path& id) const override;
    hd::Value get(const hd::Path& id, const hd::Token& key) const override;
    hd::Value getIndexedPrimvar(const hd::Path& id, const hd::Token& key,
                                std::vector<int>* indices) const override;
    std::vector<hd::PrimvarDescriptor> getPrimvarDescriptors(
        const hd::Path& id, hd::Interpolation interp) const override;
    hd::Path getMaterialId(const hd::Path& id) const override;
    std::vector<std::pair<hd::Path, std::vector<int>>> getMaterialSubsets(
        const hd::Path& id) const override;
    hd::Path getInstancerId(const hd::Path& id) const override { return _base.getInstancerId(id); }
    std::vector<int> getInstanceIndices(const hd::Path& instancerId,
                                        const hd::Path& prototypeId) const override {
        return _base.getInstanceIndices(instancerId, prototypeId);
    }
    hd::MaterialNetwork getMaterialResource(const hd::Path& materialId) const override;
    hd::Value getLightParamValue(const hd::Path& id, const hd::Token& param) const override;
    hd::Value getCameraParamValue(const hd::Path& id, const hd::Token& param) const override;

  private:
    struct Inserted {
        bool isRprim = false;
        hd::Token type;
        hd::Path id;
    };
    const hd::Value* override(const hd::Path& id, const std::string& attribute) const;
    glm::dmat4 worldTransform(const std::string& primPath) const;
    void markTransformDirty(hd::RenderIndex* index, const std::string& primPath);

    const usd::Stage& _stage;
    adapter::UsdSceneDelegate _base;
    double _time;
    std::vector<Inserted> _inserted;
    std::map<hd::Path, std::map<std::string, hd::Value>> _overrides;
    std::map<std::string, glm::dmat4> _localOverrides;  ///< prim path -> local matrix
    std::map<std::string, std::map<std::string, hd::Value>> _opOverrides;  ///< prim -> op -> value
};

}  // namespace principled::plugins
