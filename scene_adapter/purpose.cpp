// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/purpose.h"

#include <string>

#include "scene_adapter/lightTypes.h"
#include "scene_adapter/usda/stage.h"

namespace principled::adapter {

bool renderPurpose(const usd::Prim& prim, double time) {
    const std::string& type = prim.typeName();
    if (type == "Material" || type == "Camera" || !lightTypeOf(type).empty()) return true;
    for (const usd::Prim* p = &prim; p && p->path() != "/"; p = p->parent())
        if (const usd::Attribute* a = p->attribute("purpose"); a && a->hasValue()) {
            const std::string purpose = a->get(time).getString().value_or("default");
            return purpose != "guide" && purpose != "proxy";
        }
    return true;
}

}  // namespace principled::adapter
