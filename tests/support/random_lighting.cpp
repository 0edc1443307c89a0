// The random lighting configurations (see random_lighting.h).
#include "tests/support/random_lighting.h"

#include <cmath>
#include <random>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"

namespace pathfarm::test {
namespace {

constexpr Vec3 kReceiverCentre(0.0f, 0.5f, 0.0f);
constexpr float kReceiverRadius = 0.5f;

// Portable uniform numbers: the standard distributions may differ between libraries.
class Draw {
public:
    explicit Draw(uint32_t seed) : rng_(seed) {}
    float uniform() { return float(rng_() >> 8) * 0x1p-24f; }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    float log_uniform(float lo, float hi) { return lo * std::pow(hi / lo, uniform()); }
    bool chance(float p) { return uniform() < p; }
    Vec3 unit_vector() {
        const float z = uniform(-1.0f, 1.0f), phi = uniform(0.0f, 2.0f * kPi);
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        return {r * std::cos(phi), r * std::sin(phi), z};
    }
    glm::quat rotation() {  // uniform on SO(3) (Shoemake)
        const float u1 = uniform(), u2 = uniform(0.0f, 2.0f * kPi), u3 = uniform(0.0f, 2.0f * kPi);
        const float a = std::sqrt(1.0f - u1), b = std::sqrt(u1);
        return glm::normalize(
            glm::quat(a * std::sin(u2), a * std::cos(u2), b * std::sin(u3), b * std::cos(u3)));
    }
    Rgb tint(float lo) { return {uniform(lo, 1.0f), uniform(lo, 1.0f), uniform(lo, 1.0f)}; }

private:
    std::mt19937 rng_;
};

const char* name(EmitterShape s) {
    constexpr const char* kNames[] = {"triangle", "quad", "closed mesh", "sun/sky"};
    return kNames[int(s)];
}
const char* name(EmitterTransform t) {
    constexpr const char* kNames[] = {"rotated", "scaled", "non-uniformly scaled", "mirrored",
                                      "under a sheared parent"};
    return kNames[int(t)];
}
const char* name(ReceiverKind r) {
    constexpr const char* kNames[] = {
        "lambert",     "textured lambert", "rough plastic", "normal-mapped plastic",
        "rough metal", "mirror",           "rough glass",   "smooth glass"};
    return kNames[int(r)];
}

// A checkerboard of random sRGB colours (emission, base colour).
Image checker_image(Draw& draw, int n) {
    Image img{"checker", n, n, std::vector<uint8_t>(std::size_t(n) * n * 4, 255)};
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c)
                img.rgba[std::size_t(y * n + x) * 4 + c] =
                    uint8_t(40 + ((x + y) % 2 ? 215 : 120) * draw.uniform(0.3f, 1.0f));
    return img;
}

// Tangent-space bumps: a normal map whose normals tilt up to ~35 degrees.
Image bump_image(int n) {
    Image img{"bumps", n, n, std::vector<uint8_t>(std::size_t(n) * n * 4, 255)};
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float a = 0.6f * std::sin(2.0f * kPi * 3.0f * float(x) / float(n));
            const float b = 0.6f * std::cos(2.0f * kPi * 2.0f * float(y) / float(n));
            const Vec3 nrm = glm::normalize(Vec3(a, b, 1.0f));
            for (int c = 0; c < 3; ++c)
                img.rgba[std::size_t(y * n + x) * 4 + c] =
                    uint8_t(std::lround((nrm[c] * 0.5f + 0.5f) * 255.0f));
        }
    return img;
}

int add_texture(SceneBuilder& b, Image image, FilterMode filter) {
    Texture t;
    t.image = b.add_image(std::move(image));
    t.sampler.filter = filter;
    return b.add_texture(t);
}

