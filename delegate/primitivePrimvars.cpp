// SPDX-License-Identifier: Apache-2.0
#include "delegate/primitivePrimvars.h"

#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"
#include "delegate/primvarUtil.h"

namespace principled::embree {

using namespace hd;

std::vector<PrimvarChannel> primitivePrimvars(const SceneDelegate* delegate, const Path& id,
                                              size_t primitiveCount, const PrimitiveSource& source,
                                              std::vector<Token>* dropped) {
    std::vector<PrimvarChannel> out;
    for (Interpolation interp : {Interpolation::Constant, Interpolation::Uniform, Interpolation::Varying,
                                 Interpolation::Vertex, Interpolation::FaceVarying}) {
        for (const auto& d : delegate->getPrimvarDescriptors(id, interp)) {
            if (d.name == tokens::points() || d.name == tokens::normals() || d.name == tokens::widths()) continue;
            std::vector<int> indices;
            std::vector<float> flat;
            int components = 0;
            Value v = delegate->getIndexedPrimvar(id, d.name, &indices);
            if (!flattenFloats(v, &flat, &components) || components < 1 || components > 4) continue;
            const size_t values = flat.size() / size_t(components);
            const size_t count = indices.empty() ? values : indices.size();
            auto valueAt = [&](size_t e) -> const float* {
                size_t k = indices.empty() ? e : size_t(indices[e]);
                return k < values ? &flat[k * size_t(components)] : nullptr;
            };
            PrimvarChannel ch;
            ch.name = d.name;
            ch.components = components;
            bool ok = true;
            if (interp == Interpolation::Constant) {
                const float* f = count > 0 ? valueAt(0) : nullptr;
                ok = f != nullptr;
                if (ok) ch.data.assign(f, f + components);
                ch.constant = true;
            } else {
                ch.perPrimitive = true;
                ch.data.resize(primitiveCount * size_t(components));
                for (size_t i = 0; i < primitiveCount && ok; ++i) {
                    size_t e = source(interp, i, count);
                    const float* f = e < count ? valueAt(e) : nullptr;
                    ok = f != nullptr;
                    if (ok) std::copy(f, f + components, &ch.data[i * size_t(components)]);
                }
            }
            if (ok)
                out.push_back(std::move(ch));
            else if (dropped)
                dropped->push_back(d.name);
        }
    }
    return out;
}

}  // namespace principled::embree
