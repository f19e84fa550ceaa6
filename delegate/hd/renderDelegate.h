// SPDX-License-Identifier: Apache-2.0
// RenderDelegate: the renderer side of the render index. Creates prims and passes, owns the
// renderer's resources and commits them once per frame (Hydra's HdRenderDelegate).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "delegate/hd/aov.h"
#include "delegate/hd/prim.h"
#include "delegate/hd/renderBuffer.h"
#include "delegate/hd/renderPass.h"
#include "delegate/hd/renderSettings.h"

namespace principled::hd {

class ChangeTracker;
class RenderIndex;

class RenderDelegate {
public:
    virtual ~RenderDelegate() = default;

    virtual const std::vector<Token>& supportedRprimTypes() const = 0;
    virtual const std::vector<Token>& supportedSprimTypes() const = 0;
    virtual const std::vector<Token>& supportedBprimTypes() const = 0;

    virtual std::unique_ptr<Rprim> createRprim(const Token& typeId, const Path& id) = 0;
    virtual std::unique_ptr<Sprim> createSprim(const Token& typeId, const Path& id) = 0;
    virtual std::unique_ptr<Bprim> createBprim(const Token& typeId, const Path& id) = 0;
    virtual std::unique_ptr<RenderPass> createRenderPass(RenderIndex* index) = 0;

    virtual RenderParam* renderParam() = 0;
    /// Called once per sync before the dirty rprims sync (in parallel): prims[i] will sync
    /// through delegates[i] with bits[i]. For plans that need every rprim at once (a
    /// scene-wide budget). Rprims the plan changes go into *alsoSync with the bits to sync
    /// them with (added to this sync, or to the bits of one already in it); while it adds any,
    /// the render index calls it again with the extended lists. The default does nothing.
    virtual void prepareRprimSync(const std::vector<Rprim*>& prims, const std::vector<SceneDelegate*>& delegates,
                                  const std::vector<DirtyBits>& bits,
                                  std::vector<std::pair<Rprim*, DirtyBits>>* alsoSync) {
        (void)prims, (void)delegates, (void)bits, (void)alsoSync;
    }
    /// Called once after every sync: build acceleration structures, upload, etc.
    virtual void commitResources(ChangeTracker* tracker) = 0;

    virtual AovDescriptor defaultAovDescriptor(const Token& aovName) const = 0;

    virtual std::vector<RenderSettingDescriptor> renderSettingDescriptors() const = 0;
    virtual void setRenderSetting(const Token& key, const Value& value) = 0;
    virtual Value renderSetting(const Token& key) const = 0;
    /// Bumped by every setRenderSetting() that changes a value; passes restart on a change.
    virtual unsigned renderSettingsVersion() const = 0;

    /// Counters and timings (rays, samples, BVH builds, seconds) for tests and --stats.
    virtual std::map<std::string, double> renderStats() const = 0;
};

}  // namespace principled::hd