Material receiver_material(ReceiverKind kind, Draw& draw, SceneBuilder& b) {
    Material m = make_lambert("receiver", draw.tint(0.4f) * 0.8f);
    switch (kind) {
        case ReceiverKind::lambert:
            break;
        case ReceiverKind::textured_lambert:
            m.base_color_texture.texture =
                add_texture(b, checker_image(draw, 8), FilterMode::nearest);
            break;
        case ReceiverKind::normal_mapped_plastic:
            m.normal_texture.texture = add_texture(b, bump_image(32), FilterMode::linear);
            [[fallthrough]];
        case ReceiverKind::rough_plastic:
            m.specular_factor = 1.0f;
            m.roughness_factor = draw.uniform(0.3f, 0.8f);
            break;
        case ReceiverKind::rough_metal:
            m.metallic_factor = 1.0f;
            m.roughness_factor = draw.uniform(0.35f, 0.75f);
            m.base_color_factor = Vec4(draw.tint(0.6f), 1.0f);
            break;
        case ReceiverKind::mirror:
            m.metallic_factor = 1.0f;
            m.roughness_factor = 0.0f;
            break;
        case ReceiverKind::rough_glass:
        case ReceiverKind::smooth_glass:
            m.transmission_factor = 1.0f;
            m.specular_factor = 1.0f;
            m.base_color_factor = Vec4(1.0f);
            m.ior = draw.uniform(1.3f, 1.8f);
            m.roughness_factor =
                kind == ReceiverKind::rough_glass ? draw.uniform(0.3f, 0.6f) : 0.0f;
            if (draw.chance(0.5f)) {
                m.attenuation_color = draw.tint(0.3f);
                m.attenuation_distance = draw.uniform(0.3f, 2.0f);
            }
            break;
    }
    return m;
}

// The emitter's mesh at unit size around the origin, front face +Z where it is flat.
Mesh emitter_mesh(EmitterShape shape, uint32_t index, int material) {
    if (shape == EmitterShape::quad)
        return make_quad(Vec3(0.0f), Vec3(0.5f, 0, 0), Vec3(0, 0.5f, 0), material);
    if (shape == EmitterShape::closed_mesh)
        return index % 2 ? make_unit_cube(material) : make_sphere(0.5f, 6, 10, material);
    Mesh m;
    m.name = "triangle";
    m.material = material;
    const float h = 0.5f * std::sqrt(3.0f);
    m.positions = {
        {-0.5f, -h / 3.0f, 0.0f}, {0.5f, -h / 3.0f, 0.0f}, {0.0f, 2.0f * h / 3.0f, 0.0f}};
    m.uvs = {{0.0f, 1.0f}, {1.0f, 1.0f}, {0.5f, 0.0f}};
    m.indices = {0, 1, 2};
    return m;
}

Vec3 scale_axes(Draw& draw) {  // non-uniform, geometric mean 1
    Vec3 s(draw.log_uniform(0.3f, 3.0f), draw.log_uniform(0.3f, 3.0f), 1.0f);
    s.z = 1.0f / (s.x * s.y);
    return s;
}

// Adds the emitter as node(s) placing a unit-size mesh at `centre` with extent size_m.
void add_emitter(SceneBuilder& b, LightingCase& c, Draw& draw, int material, const Vec3& centre) {
    Mesh mesh = emitter_mesh(c.shape, c.index, material);
    const Mat4 place = glm::translate(Mat4(1.0f), centre) * glm::mat4_cast(draw.rotation());
    Mat4 local = place;
    switch (c.transform) {
        case EmitterTransform::rotated:  // the size is in the vertices, the node only turns
            for (Vec3& p : mesh.positions)
                p *= c.size_m;
            break;
        case EmitterTransform::scaled:
            local = place * glm::scale(Mat4(1.0f), Vec3(c.size_m));
            break;
        case EmitterTransform::non_uniform:
            local = place * glm::scale(Mat4(1.0f), c.size_m * scale_axes(draw));
            break;
        case EmitterTransform::mirrored: {
            Vec3 s = c.size_m * (draw.chance(0.5f) ? scale_axes(draw) : Vec3(1.0f));
            s[int(draw.uniform() * 2.999f)] *= -1.0f;
            local = place * glm::scale(Mat4(1.0f), s);
            break;
        }
        case EmitterTransform::parented: {
            const Mat4 parent =
                place *
                glm::scale(Mat4(1.0f), scale_axes(draw) * (draw.chance(0.3f) ? -1.0f : 1.0f));
            const int p = b.add_instance(-1, parent, -1, "emitter-parent");
            const Mat4 child =
                glm::mat4_cast(draw.rotation()) * glm::scale(Mat4(1.0f), Vec3(c.size_m));
            b.add_instance(b.add_mesh(std::move(mesh)), child, p, "emitter");
            return;
        }
    }
    b.add_instance(b.add_mesh(std::move(mesh)), local, -1, "emitter");
}

Camera case_camera(Draw& draw) {
    const float elevation = glm::radians(draw.uniform(15.0f, 65.0f));
    const float azimuth = draw.uniform(0.0f, 2.0f * kPi);
    const float r = draw.uniform(2.2f, 4.0f);
    const Vec3 eye =
        kReceiverCentre + r * Vec3(std::cos(elevation) * std::cos(azimuth), std::sin(elevation),
                                   std::cos(elevation) * std::sin(azimuth));
    Camera cam;
    cam.yfov_radians = glm::radians(45.0f);
    cam.camera_to_world = glm::inverse(glm::lookAt(eye, Vec3(0.0f, 0.4f, 0.0f), Vec3(0, 1, 0)));
    return cam;
}

}  // namespace

