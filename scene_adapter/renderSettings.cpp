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
    const usd::Value value = a->get();
    const auto v = value.getTuple();
    if (value.typeName() != "int2" || !v || v->size() != 2 || !((*v)[0] >= 1 && (*v)[0] <= 32768) || !((*v)[1] >= 1 && (*v)[1] <= 32768)) {
        warnings->push_back(p.path() + ": resolution is not an int2 of sizes within 1..32768; ignored");
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
    if (settings && (!settings->isActive() || !settings->isDefined() || settings->isAbstract())) {
        out.warnings.push_back(settings->path() + ": renderSettingsPrimPath names an inactive or undefined prim; ignored");
        settings = nullptr;
    }
    if (!settings)
        for (const usd::Prim* p : stage.traverse())  // active, defined, not abstract
            if (p->typeName() == "RenderSettings") {
                settings = p;
                break;
            }
    if (!settings) return out;
    out.prim = settings->path();
    out.camera = target(*settings, "camera");
    // UsdRenderSettingsBase's fallback resolution when the prim authors none.
    out.width = 2048, out.height = 1080;
    resolution(*settings, &out.width, &out.height, &out.warnings);
    auto ignored = [&](const usd::Prim& p) {
        for (const char* name : {"pixelAspectRatio", "aspectRatioConformPolicy", "dataWindowNDC"})
            if (const usd::Attribute* a = p.attribute(name); a && a->hasValue())
                out.warnings.push_back(p.path() + ": " + name +
                                       " is not supported (square pixels, the camera's aperture expanded to the image)");
    };
    ignored(*settings);
    const std::string productPath = target(*settings, "products");
    if (!productPath.empty()) {
        const usd::Prim* product = stage.prim(productPath);
        if (product && product->typeName() == "RenderProduct" && product->isActive() && product->isDefined()) {
            if (std::string c = target(*product, "camera"); !c.empty()) out.camera = c;
            resolution(*product, &out.width, &out.height, &out.warnings);
            ignored(*product);
        } else {
            out.warnings.push_back(settings->path() + ": products <" + productPath +
                                   "> is not an active RenderProduct; ignored");
        }
    }
    return out;
}

}  // namespace principled::adapter
