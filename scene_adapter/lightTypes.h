// SPDX-License-Identifier: Apache-2.0
// Which UsdLux prim types the adapter maps onto light sprims.
#pragma once

#include <string>

#include "delegate/hd/tokens.h"

namespace principled::adapter {

/// The light sprim type of a UsdLux prim type name (DistantLight, DomeLight, DomeLight_1,
/// SphereLight, RectLight, DiskLight, CylinderLight, PortalLight); empty for anything else.
hd::Token lightTypeOf(const std::string& type);

}  // namespace principled::adapter
