// SPDX-License-Identifier: Apache-2.0
// lambertPlaneScene: USDA text of a large Lambertian plane seen through a tiny orthographic
// camera, for tests that compare rendered radiance with closed-form irradiance.
#pragma once

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "plugins/renderSession.h"

namespace principled::test {

// A Lambert plane (y = 0, facing +Y) seen by a tiny orthographic camera aimed at the origin,
// tilted by `tilt` degrees from straight down (so it can look past a light in the way), plus
// the given light prims. Render with the UE4 model so the diffuse is exactly Lambertian at
// any view angle. ior and roughness make the plane glossy (ior 1: no specular lobe).
inline std::string planeScene(double albedo, const std::string& lights, double tilt = 0.0, double ior = 1.0,
                              double roughness = 1.0) {
    double rad = tilt * 3.14159265358979323846 / 180.0;
    char head[2048];
    std::snprintf(head, sizeof head, R"(#usda 1.0
def Mesh "Plane" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(-50, 0, -50), (-50, 0, 50), (50, 0, 50), (50, 0, -50)]
    rel material:binding = </Mat>
}
def Material "Mat"
{
    token outputs:surface.connect = </Mat/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (%g, %g, %g)
        float inputs:ior = %g
        float inputs:roughness = %g
        token outputs:surface
    }
}
def Camera "Cam"
{
    token projection = "orthographic"
    float horizontalAperture = 0.01
    float verticalAperture = 0.01
    float2 clippingRange = (0.001, 1000)
    double3 xformOp:translate = (0, %g, %g)
    float xformOp:rotateX = %g
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)",
                  albedo, albedo, albedo, ior, roughness, 50.0 * std::cos(rad), 50.0 * std::sin(rad), -90.0 + tilt);
    return std::string(head) + lights;
}

/// The red values of the 4 x 4 pixels of planeScene's camera (each an independent estimate of
/// the plane's radiance), rendered with the UE4 model (exactly Lambertian diffuse) and the given
/// seed; maxDepth > 0 overrides the session's path depth.
inline std::vector<double> planePixels(const std::string& usda, int spp,
                                       std::map<std::string, std::string> settings = {}, int maxDepth = 0,
                                       int seed = 0) {
    host::SessionOptions o;
    o.width = o.height = 4;
    o.samplesPerPixel = spp;
    o.seed = seed;
    if (maxDepth > 0) o.maxDepth = maxDepth;
    o.settings = std::move(settings);
    o.settings["shadingModel"] = "ue4";
    auto s = host::RenderSession::openString(usda, "plane.usda", o);
    while (!s->step()) {
    }
    const float* c = s->color();
    std::vector<double> v(16);
    for (int i = 0; i < 16; ++i) v[i] = c[4 * i];
    return v;
}

/// The mean of planePixels(): the plane's radiance.
inline double planeRadiance(const std::string& usda, int spp,
                            std::map<std::string, std::string> settings = {}, int maxDepth = 0) {
    double sum = 0.0;
    for (double v : planePixels(usda, spp, std::move(settings), maxDepth)) sum += v;
    return sum / 16.0;
}

}  // namespace principled::test
