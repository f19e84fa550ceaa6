// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/valueConvert.h"

#include "scene_adapter/usda/value.h"

namespace principled::adapter {

namespace {

bool isIntegerType(const std::string& t) {
    return t == "int" || t == "uint" || t == "int64" || t == "uint64" || t == "uchar";
}

}  // namespace

hd::Value toHdValue(const usd::Value& v) {
    using K = usd::Value::Kind;
    const std::string& type = v.typeName();
    switch (v.kind()) {
        case K::Number: {
            if (type == "bool") return hd::Value(*v.getBool());
            if (isIntegerType(type)) return hd::Value(static_cast<int>(*v.getInt()));
            return hd::Value(static_cast<float>(*v.getDouble()));
        }
        case K::Tuple: {
            std::vector<double> t = *v.getTuple();
            if (t.size() == 2) return hd::Value(glm::vec2(t[0], t[1]));
            if (t.size() == 3) return hd::Value(glm::vec3(t[0], t[1], t[2]));
            if (t.size() == 4) return hd::Value(glm::vec4(t[0], t[1], t[2], t[3]));
            if (t.size() == 16) {
                glm::dmat4 m;
                for (int c = 0; c < 4; ++c)
                    for (int r = 0; r < 4; ++r) m[c][r] = t[c * 4 + r];
                return hd::Value(m);
            }
            return {};
        }
        case K::String:
            if (type == "string") return hd::Value(*v.getString());
            return hd::Value(hd::Token(*v.getString()));
        case K::Asset: {
            usd::AssetPath a = *v.getAsset();
            // A missing file is still named where the layer points (it may appear later: texture
            // reloads watch that path), not relative to the working directory.
            if (!a.resolved.empty()) return hd::Value(a.resolved);
            return hd::Value(a.anchored.empty() ? a.authored : a.anchored);
        }
        case K::NumberArray: {
            const std::vector<double>& n = *v.numbers();
            int c = v.components();
            size_t count = c > 0 ? n.size() / size_t(c) : 0;
            if (c == 1) {
                if (isIntegerType(type) || type == "bool") {
                    std::vector<int> out(count);
                    for (size_t i = 0; i < count; ++i) out[i] = static_cast<int>(n[i]);
                    return hd::Value(std::move(out));
                }
                std::vector<float> out(count);
                for (size_t i = 0; i < count; ++i) out[i] = static_cast<float>(n[i]);
                return hd::Value(std::move(out));
            }
            if (c == 2) {
                std::vector<glm::vec2> out(count);
                for (size_t i = 0; i < count; ++i) out[i] = glm::vec2(n[2 * i], n[2 * i + 1]);
                return hd::Value(std::move(out));
            }
            if (c == 3) {
                std::vector<glm::vec3> out(count);
                for (size_t i = 0; i < count; ++i)
                    out[i] = glm::vec3(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
                return hd::Value(std::move(out));
            }
            if (c == 4) {
                std::vector<glm::vec4> out(count);
                for (size_t i = 0; i < count; ++i)
                    out[i] = glm::vec4(n[4 * i], n[4 * i + 1], n[4 * i + 2], n[4 * i + 3]);
                return hd::Value(std::move(out));
            }
            return {};
        }
        case K::StringArray: {
            std::vector<hd::Token> out;
            for (const auto& s : *v.strings()) out.emplace_back(s);
            return hd::Value(std::move(out));
        }
        default: return {};
    }
}

}  // namespace principled::adapter
