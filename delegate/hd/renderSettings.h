// SPDX-License-Identifier: Apache-2.0
// Render settings: named values a host sets on a render delegate, with descriptors it can list.
#pragma once

#include <cmath>
#include <limits>
#include <map>
#include <sstream>
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
    /// A word setting's allowed words (empty: any word).
    std::vector<std::string> choices = {};
    /// A number setting's allowed range (finite numbers only).
    double minValue = -std::numeric_limits<double>::infinity();
    double maxValue = std::numeric_limits<double>::infinity();
};

/// What is wrong with `value` for the setting `d` ("" when it is allowed): a word not among
/// d.choices, a number outside [d.minValue, d.maxValue] or not finite.
inline std::string renderSettingProblem(const RenderSettingDescriptor& d, const Value& value) {
    if (auto s = getString(value); s && !d.choices.empty()) {
        for (const auto& c : d.choices)
            if (*s == c) return "";
        std::string list;
        for (const auto& c : d.choices) list += (list.empty() ? "" : ", ") + c;
        return "must be one of " + list + ", not '" + *s + "'";
    }
    if (auto f = getFloat(value)) {
        double v = double(*f);
        if (const int* i = std::get_if<int>(&value)) v = double(*i);
        if (!std::isfinite(v)) return "must be a finite number";
        if (v < d.minValue || v > d.maxValue) {
            std::ostringstream s;
            if (std::isinf(d.maxValue)) s << "must be at least " << d.minValue;
            else if (std::isinf(d.minValue)) s << "must be at most " << d.maxValue;
            else s << "must be between " << d.minValue << " and " << d.maxValue;
            return s.str();
        }
    }
    return "";
}

using RenderSettingsMap = std::map<Token, Value>;

}  // namespace principled::hd
