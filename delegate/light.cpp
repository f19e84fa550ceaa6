// SPDX-License-Identifier: Apache-2.0
#include "delegate/light.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "delegate/colorTemperature.h"
#include "delegate/environmentFormat.h"
#include "delegate/environmentSampling.h"
#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"
#include "delegate/imageio/imageIO.h"

namespace principled::embree {

using namespace hd;

namespace {

constexpr float kPi = 3.14159265358979323846f;

glm::vec3 finiteNonNegative(glm::vec3 v) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(v[i]) || v[i] < 0.0f) v[i] = 0.0f;
    return v;
}

glm::vec3 point(const glm::dmat4& m, double x, double y, double z) {
    return glm::vec3(m * glm::dvec4(x, y, z, 1.0));
}
glm::vec3 vector(const glm::dmat4& m, double x, double y, double z) {
    return glm::vec3(m * glm::dvec4(x, y, z, 0.0));
}

// Reads an image as linear RGB; null on failure (with *error naming `what`). A lat-long image
// also gets its sampling distributions (delegate/environmentSampling.h).
std::shared_ptr<EnvironmentMap> loadImage(const std::string& path, const std::string& what, bool latLong,
                                          std::string* error) {
    std::string reason;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {  // a device or directory would block or fail oddly
        *error = "cannot read " + what + " '" + path + "': not a regular file";
        return nullptr;
    }
    imageio::Backend* io = imageio::backend(&reason);
    std::unique_ptr<imageio::ImageReader> in = io ? io->open(path, &reason) : nullptr;
    if (!in) {
        *error = "cannot read " + what + " '" + path + "': " + reason;
        return nullptr;
    }
    const imageio::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || size_t(spec.width) * spec.height > (size_t(1) << 26)) {
        *error = what + " '" + path + "' has an unsupported size";
        return nullptr;
    }
    int channels = spec.channels;
    std::vector<float> px(size_t(spec.width) * spec.height * channels);
    if (!in->read(imageio::PixelType::Float, channels, px.data())) {
        *error = "cannot read " + what + " '" + path + "': " + in->error();
        return nullptr;
    }
    // 8-bit images are display-encoded (sRGB); float images are linear.
    bool srgb = spec.format == imageio::PixelType::UInt8;
    auto decode = [&](float v) {
        if (!std::isfinite(v) || v < 0.0f) return 0.0f;
        if (!srgb) return v;
        return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);  // IEC 61966-2-1
    };
    auto env = std::make_shared<EnvironmentMap>();
    env->width = spec.width;
    env->height = spec.height;
    env->texels.resize(size_t(spec.width) * spec.height);
    for (int y = 0; y < spec.height; ++y) {
        for (int x = 0; x < spec.width; ++x) {
            size_t i = size_t(y) * spec.width + x;
            const float* p = &px[i * channels];
            glm::vec3 c = channels >= 3 ? glm::vec3(decode(p[0]), decode(p[1]), decode(p[2]))
                                        : glm::vec3(decode(p[0]));
            env->texels[i] = c;
        }
    }
    glm::dvec3 sum(0.0);
    for (const auto& t : env->texels) sum += glm::dvec3(t);
    env->mean = glm::vec3(sum / double(env->texels.size()));
    if (latLong) prepareEnvironmentSampling(*env);
    return env;
}

}  // namespace

