// SPDX-License-Identifier: Apache-2.0
#include "delegate/instancerPrimvars.h"

#include <algorithm>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/primvarUtil.h"

namespace principled::embree {

using namespace hd;

InstancerPrimvars readInstancerPrimvars(const SceneDelegate* delegate, const Path& instancerId,
                                        size_t count, std::vector<std::string>* warnings) {
    // UsdGeomPointInstancer: primvars with vertex, varying or uniform interpolation hold one
    // value per instance.
    auto primvars = std::make_shared<std::vector<PrimvarChannel>>();
    for (Interpolation interp : {Interpolation::Vertex, Interpolation::Varying, Interpolation::Uniform,
                                 Interpolation::Instance})
        for (const auto& d : delegate->getPrimvarDescriptors(instancerId, interp)) {
            std::vector<int> idx;
            std::vector<float> flat;
            int components = 0;
            if (!flattenFloats(delegate->getIndexedPrimvar(instancerId, d.name, &idx), &flat, &components) ||
                components <= 0 || components > 4)
                continue;
            const size_t values = flat.size() / size_t(components);
            const size_t n = idx.empty() ? values : idx.size();
            if (n != count) {
                warnings->push_back("primvar '" + d.name.str() + "' of the instancer has " + std::to_string(n) +
                                    " values for " + std::to_string(count) + " instances; ignored");
                continue;
            }
            PrimvarChannel ch;
            ch.name = d.name;
            ch.components = components;
            ch.perPrimitive = true;
            ch.data.resize(count * size_t(components));
            bool ok = true;
            for (size_t i = 0; i < count && ok; ++i) {
                const size_t v = idx.empty() ? i : size_t(idx[i]);
                ok = idx.empty() || (idx[i] >= 0 && v < values);
                if (ok) std::copy_n(&flat[v * size_t(components)], components, &ch.data[i * size_t(components)]);
            }
            if (ok) primvars->push_back(std::move(ch));
        }
    if (primvars->empty()) return nullptr;
    return primvars;
}

InstancerPrimvars InstancerPrimvarCache::get(const SceneDelegate* delegate, const Path& instancerId,
                                             const std::shared_ptr<const InstancerArrays>& arrays,
                                             size_t count, std::vector<std::string>* warnings) {
    std::shared_ptr<Entry> entry;
    {
        std::lock_guard<std::mutex> lock(_mutex);
        auto& e = _entries[instancerId];
        if (!e) e = std::make_shared<Entry>();
        entry = e;
    }
    std::lock_guard<std::mutex> lock(entry->mutex);
    if (entry->valid && entry->count == count && arrays && entry->arrays.lock() == arrays) {
        InstancerPrimvars kept = entry->primvars.lock();
        if (kept || entry->none) return kept;  // its warnings went out with the read
    }
    ++_reads;
    InstancerPrimvars primvars = readInstancerPrimvars(delegate, instancerId, count, warnings);
    entry->arrays = arrays;
    entry->count = count;
    entry->valid = true;
    entry->primvars = primvars;
    entry->none = !primvars;
    return primvars;
}

long InstancerPrimvarCache::reads() const { return _reads.load(); }

}  // namespace principled::embree
