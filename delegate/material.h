// SPDX-License-Identifier: Apache-2.0
// Material: the material sprim. Pulls its shading network from the scene delegate and maps it
// to a MaterialRecord; a parameter edit never touches geometry.
#pragma once

#include "delegate/hd/prim.h"
#include "delegate/renderParam.h"

namespace principled::embree {

class Material : public hd::Sprim, public MaterialSource {
public:
    using Sprim::Sprim;
    void sync(hd::SceneDelegate* delegate, hd::RenderParam* param, hd::DirtyBits* bits) override;
    void finalize(hd::RenderParam* param) override;

    const hd::Path& materialId() const override { return id(); }
    const MaterialRecord& record() const override { return _record; }

private:
    MaterialRecord _record;
    bool _registered = false;
};

}  // namespace principled::embree
