// SPDX-License-Identifier: Apache-2.0
// OrthoRender: a delegate, render index, test scene and colour buffer set up for the estimator
// comparisons (meshLightSampling_test, neeAllLights_test): build the scene, then render it to
// convergence through an orthographic camera looking down -Z and read the red channel.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "delegate/renderPass.h"
#include "tests/support/testSceneDelegate.h"

namespace principled::test {

struct OrthoRender {
    embree::EmbreeRenderDelegate delegate;
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    embree::EmbreeRenderBuffer* color = nullptr;
    std::unique_ptr<hd::RenderPass> pass;
    int width, height;

    /// settings: render settings by name (convergedSamplesPerPixel, seed, maxDepth, ...).
    OrthoRender(int w, int h, const std::vector<std::pair<std::string, hd::Value>>& settings)
        : width(w), height(h) {
        index.insertBprim(hd::tokens::renderBuffer(), &scene, hd::Path("/color"));
        color = static_cast<embree::EmbreeRenderBuffer*>(index.bprim(hd::tokens::renderBuffer(), hd::Path("/color")));
        color->allocate(w, h, hd::Format::Float32Vec4, true);
        pass = delegate.createRenderPass(&index);
        for (const auto& [name, value] : settings) delegate.setRenderSetting(hd::Token(name), value);
    }

    /// Adds the camera at height z over the origin (a square aperture in scene units), renders
    /// to convergence and returns the red channel.
    std::vector<float> redFromAbove(double z, float aperture) {
        scene.addCamera(hd::Path("/cam"), translate(0, 0, z),
                        {{hd::Token("projection"), hd::Value(hd::Token("orthographic"))},
                         {hd::Token("horizontalAperture"), hd::Value(aperture)},
                         {hd::Token("verticalAperture"), hd::Value(aperture)}});
        index.sync();
        hd::RenderPassState s{hd::Path("/cam"), width, height, {{hd::tokens::color(), color}}};
        do pass->execute(s);
        while (!pass->isConverged());
        const float* p = static_cast<const float*>(color->map());
        std::vector<float> red(size_t(width) * height);
        for (size_t i = 0; i < red.size(); ++i) red[i] = p[4 * i];
        return red;
    }
};

}  // namespace principled::test