std::string LightingCase::describe() const {
    std::ostringstream s;
    s << "case " << index << ": ";
    if (shape == EmitterShape::sky) {
        s << "sun/sky only";
    } else {
        s << (double_sided ? "two-sided " : "one-sided ") << (textured_emission ? "textured " : "")
          << name(shape) << " of " << size_m << " m, " << name(transform) << ", " << distance_m
          << " m away";
    }
    s << "; receiver " << name(receiver);
    return s.str();
}

LightingCase make_lighting_case(uint32_t index) {
    LightingCase c;
    c.index = index;
    Draw draw(0x9e3779b9u * (index + 1u));
    constexpr EmitterShape kShapes[] = {EmitterShape::triangle,    EmitterShape::quad,
                                        EmitterShape::closed_mesh, EmitterShape::quad,
                                        EmitterShape::triangle,    EmitterShape::closed_mesh,
                                        EmitterShape::sky};
    c.shape = kShapes[index % 7];
    c.transform = EmitterTransform(index % 5);
    c.receiver = ReceiverKind(index % kReceiverKinds);

    SceneBuilder b("lighting-case-" + std::to_string(index));
    const int ground = b.add_material(make_lambert("ground", Rgb(0.5f)));
    b.add_instance(b.add_mesh(make_quad(Vec3(0.0f), Vec3(3, 0, 0), Vec3(0, 0, -3), ground)),
                   Mat4(1.0f), -1, "ground");
    const int receiver = b.add_material(receiver_material(c.receiver, draw, b));
    // Mirrored receivers too: the winding and the normal map's bitangent follow the transform.
    const Mat4 receiver_place = glm::translate(Mat4(1.0f), kReceiverCentre) *
                                glm::scale(Mat4(1.0f), Vec3(index % 3 == 1 ? -1.0f : 1.0f, 1, 1));
    b.add_instance(b.add_mesh(make_sphere(kReceiverRadius, 16, 24, receiver)), receiver_place, -1,
                   "receiver");
    const Camera camera = case_camera(draw);
    b.add_camera(camera);

    if (c.shape == EmitterShape::sky) {
        b.environment().sky = SkyMode::on;
        const Vec3 d = draw.unit_vector();
        b.environment().sun_direction = glm::normalize(Vec3(d.x, 0.25f + std::abs(d.y), d.z));
        c.bsdf_informative = false;
        c.scene = b.finish();
        return c;
    }
    b.environment().sky = SkyMode::off;
    c.size_m = draw.log_uniform(0.01f, 3.0f);
    c.double_sided = draw.chance(0.4f);
    c.textured_emission = draw.chance(0.3f);
    const Vec3 eye = Vec3(camera.camera_to_world[3]);
    Vec3 centre(0.0f);
    // Half near-field (distance within a few sizes), half far.
    const bool near_field = draw.chance(0.5f);
    for (int attempt = 0; attempt < 32; ++attempt) {  // keep the camera outside the emitter
        const float ratio =
            near_field ? draw.log_uniform(0.4f, 3.0f) : draw.log_uniform(3.0f, 150.0f);
        const float near_m = kReceiverRadius + 0.6f * c.size_m;
        c.distance_m = std::min(40.0f, std::max(near_m, c.size_m * ratio));
        const Vec3 d = draw.unit_vector();
        centre =
            kReceiverCentre + c.distance_m * glm::normalize(Vec3(d.x, 0.15f + std::abs(d.y), d.z));
        if (glm::length(centre - eye) > 1.6f * c.size_m + 0.2f) break;
    }
    c.bsdf_informative = c.size_m >= 0.1f * c.distance_m;
    // Radiance ~ distance² / size²: about the same irradiance at the receiver in every case.
    Material light =
        make_emitter("emitter", draw.tint(0.5f) * (0.6f * glm::pow(c.distance_m / c.size_m, 2.0f)),
                     c.double_sided);
    if (c.textured_emission)
        light.emissive_texture.texture =
            add_texture(b, checker_image(draw, 4), FilterMode::nearest);
    add_emitter(b, c, draw, b.add_material(light), centre);
    c.scene = b.finish();
    return c;
}

}  // namespace pathfarm::test
