// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/purpose.h"

#include <algorithm>
#include <string>

#include "scene_adapter/lightTypes.h"
#include "scene_adapter/usda/stage.h"

namespace principled::adapter {

bool renderPurpose(const usd::Prim& prim, double time, const std::vector<std::string>& included) {
    const std::string& type = prim.typeName();
    if (type == "Material" || type == "Camera" || !lightTypeOf(type).empty()) return true;
    std::string purpose = "default";
    for (const usd::Prim* p = &prim; p && p->path() != "/"; p = p->parent())
        if (const usd::Attribute* a = p->attribute("purpose"); a && a->hasValue()) {
            purpose = a->get(time).getString().value_or("default");
            break;
        }
    return std::find(included.begin(), included.end(), purpose) != included.end();
}

}  // namespace principled::adapter
