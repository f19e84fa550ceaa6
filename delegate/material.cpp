// SPDX-License-Identifier: Apache-2.0
#include "delegate/material.h"

#include "delegate/hd/sceneDelegate.h"

namespace principled::embree {

using namespace hd;

void Material::sync(SceneDelegate* delegate, RenderParam* renderParam, DirtyBits* bits) {
    auto* param = static_cast<EmbreeRenderParam*>(renderParam);
    if (!_registered) {
        param->add(static_cast<MaterialSource*>(this));
        _registered = true;
    }
    if (*bits & (SprimDirty::MaterialParams | SprimDirty::Resource | SprimDirty::Params)) {
        std::vector<std::string> notes;
        const hd::MaterialNetwork network = delegate->getMaterialResource(id());
        notes = network.problems;
        auto program = std::make_shared<shading::MaterialProgram>(
            shading::MaterialProgram::compile(network, *param->textureCache(), &notes));
        _record.constant = program->constantResult();
        _record.program = program->isConstant() ? nullptr : program;
        _record.mayBePartlyPresent = program->mayBePartlyPresent();
        _record.mayEmit = program->mayEmit();
        _record.hasSurface = program->hasSurface();
        for (const auto& n : notes) param->warn(id(), n);
        param->materialChanged(this);  // its record, in place (a new material: its table too)
    }
    *bits = SprimDirty::Clean;
}

void Material::finalize(RenderParam* renderParam) {
    auto* param = static_cast<EmbreeRenderParam*>(renderParam);
    if (_registered) param->remove(static_cast<MaterialSource*>(this));
    _registered = false;  // remove() rebuilds the material table at the next commit
}

}  // namespace principled::embree