std::shared_ptr<const EnvironmentMap> Light::image(EmbreeRenderParam* param, const std::string& file, bool dome,
                                                   DomeFormat format, std::string* error) {
    shading::TextureCache* textures = param->textureCache();
    const std::string key = std::string(dome ? "dome " : "rect ") + std::to_string(int(format)) + " " + file;
    const uint64_t version = textures ? textures->fileVersion(file) : 0;
    if (textures && _cached.image && _cached.key == key && _cached.version == version) return _cached.image;
    if (textures) textures->watch(file);  // reloadTextures() sees later edits of the file
    const bool latLong = dome && format == DomeFormat::LatLong;
    std::shared_ptr<EnvironmentMap> img = loadImage(file, dome ? "dome texture" : "rect light texture", latLong, error);
    if (img && dome && !latLong) {
        // A mirrored ball or angular map, resampled once into the lat-long layout.
        img = std::make_shared<EnvironmentMap>(resampleToLatLong(*img, format));
        prepareEnvironmentSampling(*img);
    }
    _cached = img ? CachedImage{key, version, img} : CachedImage{};
    return img;
}

void Light::sync(SceneDelegate* delegate, RenderParam* renderParam, DirtyBits* bits) {
    auto* param = static_cast<EmbreeRenderParam*>(renderParam);
    if (!_registered) {
        param->add(static_cast<LightSource*>(this));
        _registered = true;
    }
    auto scalar = [&](const char* name, float fallback) {
        auto v = getFloat(delegate->getLightParamValue(id(), Token(name)));
        return (v && std::isfinite(*v)) ? *v : fallback;
    };
    if (*bits & (SprimDirty::Params | SprimDirty::Transform | SprimDirty::Resource |
                 SprimDirty::Visibility)) {
        _enabled = delegate->getVisible(id());
        // USD light units: L = color * intensity * 2^exposure (UsdLux LightAPI).
        glm::vec3 color = getVec3(delegate->getLightParamValue(id(), Token("color")))
                              .value_or(glm::vec3(1.0f));
        if (scalar("enableColorTemperature", 0.0f) > 0.5f)
            color *= blackbodyColor(scalar("colorTemperature", 6500.0f));
        float intensity = scalar("intensity", _type == tokens::distantLight() ? 50000.0f : 1.0f);
        if (intensity < 0.0f) param->warn(id(), "negative intensity " + std::to_string(intensity) + "; the light emits nothing");
        for (const char* length : {"radius", "width", "height", "length", "angle"})
            if (scalar(length, 0.0f) < 0.0f)
                param->warn(id(), std::string(length) + " is negative (" + std::to_string(scalar(length, 0.0f)) + "); read as 0");
        float exposure = scalar("exposure", 0.0f);
        bool normalize = scalar("normalize", 0.0f) > 0.5f;
        glm::vec3 scaled = finiteNonNegative(color * intensity * std::exp2(exposure));
        glm::dmat4 xf = delegate->getTransform(id());
        _record = LightRecord();
        glm::vec3 pointIntensity(0.0f);  // LightRecord::point lights
        _record.castsShadows = scalar("shadow:enable", 1.0f) > 0.5f;  // UsdLux ShadowAPI
        _record.linkCategory = getString(delegate->getLightParamValue(id(), Token("lightLink"))).value_or("");
        _record.shadowCategory = getString(delegate->getLightParamValue(id(), Token("shadowLink"))).value_or("");
        // Non-physical multipliers, capped so that light times multiplier stays finite.
        _record.diffuseScale = std::clamp(scalar("diffuse", 1.0f), 0.0f, 1e6f);
        _record.specularScale = std::clamp(scalar("specular", 1.0f), 0.0f, 1e6f);
        if (getVec3(delegate->getLightParamValue(id(), Token("shadow:color"))).value_or(glm::vec3(0.0f)) != glm::vec3(0.0f) ||
            getFloat(delegate->getLightParamValue(id(), Token("shadow:distance"))).value_or(-1.0f) >= 0.0f)
            param->warn(id(), "shadow:color and shadow:distance are not supported; shadows are black and unbounded");
        if (_type == tokens::distantLight()) {
            _record.kind = LightRecord::Kind::Distant;
            glm::vec3 d = vector(xf, 0.0, 0.0, -1.0);
            float len = glm::length(d);
            _record.direction = len > 0.0f ? d / len : glm::vec3(0, 0, -1);
            float angle = std::clamp(scalar("angle", 0.53f), 0.0f, 180.0f);
            float half = 0.5f * angle * kPi / 180.0f;
            _record.cosHalfAngle = std::cos(half);
            const float sq = std::sin(0.5f * half);
            _record.oneMinusCosHalfAngle = 2.0f * sq * sq;
            float s = std::sin(half);
            // The disc of angular diameter `angle` delivers E = L * pi * sin^2(angle/2) head-on
            // (solid angle of a cone, projected); a zero angle is a delta light with E = L.
            float solid = kPi * s * s;
            if (angle <= 0.0f || solid <= 1e-12f) {
                _record.cosHalfAngle = 1.0f;
                _record.oneMinusCosHalfAngle = 0.0f;
                _record.irradiance = scaled;
                _record.radiance = scaled;
            } else if (normalize) {
                // normalize: intensity is the illuminance (lux) the light delivers.
                _record.irradiance = scaled;
                _record.radiance = scaled / solid;
            } else {
                _record.radiance = scaled;
                _record.irradiance = scaled * solid;
            }
        } else if (_type == tokens::domeLight()) {
            _record.kind = LightRecord::Kind::Dome;
            _record.radiance = scaled;
            _record.irradiance = scaled * kPi;
            auto file = getString(delegate->getLightParamValue(id(), Token("texture:file")));
            if (file && !file->empty()) {
                auto formatToken = getString(delegate->getLightParamValue(id(), Token("texture:format")));
                std::optional<DomeFormat> format = domeFormatFromToken(formatToken.value_or("automatic"));
                if (!format) {
                    param->warn(id(), "dome texture format '" + *formatToken + "' is not supported; read as latlong");
                    format = DomeFormat::LatLong;
                }
                std::string error;
                if (auto env = image(param, *file, true, *format, &error)) {
                    glm::mat3 r(xf);
                    for (int c = 0; c < 3; ++c) {
                        float l = glm::length(r[c]);
                        if (l > 0.0f) r[c] /= l;
                    }
                    _record.domeLocalToWorld = r;
                    _record.domeWorldToLocal = glm::transpose(r);
                    _record.environment = std::move(env);
                } else {
                    param->warn(id(), error + "; using its constant colour");
                }
            }
        } else {
            // Area lights: shapes in the light's frame, taken to world space.
            glm::vec3 c = point(xf, 0, 0, 0);
            _record.center = c;
            if (_type == tokens::sphereLight()) {
                _record.kind = LightRecord::Kind::Sphere;
                float r = std::max(0.0f, scalar("radius", 0.5f));
                const float sx = glm::length(vector(xf, 1, 0, 0)), sy = glm::length(vector(xf, 0, 1, 0)),
                            sz = glm::length(vector(xf, 0, 0, 1));
                float s = std::max({sx, sy, sz});
                if (r > 0.0f && std::min({sx, sy, sz}) < 0.999f * s)
                    param->warn(id(), "non-uniform scale: the sphere light is drawn as a sphere of the largest scaled radius, not an ellipsoid");
                _record.radius = std::max(r * s, 1e-6f);
                _record.area = 4.0f * kPi * _record.radius * _record.radius;
                // UsdLux treatAsPoint, and a zero radius: a point light with the sphere's power,
                // radiant intensity I = L pi r^2 (normalized: scaled / 4, the same for any r). A
                // zero radius has no unnormalized power; it is read as normalized (as Arnold reads
                // Maya's radius-0 point lights) rather than rendering black.
                // An authored radius of 0 is the point; a zero scale keeps the sphere (black, as
                // it was: a light scaled to nothing to hide it stays hidden).
                if (scalar("treatAsPoint", 0.0f) > 0.5f || !(r > 0.0f)) {
                    _record.point = true;
                    pointIntensity = normalize || !(r > 0.0f) ? scaled / 4.0f : scaled * (kPi * (r * s) * (r * s));
                }
            } else if (_type == tokens::rectLight() || _type == tokens::portalLight()) {
                _record.kind = LightRecord::Kind::Rect;
                _record.portal = _type == tokens::portalLight();
                float w = std::max(0.0f, scalar("width", 1.0f)), h = std::max(0.0f, scalar("height", 1.0f));
                _record.axisU = vector(xf, 0.5 * w, 0, 0);
                _record.axisV = vector(xf, 0, 0.5 * h, 0);
                _record.area = 4.0f * glm::length(glm::cross(_record.axisU, _record.axisV));
                const float lu = glm::length(_record.axisU), lv = glm::length(_record.axisV);
                if (_record.portal && lu > 0.0f && lv > 0.0f &&
                    std::abs(glm::dot(_record.axisU, _record.axisV)) > 1e-4f * lu * lv) {
                    param->warn(id(), "portal is sheared by its transform (its sides are not perpendicular); ignored");
                    _record.area = 0.0f;
                }
                auto file = _record.portal ? std::nullopt
                                           : getString(delegate->getLightParamValue(id(), Token("texture:file")));
                if (file && !file->empty()) {
                    std::string error;
                    if (auto img = image(param, *file, false, DomeFormat::LatLong, &error))
                        _record.rectTexture = std::move(img);
                    else
                        param->warn(id(), error + "; using its constant colour");
                }
            } else if (_type == tokens::diskLight()) {
                _record.kind = LightRecord::Kind::Disk;
                float r = std::max(0.0f, scalar("radius", 0.5f));
                _record.axisU = vector(xf, r, 0, 0);
                _record.axisV = vector(xf, 0, r, 0);
                _record.area = kPi * glm::length(glm::cross(_record.axisU, _record.axisV));
            } else {  // cylinder: major axis X, no caps
                _record.kind = LightRecord::Kind::Cylinder;
                float len = std::max(0.0f, scalar("length", 1.0f)), r = std::max(0.0f, scalar("radius", 0.5f));
                _record.axisU = vector(xf, 0.5 * len, 0, 0);
                const float sy = glm::length(vector(xf, 0, 1, 0)), sz = glm::length(vector(xf, 0, 0, 1));
                float s = std::max(sy, sz);
                if (r > 0.0f && std::min(sy, sz) < 0.999f * s)
                    param->warn(id(), "non-uniform scale across the axis: the cylinder light is drawn round, of the largest scaled radius");
                _record.radius = std::max(r * s, 1e-6f);
                _record.area = 2.0f * kPi * _record.radius * 2.0f * glm::length(_record.axisU);
            }
            glm::vec3 n = vector(xf, 0, 0, -1);
            _record.normal = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0, 0, -1);
            // UsdLux ShapingAPI: enabled when any of its inputs is authored (the schema's
            // fallbacks then apply: cone angle 90 degrees, softness 0, focus 0).
            auto authored = [&](const char* name) {
                return getFloat(delegate->getLightParamValue(id(), Token(name))).has_value();
            };
            const auto iesFile = getString(delegate->getLightParamValue(id(), Token("shaping:ies:file")));
            const bool iesAuthored = iesFile && !iesFile->empty();
            const bool coneOrFocus = authored("shaping:cone:angle") || authored("shaping:cone:softness") ||
                                     authored("shaping:focus");
            if (coneOrFocus || iesAuthored) {
                LightShaping& sh = _record.shaping;
                sh.enabled = true;
                sh.axis = _record.normal;
                sh.coneAngle = std::clamp(scalar("shaping:cone:angle", 90.0f), 0.0f, 180.0f) * kPi / 180.0f;
                sh.softness = std::clamp(scalar("shaping:cone:softness", 0.0f), 0.0f, 1.0f);
                sh.focus = std::max(0.0f, scalar("shaping:focus", 0.0f));
                sh.focusTint = finiteNonNegative(
                    getVec3(delegate->getLightParamValue(id(), Token("shaping:focusTint")))
                        .value_or(glm::vec3(0.0f)));
                if (iesAuthored) {
                    std::string error;
                    sh.ies = loadIes(*iesFile, &error);
                    if (!sh.ies) param->warn(id(), error + "; the light emits without its IES profile");
                    const float angleScale = scalar("shaping:ies:angleScale", 0.0f);
                    sh.iesAngleScale = angleScale > -1.0f ? angleScale : 0.0f;
                    if (!(angleScale > -1.0f))
                        param->warn(id(), "shaping:ies:angleScale must be greater than -1; 0 used");
                    // Unnormalized, the profile's peak is the light's authored radiance; with
                    // ies:normalize, its mean over the sphere is (the power stays the light's).
                    const bool iesNormalize = scalar("shaping:ies:normalize", 0.0f) > 0.5f;
                    if (sh.ies) {
                        sh.iesScale = 1.0f / (iesNormalize ? sh.ies->meanCandela : sh.ies->maxCandela);
                        if (!(sh.iesScale > 0.0f) || !std::isfinite(sh.iesScale)) sh.iesScale = 1.0f;
                    } else if (!coneOrFocus) {
                        sh.enabled = false;  // nothing else shapes it: it emits as authored
                    }
                    // Horizontal angle 0 along the light's +X, made orthogonal to the axis.
                    glm::vec3 t = vector(xf, 1, 0, 0);
                    t -= glm::dot(t, sh.axis) * sh.axis;
                    sh.tangent = glm::length(t) > 0.0f ? glm::normalize(t) : glm::vec3(1, 0, 0);
                }
            }
            // normalize: the power no longer depends on the size (divide by the world area).
            _record.radiance = normalize && _record.area > 0.0f ? scaled / _record.area : scaled;
            if (_record.point) {
                _record.radiance = finiteNonNegative(pointIntensity);
                _record.radius = 0.0f;
            } else if (!(_record.area > 0.0f) || !std::isfinite(_record.area)) {
                param->warn(id(), "light has zero or invalid area; disabled");
                _enabled = false;
            }
        }
        if (!_record.environment && !_record.rectTexture) _cached = CachedImage{};  // no image held for nothing
        param->markLightsDirty();
    }
    *bits = SprimDirty::Clean;
}

