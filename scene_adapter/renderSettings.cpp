// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/renderSettings.h"

#include <cmath>

#include "scene_adapter/usda/prim.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/usda/value.h"

namespace principled::adapter {

namespace {

// The first target of relationship `name`, "" when none.
std::string target(const usd::Prim& p, const char* name) {
    const usd::Relationship* r = p.relationship(name);
    return r && !r->targets().empty() ? r->targets().front() : std::string();
}

// `resolution` (int2) when authored and usable: 1..32768 each way.
bool resolution(const usd::Prim& p, int* w, int* h, std::vector<std::string>* warnings) {
    const usd::Attribute* a = p.attribute("resolution");
    if (!a || !a->hasValue()) return false;
    const auto v = a->get().getTuple();
    if (!v || v->size() != 2 || !((*v)[0] >= 1 && (*v)[0] <= 32768) || !((*v)[1] >= 1 && (*v)[1] <= 32768)) {
        warnings->push_back(p.path() + ": resolution is not two sizes within 1..32768; ignored");
        return false;
    }
    *w = int(std::lround((*v)[0]));
    *h = int(std::lround((*v)[1]));
    return true;
}

}  // namespace

StageRenderSettings readRenderSettings(const usd::Stage& stage) {
    StageRenderSettings out;
    const usd::Prim* settings = nullptr;
    if (const usd::Value* m = stage.layerMetadata("renderSettingsPrimPath"))
        if (auto path = m->getString(); path && !path->empty()) {
            settings = stage.prim(*path);
            if (!settings || settings->typeName() != "RenderSettings") {
                out.warnings.push_back(*path + ": renderSettingsPrimPath names no RenderSettings prim; ignored");
                settings = nullptr;
            }
        }
    if (!settings)
        for (const usd::Prim* p : stage.traverse())
            if (p->typeName() == "RenderSettings") {
                settings = p;
                break;
            }
    if (!settings) return out;
    out.prim = settings->path();
    out.camera = target(*settings, "camera");
    resolution(*settings, &out.width, &out.height, &out.warnings);
    const std::string productPath = target(*settings, "products");
    if (const usd::Prim* product = productPath.empty() ? nullptr : stage.prim(productPath);
        product && product->typeName() == "RenderProduct") {
        if (std::string c = target(*product, "camera"); !c.empty()) out.camera = c;
        resolution(*product, &out.width, &out.height, &out.warnings);
    }
    return out;
}

}  // namespace principled::adapter
