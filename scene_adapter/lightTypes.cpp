// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/lightTypes.h"

namespace principled::adapter {

hd::Token lightTypeOf(const std::string& type) {
    using namespace hd;
    if (type == "DistantLight") return tokens::distantLight();
    if (type == "DomeLight" || type == "DomeLight_1") return tokens::domeLight();
    if (type == "SphereLight") return tokens::sphereLight();
    if (type == "RectLight") return tokens::rectLight();
    if (type == "DiskLight") return tokens::diskLight();
    if (type == "CylinderLight") return tokens::cylinderLight();
    if (type == "PortalLight") return tokens::portalLight();
    return Token();
}

}  // namespace principled::adapter