void Light::finalize(RenderParam* renderParam) {
    auto* param = static_cast<EmbreeRenderParam*>(renderParam);
    if (_registered) param->remove(static_cast<LightSource*>(this));
    _registered = false;
    param->markLightsDirty();
}

void prepareMeshLight(LightRecord* l) {
    prepareMeshLight(l, l->mesh ? l->mesh->objectToWorld : glm::mat4(1.0f));
}

void prepareMeshLight(LightRecord* l, const glm::mat4& objectToWorld) {
    auto world = std::make_shared<std::vector<MeshLightTriangle>>();
    if (l->mesh && l->meshTriangles) {
        const GeometryRecord& g = *l->mesh;
        world->reserve(l->meshTriangles->size());
        for (uint32_t t : *l->meshTriangles) {
            const glm::uvec3& tri = g.triangles[t];
            MeshLightTriangle m;
            m.a = glm::vec3(objectToWorld * glm::vec4(g.points[tri.x], 1.0f));
            m.b = glm::vec3(objectToWorld * glm::vec4(g.points[tri.y], 1.0f));
            m.c = glm::vec3(objectToWorld * glm::vec4(g.points[tri.z], 1.0f));
            glm::vec3 n = glm::cross(m.b - m.a, m.c - m.a);
            float len = glm::length(n);
            // A zero-area triangle keeps a zero normal: the samplers reject it.
            m.normal = len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0.0f);
            m.area = 0.5f * len;
            world->push_back(m);
        }
    }
    l->meshWorld = std::move(world);
}

}  // namespace principled::embree
