// SPDX-License-Identifier: Apache-2.0
// Render settings: named values a host sets on a render delegate, with descriptors it can list.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "delegate/hd/token.h"
#include "delegate/hd/value.h"

namespace principled::hd {

struct RenderSettingDescriptor {
    std::string name;   ///< display name
    Token key;
    Value defaultValue;
    std::string help;
};

using RenderSettingsMap = std::map<Token, Value>;

}  // namespace principled::hd
