// SPDX-License-Identifier: Apache-2.0
// Kernel-facing scene records: plain structs the integrator reads during rendering. Built at
// sync/commit time from Hydra prims; no hd types, no locks, read-only while a pass runs.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "bsdf/bsdf.h"
#include "delegate/distribution2d.h"
#include "delegate/hd/token.h"
#include "delegate/lightShaping.h"
#include "delegate/portalSampling.h"
#include "delegate/shading/materialProgram.h"

namespace principled::embree {

/// A shading material: a compiled UsdPreviewSurface program, or its constant result.
struct MaterialRecord {
    shading::ShadedMaterial constant;                        ///< used when program is null
    std::shared_ptr<const shading::MaterialProgram> program;  ///< non-null when textured
    bool mayBePartlyPresent = false;  ///< opacity < 1 somewhere: shadow rays must evaluate it
    bool mayEmit = false;  ///< constant emission != 0, or emissiveColor textured (MaterialProgram::mayEmit)
    /// False without a surface shader this renderer reads: its geometry uses displayColor.
    bool hasSurface = true;
};

/// One primvar of a mesh: by default three values per triangle (one per corner); or one value
/// (constant), one per Embree primitive (perPrimitive: a point, a curve segment, a triangle of
/// a uniform primvar), or one per point indexed through GeometryRecord::triangles (perVertex:
/// vertex and varying primvars of refined meshes, no per-corner copy), or indexed per corner
/// through cornerIndex (refined face-varying primvars).
/// GeometryRecord::cornerValue() reads any of them.
struct PrimvarChannel {
    hd::Token name;
    int components = 0;
    bool constant = false;
    bool perPrimitive = false;  ///< one value per Embree primitive (a point, a curve segment)
    bool perVertex = false;     ///< one value per point (triangles index it)
    std::vector<float> data;
    /// When set: the value index of each triangle corner (3 per triangle) into data (refined
    /// face-varying primvars: shared with the subdivision topology, not copied per corner).
    std::shared_ptr<const std::vector<int>> cornerIndex;
};

/// One rprim's geometry as the integrator sees it. Owned by the rprim; the Embree instance of
/// the rprim carries a pointer to it as user data.
struct GeometryRecord {
    /// Points are Embree sphere points, Curves Embree round curves: their hits carry Embree's
    /// geometric normal; triangleFace maps each primitive to its point or curve.
    enum class Kind : uint8_t { Triangles, Sphere, Points, Curves };
    Kind kind = Kind::Triangles;
    int primId = -1;
    int materialIndex = -1;  ///< into SceneSnapshot::materials; -1 = use displayColor
    /// The mesh lights made from this prim's emission: emissiveLightCount consecutive lights from
    /// index emissiveLight (-1: none), one per emitting material (LightRecord::meshMaterial).
    int emissiveLight = -1;
    int emissiveLightCount = 0;
    glm::vec3 displayColor{0.18f};
    /// Bit i set: lit by the linked light of LightRecord::linkBit i (lights without a link
    /// category light every prim).
    uint64_t lightLinks = 0;
    /// Bit i set: casts the shadows of the light of LightRecord::shadowBit i.
    uint64_t shadowLinks = 0;
    bool doubleSided = false;
    glm::mat4 objectToWorld{1.0f};
    glm::mat4 worldToObject{1.0f};
    glm::mat3 normalToWorld{1.0f};  ///< inverse transpose of objectToWorld's 3x3
    // Triangles: object-space positions, per-corner normals, coarse face of each triangle
    // (for elementId and per-face materials). Shading normals come from cornerNormals when it
    // is not empty, else from vertexNormals (one per point, indexed by triangles: refined
    // subdivision meshes, 12 bytes per point instead of 36 per triangle), else flat.
    std::vector<glm::vec3> points;
    std::vector<glm::uvec3> triangles;
    std::vector<glm::vec3> cornerNormals;
    std::vector<glm::vec3> vertexNormals;
    std::vector<int> triangleFace;
    std::vector<PrimvarChannel> primvars;  ///< the mesh's float primvars (st, displayColor...)
    /// GeomSubset materials: per triangle, into SceneSnapshot::materials (empty: none).
    std::vector<int> triangleMaterial;
    /// The material of a hit triangle: its GeomSubset's, else the prim's own.
    int materialFor(unsigned triangle) const {
        return triangle < triangleMaterial.size() ? triangleMaterial[triangle] : materialIndex;
    }
    const PrimvarChannel* primvar(const hd::Token& name) const {
        for (const auto& p : primvars)
            if (p.name == name) return &p;
        return nullptr;
    }
    /// The `components` floats of channel ch at corner k (0..2) of triangle t, whatever its
    /// layout (constant, perPrimitive, perVertex or per corner).
    const float* cornerValue(const PrimvarChannel& ch, unsigned t, int k) const {
        size_t element = ch.constant       ? 0
                         : ch.perPrimitive ? size_t(t)
                         : ch.perVertex    ? size_t(triangles[t][k])
                         : ch.cornerIndex  ? size_t((*ch.cornerIndex)[3 * size_t(t) + size_t(k)])
                                           : 3 * size_t(t) + size_t(k);
        return &ch.data[element * size_t(ch.components)];
    }
    /// Bytes held by the arrays (capacity, not size): for memory accounting and tests.
    /// Shared cornerIndex arrays are not counted (the subdivision topology holds them).
    size_t memoryBytes() const {
        auto b = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
        size_t bytes = b(points) + b(triangles) + b(cornerNormals) + b(vertexNormals) +
                       b(triangleFace) + b(triangleMaterial) + b(primvars);
        for (const auto& p : primvars) bytes += b(p.data);
        return bytes;
    }
    // Sphere: centre and radius in object space.
    glm::vec3 center{0.0f};
    float radius = 1.0f;
};

/// One PointInstancer instance: a top-level Embree instance of a prototype's BLAS. The
/// prototype's GeometryRecord supplies everything but the placement.
struct InstanceRecord {
    glm::mat4 objectToWorld{1.0f};  ///< instancer * translate * rotate * scale * prototype
    glm::mat3 normalToWorld{1.0f};  ///< inverse transpose of objectToWorld's 3x3 (set at sync)
    int instanceIndex = -1;         ///< index into the instancer's arrays (instanceId AOV)
    /// The instancer's per-instance primvars (one value per instance, at instanceIndex; shared
    /// by every instance of the instancer), which the prototype's materials read where the
    /// prototype has no varying primvar of that name (a scatter's per-point colour). May be null.
    std::shared_ptr<const std::vector<PrimvarChannel>> primvars;
};

/// A light as the integrator samples it.
/// A lat-long environment (DomeLight texture) with its luminance sampling distribution.
struct EnvironmentMap {
    int width = 0, height = 0;
    std::vector<glm::vec3> texels;  ///< linear RGB, row 0 = top (+Y pole)
    glm::vec3 mean{0.0f};           ///< mean texel (light power estimates), set at load
    /// A lat-long map whose sampling distributions are prepared (prepareEnvironmentSampling,
    /// delegate/environmentSampling.h); false for images that are not sampled (rect lights).
    bool latLong = false;
    /// Over (u, v) by max(0, luminance - its mean over the sphere) * sin(theta): next-event
    /// estimation's distribution when MIS pairs it with BSDF sampling (Karlik et al. 2019, "MIS
    /// compensation", section 4, the environment map case). Empty when nothing lies above the mean
    /// by more than a trace (a near-constant map): plain() is used then.
    Distribution2D compensated;
    /// Over (u, v) by luminance * sin(theta), built on first use (thread-safe): only renders
    /// without MIS or compensation, and near-constant maps, need it (8 bytes per texel).
    const Distribution2D& plain() const;
    /// The distribution next-event estimation samples: compensated with MIS, else the plain one
    /// (without MIS, the directions it never picks would be left to BSDF sampling alone).
    const Distribution2D& sampling(bool misCompensation) const {
        return misCompensation && !compensated.empty() ? compensated : plain();
    }

private:
    mutable Distribution2D _plain;
    mutable std::unique_ptr<std::once_flag> _plainOnce = std::make_unique<std::once_flag>();
};

/// One emitting triangle of a mesh light in world space, with its unit normal ((b - a) x (c - a)
/// normalised) and area: computed once at commit (prepareMeshLight, light.cpp) so sampling does
/// not transform three points per triangle per sample.
struct MeshLightTriangle {
    glm::vec3 a{0.0f}, b{0.0f}, c{0.0f};
    glm::vec3 normal{0.0f};
    float area = 0.0f;
};

struct LightRecord {
    enum class Kind : uint8_t { Distant, Dome, Sphere, Rect, Disk, Cylinder, Mesh };
    Kind kind = Kind::Distant;
    glm::vec3 radiance{1.0f};    ///< color * intensity * 2^exposure (/ area when normalized)
    glm::vec3 direction{0, 0, -1};  ///< distant: world direction the light travels
    float cosHalfAngle = 1.0f;   ///< distant: cos of half the angular diameter (1 = delta)
    /// distant: 1 - cosHalfAngle, computed as 2 sin^2(half / 2): for the sun's 0.27 degrees the
    /// float difference 1 - cos lost 0.3 % of its light (the cone's solid angle is 2 pi times it).
    float oneMinusCosHalfAngle = 0.0f;
    glm::vec3 irradiance{0.0f};  ///< distant: perpendicular irradiance it delivers
    bool visibleToCamera = true;
    /// UsdLux ShadowAPI inputs:shadow:enable: false lets the light through occluders (no shadow
    /// rays; next-event estimation alone carries it, BSDF-sampled hits on it weigh 0).
    bool castsShadows = true;
    /// UsdLux LightAPI inputs:diffuse / inputs:specular: how strongly the light reaches the
    /// diffuse lobes (diffuse, sheen) and the specular ones (specular, clearcoat, transmission)
    /// of the surface it lights (1, 1: as the BSDF says).
    float diffuseScale = 1.0f, specularScale = 1.0f;
    bool scalesLobes() const { return diffuseScale != 1.0f || specularScale != 1.0f; }
    /// UsdLux light linking: the category (SceneDelegate::getCategories) of the prims this light
    /// lights, empty for all; linkBit is its bit in GeometryRecord::lightLinks (-1: lights all).
    std::string linkCategory;
    int linkBit = -1;
    bool lights(uint64_t geometryLinks) const { return linkBit < 0 || ((geometryLinks >> linkBit) & 1u); }
    /// Shadow linking: the category of the prims that cast this light's shadows, empty for all;
    /// shadowBit is its bit in GeometryRecord::shadowLinks (-1: every prim casts them).
    std::string shadowCategory;
    int shadowBit = -1;
    bool shadowedBy(uint64_t geometryShadowLinks) const {
        return shadowBit < 0 || ((geometryShadowLinks >> shadowBit) & 1u);
    }
    /// Its light reaches points that BSDF rays from them cannot (no shadows, or prims that do
    /// not cast them): next-event estimation alone carries it, with weight 1.
    bool neeOnly() const { return !castsShadows || shadowBit >= 0; }
    // Area lights, in world space.
    glm::vec3 center{0.0f};
    glm::vec3 axisU{0.0f}, axisV{0.0f};  ///< rect: half extents; disk: radii; cylinder: U = half length along the axis
    glm::vec3 normal{0, 0, -1};          ///< rect/disk: the side that emits
    float radius = 0.0f;                 ///< sphere, cylinder
    /// A sphere light rendered as a point (UsdLux treatAsPoint, or radius 0): radiance holds
    /// its radiant intensity; next-event estimation alone finds it (rays never hit it).
    bool point = false;
    float area = 0.0f;
    LightShaping shaping;                ///< sphere/rect/disk/cylinder: UsdLux ShapingAPI cone
    /// Dome texture (null: constant), unscaled and in the dome's own frame: the image is shared
    /// between syncs of the light (an intensity or rotation edit does not read it again), so
    /// what varies per sync (radiance, the rotation below) lives in the record.
    std::shared_ptr<const EnvironmentMap> environment;
    glm::mat3 domeWorldToLocal{1.0f};  ///< the dome's rotation (its frame: +Y up)
    glm::mat3 domeLocalToWorld{1.0f};
    /// Rect light texture:file (texels only; null: constant). Texel (0, 0), the image's top
    /// left, sits at the light's (+X, +Y) corner.
    std::shared_ptr<const EnvironmentMap> rectTexture;
    /// A UsdLux PortalLight (kind Rect geometry; normal = the direction light passes): never a
    /// light of the snapshot, it guides the dome lights' sampling (`portals`).
    bool portal = false;
    /// Dome lights: the scene's portals, or null (delegate/portalSampling.h).
    std::shared_ptr<const PortalSet> portals;
    float pickProbability = 1.0f;  ///< chance next-event estimation picks this light
    // Mesh lights (emissive geometry, one light per emitting material of a prim or of a placed
    // copy): the triangles that emit, with a CDF over their world-space areas. Emission is
    // two-sided, as it is shaded.
    const GeometryRecord* mesh = nullptr;
    std::shared_ptr<const std::vector<uint32_t>> meshTriangles;
    std::shared_ptr<const std::vector<float>> meshAreaCdf;  ///< meshTriangles.size() + 1
    bool solidAngleSampling = true;  ///< small mesh lights: sample by solid angle (lightSampling.cpp)
    int meshMaterial = -1;           ///< the material (SceneSnapshot::materials) of its triangles
    /// The material's emission is textured: `radiance` is only its estimated mean (for picking
    /// lights); each sample's radiance comes from the material at the sampled point.
    bool texturedEmission = false;
    /// meshTriangles in world space, same order (prepareMeshLight, light.cpp).
    std::shared_ptr<const std::vector<MeshLightTriangle>> meshWorld;
};

/// Everything a render pass reads: the committed top-level scene and the tables the records
/// index. Rebuilt by the render delegate's commitResources(); immutable while a pass runs.
struct SceneSnapshot {
    RTCScene scene = nullptr;
    std::vector<GeometryRecord*> geometryByInstance;  ///< indexed by Embree instance geomID
    /// Also by geomID: the instance's own placement for PointInstancer instances, else null
    /// (empty when the scene has no instancer).
    std::vector<const InstanceRecord*> instanceByInstance;
    /// Mesh lights of placed copies of instanced emitters, by Embree instance geomID: (first
    /// light, count), (-1, 0) for none. Prims drawn on their own use GeometryRecord::emissiveLight.
    std::vector<std::pair<int, int>> instanceLights;
    std::vector<MaterialRecord> materials;
    std::vector<LightRecord> lights;                  ///< sorted by prim path (determinism)
    std::vector<float> lightCdf;                      ///< lights.size() + 1 entries, by power
    /// The scene's bounding radius the light powers were taken against (distant and dome lights
    /// deliver power in proportion to its square; delegate/lightPick.h).
    float lightSceneRadius = 0.0f;
    bool usingDefaultLight = false;                   ///< the scene had no light
    /// Some material can be partly present (opacity, cutouts): shadow rays then look at
    /// each surface they cross instead of stopping at the first.
    bool anyPartlyPresent = false;
    /// Next-event estimation samples every light at every vertex (setting neeAllLights: scenes
    /// with at most that many lights); each light's pickProbability is then 1.
    bool neeAllLights = false;
};

}  // namespace principled::embree
