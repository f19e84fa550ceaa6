// Framing: the UsdRender conform policies on the camera's screen window, and the pixels a data
// window covers.
#include <gtest/gtest.h>

#include "delegate/hd/camera.h"
#include "delegate/hd/framing.h"

using principled::hd::Camera;
using principled::hd::Framing;
using principled::hd::Path;

namespace {

// A 2:1 aperture (20 x 10 tenths of a unit) with a 50-tenths lens: the window at unit distance
// is 0.4 x 0.2 before conforming.
Camera wideCamera() {
    Camera c{Path("/cam")};
    c.set(glm::dmat4(1.0), 5.0f, 2.0f, 1.0f);
    return c;
}

void expectWindow(const glm::vec4& w, float width, float height) {
    EXPECT_NEAR(w.y - w.x, width, 1e-6f);
    EXPECT_NEAR(w.w - w.z, height, 1e-6f);
    EXPECT_NEAR(w.x + w.y, 0.0f, 1e-6f);  // centred (no aperture offset)
    EXPECT_NEAR(w.z + w.w, 0.0f, 1e-6f);
}

}  // namespace

TEST(Framing, ConformPoliciesFollowUsdRender) {
    // The 2:1 aperture on a square image: expand grows the height (all of the aperture seen),
    // crop shrinks the width (the image filled), the adjust policies keep one side each, and
    // adjustPixelAspectRatio keeps the aperture (pixels become 2:1).
    const Camera c = wideCamera();
    using C = Framing::Conform;
    expectWindow(c.screenWindow(1.0, C::ExpandAperture), 0.4f, 0.4f);
    expectWindow(c.screenWindow(1.0, C::CropAperture), 0.2f, 0.2f);
    expectWindow(c.screenWindow(1.0, C::AdjustApertureWidth), 0.2f, 0.2f);
    expectWindow(c.screenWindow(1.0, C::AdjustApertureHeight), 0.4f, 0.4f);
    expectWindow(c.screenWindow(1.0, C::AdjustPixelAspectRatio), 0.4f, 0.2f);
    // A 4:1 image (wider than the aperture): expand grows the width, crop cuts the height.
    expectWindow(c.screenWindow(4.0, C::ExpandAperture), 0.8f, 0.2f);
    expectWindow(c.screenWindow(4.0, C::CropAperture), 0.4f, 0.1f);
    expectWindow(c.screenWindow(4.0, C::AdjustApertureWidth), 0.8f, 0.2f);
    expectWindow(c.screenWindow(4.0, C::AdjustApertureHeight), 0.4f, 0.1f);
    // The default is expandAperture (the renderer's behaviour before framing existed).
    expectWindow(c.screenWindow(1.0), 0.4f, 0.4f);
    // Pixel aspect ratio 2 on a 16 x 32 image is a 1:1 picture: the same window as a square image.
    Framing f;
    f.pixelAspectRatio = 2.0f;
    expectWindow(c.screenWindow(16, 32, f), 0.4f, 0.4f);
}

TEST(Framing, DataWindowCoversThePixelsWhoseCentresItHolds) {
    Framing f;
    EXPECT_EQ(f.pixelRect(16, 8), glm::ivec4(0, 0, 16, 8));  // the fallback: every pixel
    // The top-left quadrant: NDC (0, 0.5)-(0.5, 1), (0, 0) being the bottom left.
    f.dataWindowNDC = {0.0f, 0.5f, 0.5f, 1.0f};
    EXPECT_EQ(f.pixelRect(16, 8), glm::ivec4(0, 0, 8, 4));
    // Windows that tile the unit square cover each pixel once, even with edges on pixel centres:
    // on 10 pixels, 0.25 puts an edge on centre 2 (2.5 / 10).
    for (int w : {10, 11, 16}) {
        std::vector<int> covered(size_t(w), 0);
        for (auto [a, b] : {std::pair{0.0f, 0.25f}, {0.25f, 0.7f}, {0.7f, 1.0f}}) {
            f.dataWindowNDC = {a, 0.0f, b, 1.0f};
            const glm::ivec4 r = f.pixelRect(w, 1);
            for (int x = r.x; x < r.z; ++x) ++covered[size_t(x)];
        }
        for (int x = 0; x < w; ++x) EXPECT_EQ(covered[size_t(x)], 1) << w << " " << x;
    }
    f.dataWindowNDC = {0.0f, 0.0f, 0.25f, 1.0f};
    EXPECT_EQ(f.pixelRect(10, 1), glm::ivec4(0, 0, 2, 1));  // centres 0.05, 0.15 (0.25 is excluded)
    // Rows: the window's bottom edge at 0.25 of 4 rows takes row 3 (centre 0.125) out.
    f.dataWindowNDC = {0.0f, 0.25f, 1.0f, 1.0f};
    EXPECT_EQ(f.pixelRect(1, 4), glm::ivec4(0, 0, 1, 3));
    // A window thinner than a pixel between two centres covers nothing; outside the image is clipped.
    f.dataWindowNDC = {0.11f, 0.0f, 0.14f, 1.0f};
    const glm::ivec4 r = f.pixelRect(10, 1);
    EXPECT_EQ(r.z - r.x, 0);
    f.dataWindowNDC = {-0.5f, -0.5f, 1.5f, 1.5f};
    EXPECT_EQ(f.pixelRect(16, 8), glm::ivec4(0, 0, 16, 8));
}
