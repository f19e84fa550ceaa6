// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/renderSettings.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

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

// The authored value of attribute `name`, null when there is none.
const usd::Attribute* authored(const usd::Prim& p, const char* name) {
    const usd::Attribute* a = p.attribute(name);
    return a && a->hasValue() ? a : nullptr;
}

// UsdRenderSettingsBase's framing attributes authored on p, over what `out` holds (a product's
// over its settings'): pixelAspectRatio, aspectRatioConformPolicy and dataWindowNDC. Values
// with no meaning are warned about and leave `out` as it was.
void framing(const usd::Prim& p, hd::Framing* out, std::vector<std::string>* warnings) {
    if (const usd::Attribute* a = authored(p, "pixelAspectRatio")) {
        const auto v = a->get().getDouble();
        if (v && hd::Framing::validPixelAspectRatio(*v))
            out->pixelAspectRatio = float(*v);
        else
            warnings->push_back(p.path() + ": pixelAspectRatio must be a number from 1e-4 to 1e4; ignored");
    }
    if (const usd::Attribute* a = authored(p, "aspectRatioConformPolicy")) {
        const auto token = a->get().getString();
        if (const auto policy = hd::Framing::conformFromToken(token.value_or("")))
            out->conform = *policy;
        else
            warnings->push_back(p.path() + ": aspectRatioConformPolicy '" + token.value_or("") + "' is not " +
                                hd::Framing::kConformTokens + "; ignored");
    }
    if (const usd::Attribute* a = authored(p, "dataWindowNDC")) {
        const auto v = a->get().getTuple();
        const bool ok = v && v->size() == 4 && std::all_of(v->begin(), v->end(), [](double x) { return std::isfinite(x); }) &&
                        (*v)[0] < (*v)[2] && (*v)[1] < (*v)[3];
        if (!ok) {
            warnings->push_back(p.path() + ": dataWindowNDC must be a float4 (xmin, ymin, xmax, ymax) with min < max; ignored");
        } else {
            const glm::vec4 w{float((*v)[0]), float((*v)[1]), float((*v)[2]), float((*v)[3])};
            const glm::vec4 clipped = glm::clamp(w, glm::vec4(0.0f), glm::vec4(1.0f));
            if (!(clipped.x < clipped.z && clipped.y < clipped.w)) {
                warnings->push_back(p.path() + ": dataWindowNDC covers no part of the image (overscan is not "
                                               "supported); ignored");
            } else {
                if (clipped != w)
                    warnings->push_back(p.path() + ": dataWindowNDC reaches outside (0, 0, 1, 1); overscan is not "
                                                   "supported, the window is clipped to the image");
                out->dataWindowNDC = clipped;
            }
        }
    }
}

// A token[] attribute's values when authored as one.
std::optional<std::vector<std::string>> tokens(const usd::Prim& p, const char* name, std::vector<std::string>* warnings) {
    const usd::Attribute* a = authored(p, name);
    if (!a) return std::nullopt;
    const usd::Value v = a->get();
    if (const std::vector<std::string>* t = v.strings()) return *t;
    warnings->push_back(p.path() + ": " + name + " is not a token[]; ignored");
    return std::nullopt;
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
    framing(*settings, &out.framing, &out.warnings);
    if (auto t = tokens(*settings, "includedPurposes", &out.warnings)) out.includedPurposes = *t;
    if (auto t = tokens(*settings, "materialBindingPurposes", &out.warnings)) {
        out.materialBindingPurposes.clear();  // the schema allows "full", "preview" and ""
        for (const std::string& purpose : *t) {
            if (purpose == "full" || purpose == "preview" || purpose.empty()) out.materialBindingPurposes.push_back(purpose);
            else out.warnings.push_back(settings->path() + ": materialBindingPurposes '" + purpose +
                                        "' is not full, preview or \"\"; ignored");
        }
    }
    if (const usd::Attribute* a = authored(*settings, "disableDepthOfField"))
        out.disableDepthOfField = a->get().getBool().value_or(false);
    if (const usd::Relationship* r = settings->relationship("products"); r && r->targets().size() > 1)
        out.warnings.push_back(settings->path() + ": " + std::to_string(r->targets().size()) +
                               " products; only the first, <" + r->targets().front() + ">, is rendered");
    const std::string productPath = target(*settings, "products");
    if (!productPath.empty()) {
        const usd::Prim* product = stage.prim(productPath);
        if (product && product->typeName() == "RenderProduct" && product->isActive() && product->isDefined()) {
            if (std::string c = target(*product, "camera"); !c.empty()) out.camera = c;
            if (const usd::Relationship* vars = product->relationship("orderedVars"); vars && !vars->targets().empty())
                out.warnings.push_back(product->path() + ": orderedVars (RenderVars) are not written; ask for AOVs with "
                                                         "--aov (principled render --aov all lists them)");
            resolution(*product, &out.width, &out.height, &out.warnings);
            framing(*product, &out.framing, &out.warnings);
        } else {
            out.warnings.push_back(settings->path() + ": products <" + productPath +
                                   "> is not an active RenderProduct; ignored");
        }
    }
    return out;
}

}  // namespace principled::adapter
