// SPDX-License-Identifier: Apache-2.0
// SceneDelegate: the pull interface a scene adapter serves. Prims call it during sync for the
// data their dirty bits name (Hydra's HdSceneDelegate, hydra.md section 2.5).
#pragma once

#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "delegate/hd/materialNetwork.h"
#include "delegate/hd/meshTopology.h"
#include "delegate/hd/path.h"
#include "delegate/hd/primvar.h"
#include "delegate/hd/tokens.h"
#include "delegate/hd/value.h"

namespace principled::hd {

/// A PointInstancer's per-instance arrays (absent: not authored).
struct InstancerArrays {
    std::optional<std::vector<glm::vec3>> translations, scales;
    std::optional<std::vector<glm::vec4>> rotations;  ///< (real, i, j, k)
    std::optional<std::vector<glm::dmat4>> transforms;  ///< native instancing: whole matrices
};

/// An instancer's arrays from its values by key (tokens::instanceTranslations() ...).
template <class Get>
std::shared_ptr<InstancerArrays> readInstancerArrays(Get&& get) {
    auto a = std::make_shared<InstancerArrays>();
    auto take = [&](const Token& key, auto* out) {
        Value v = get(key);
        using V = typename std::remove_pointer_t<decltype(out)>::value_type;
        if (auto* x = std::get_if<V>(&v)) *out = std::move(*x);
    };
    take(tokens::instanceTranslations(), &a->translations);
    take(tokens::instanceRotations(), &a->rotations);
    take(tokens::instanceScales(), &a->scales);
    take(tokens::instanceTransforms(), &a->transforms);
    return a;
}

/// Answers queries about the prims it inserted into a render index. Every method may be called
/// concurrently from rprim sync workers, so implementations must be safe for concurrent reads.
class SceneDelegate {
public:
    virtual ~SceneDelegate() = default;

    virtual MeshTopology getMeshTopology(const Path& id) const = 0;
    virtual SubdivTags getSubdivTags(const Path& id) const = 0;
    /// Object-to-world, column-vector convention (glm): p_world = M * p_object.
    virtual glm::dmat4 getTransform(const Path& id) const = 0;
    virtual bool getVisible(const Path& id) const = 0;
    virtual bool getDoubleSided(const Path& id) const = 0;
    /// A named value: geometry ("points", "radius"), primvars by name.
    virtual Value get(const Path& id, const Token& key) const = 0;
    /// An indexed primvar: values plus indices (indices empty if not indexed).
    virtual Value getIndexedPrimvar(const Path& id, const Token& key,
                                    std::vector<int>* indices) const = 0;
    virtual std::vector<PrimvarDescriptor> getPrimvarDescriptors(const Path& id,
                                                                 Interpolation interp) const = 0;
    /// The material bound to an rprim (empty path: none).
    virtual Path getMaterialId(const Path& id) const = 0;
    /// Per-face material assignments (GeomSubset); each pair is (material, face indices).
    virtual std::vector<std::pair<Path, std::vector<int>>> getMaterialSubsets(const Path& id) const {
        (void)id;
        return {};
    }
    virtual MaterialNetwork getMaterialResource(const Path& materialId) const = 0;
    /// Instancing (UsdGeomPointInstancer, hydra.md section 1.5): the instancer that draws rprim
    /// `id` (empty: the rprim is drawn on its own). An instanced rprim's getTransform() is
    /// relative to the instancer; the instancer's own transform is getTransform(instancerId),
    /// and its per-instance arrays are get(instancerId, tokens::instanceTranslations()...).
    virtual Path getInstancerId(const Path& id) const {
        (void)id;
        return Path();
    }
    /// An instancer's per-instance arrays at once, shared by its prototypes (each prototype rprim
    /// reads them when it syncs: a PointInstancer with P prototypes and N instances must not cost
    /// P x N). The default reads get(); scene delegates may keep the result until an edit.
    virtual std::shared_ptr<const InstancerArrays> getInstancerArrays(const Path& instancerId) const {
        return readInstancerArrays([&](const Token& key) { return get(instancerId, key); });
    }
    /// The instances of `instancerId` that draw prototype rprim `prototypeId`: indices into
    /// the instancer's arrays, invisible instances already left out.
    virtual std::vector<int> getInstanceIndices(const Path& instancerId, const Path& prototypeId) const {
        (void)instancerId;
        (void)prototypeId;
        return {};
    }
    /// Light parameters by USD input name without the "inputs:" prefix ("intensity", "color").
    virtual Value getLightParamValue(const Path& id, const Token& param) const = 0;
    /// Light linking (Hydra's categories): the categories an rprim belongs to. A light whose
    /// getLightParamValue(id, "lightLink") names a category lights only the rprims in it; a
    /// light without one lights every rprim.
    virtual std::vector<Token> getCategories(const Path& id) const {
        (void)id;
        return {};
    }
    /// Camera parameters in scene units (apertures already converted from tenths of a unit).
    virtual Value getCameraParamValue(const Path& id, const Token& param) const = 0;
};

}  // namespace principled::hd
