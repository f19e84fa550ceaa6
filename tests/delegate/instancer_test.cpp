// PointInstancer placement math: scale, then rotation, then translation, then the instancer.
#include "delegate/instancer.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace principled::embree;

TEST(Instancer, ScaleThenRotateThenTranslateThenInstancer) {
    float h = std::sqrt(0.5f);
    glm::vec4 rotZ90(h, 0, 0, h);  // (real, i, j, k): 90 degrees about +Z
    glm::mat4 instancer(1.0f);
    instancer[3] = glm::vec4(0, 0, 5, 1);
    glm::mat4 proto(1.0f);
    proto[3] = glm::vec4(1, 0, 0, 1);  // the prototype's own op comes first
    glm::mat4 m = instanceTransform(instancer, {10, 0, 0}, rotZ90, {2, 1, 1}, proto);
    glm::vec3 p = glm::vec3(m * glm::vec4(0, 0, 0, 1));
    // (0,0,0) -> proto (1,0,0) -> scale (2,0,0) -> rotate (0,2,0) -> translate (10,2,0) -> +z5.
    EXPECT_NEAR(p.x, 10.0f, 1e-5f);
    EXPECT_NEAR(p.y, 2.0f, 1e-5f);
    EXPECT_NEAR(p.z, 5.0f, 1e-5f);
    // A non-unit quaternion is normalised; a zero one means no rotation.
    glm::mat4 z = instanceTransform(glm::mat4(1.0f), {0, 0, 0}, {0, 0, 0, 0}, {1, 1, 1}, glm::mat4(1.0f));
    EXPECT_EQ(z, glm::mat4(1.0f));
    glm::mat4 big = instanceTransform(glm::mat4(1.0f), {0, 0, 0}, 4.0f * rotZ90, {1, 1, 1}, glm::mat4(1.0f));
    EXPECT_NEAR((big * glm::vec4(1, 0, 0, 0)).y, 1.0f, 1e-5f);
}
