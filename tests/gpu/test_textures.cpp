// Textures seen directly (an emissive textured quad under --max-depth 1, orthographic camera, 4 pixels per
// texel): every pixel equals the sRGB-decoded texel that an independent reference addressing picks, for each
// wrap mode, both filters, TEXCOORD_1 and KHR_texture_transform. Rendered through the real stages on lavapipe
// with validation on.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../unit/scene/gltf_builder.h"
#include "render/renderer.h"
#include "scene/bvh/bvh.h"
#include "scene/pack.h"
#include "vk/context.h"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace fh::test {
namespace {

constexpr int TEX = 4;      // texture side in texels
constexpr int PIXELS = 48;  // film side: the quad's UV range of 3 maps 12 texels to 48 pixels

vk::Context& context() {
    static std::unique_ptr<vk::Context> c = [] {
        vk::ContextOptions o;
        o.validation = true;
        return std::make_unique<vk::Context>(o);
    }();
    return *c;
}

std::vector<unsigned char> encode_png(const std::vector<uint32_t>& rgba, int w, int h) {
    std::vector<unsigned char> out;
    stbi_write_png_to_func([](void* ctx, void* data, int size) {
        auto* v = static_cast<std::vector<unsigned char>*>(ctx);
        v->insert(v->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
    }, &out, w, h, 4, rgba.data(), w * 4);
    return out;
}

double srgb_decode(uint32_t byte) {
    const double c = byte / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// Reference wrap of an integer texel coordinate (OpenGL's definitions, written out).
int wrap_reference(int i, int n, const std::string& mode) {
    if (mode == "clamp") return std::min(std::max(i, 0), n - 1);
    const int r = ((i % n) + n) % n;
    if (mode == "repeat") return r;
    const int period = ((i % (2 * n)) + 2 * n) % (2 * n);  // mirrored: even periods forward, odd backward
    return period < n ? period : 2 * n - 1 - period;
}

int gl_wrap(const std::string& mode) { return mode == "clamp" ? 33071 : mode == "mirror" ? 33648 : 10497; }

struct Case {
    std::string wrap_s = "repeat", wrap_t = "repeat";
    bool nearest = true;
    int tex_coord = 0;
    bool transform = false;  // offset (0.5, 0.25), rotation pi/2, scale (2, 2)
};

struct Scene2 {
    std::vector<uint32_t> texels;
    std::filesystem::path file;
};

// The quad z = 0 over [-1, 1]^2 with UV (-1, -1) at the top left and (2, 2) at the bottom right, emissive,
// seen by an orthographic camera that frames it exactly.
Scene2 make_scene(const Case& c, uint32_t seed) {
    Scene2 out;
    std::mt19937 rng(seed);
    for (int i = 0; i < TEX * TEX; ++i) out.texels.push_back(rng() | 0xff000000u);
    GltfBuilder b;
    const std::vector<glm::vec3> p = {{-1, 1, 0}, {1, 1, 0}, {1, -1, 0}, {-1, -1, 0}};
    const std::vector<float> uv = {-1, -1, 2, -1, 2, 2, -1, 2};
    const std::vector<float> junk = {0.3f, 0.3f, 0.3f, 0.3f, 0.3f, 0.3f, 0.3f, 0.3f};
    const int uv_right = b.add_accessor(b.add_view(uv.data(), uv.size() * 4), 5126, 4, "VEC2");
    const int uv_junk = b.add_accessor(b.add_view(junk.data(), junk.size() * 4), 5126, 4, "VEC2");
    nlohmann::json attributes = {{"POSITION", b.add_vec3(p)}};
    attributes["TEXCOORD_0"] = c.tex_coord == 0 ? uv_right : uv_junk;
    if (c.tex_coord == 1) attributes["TEXCOORD_1"] = uv_right;
    const std::vector<uint32_t> indices = {0, 3, 2, 0, 2, 1};
    nlohmann::json info = {{"index", 0}, {"texCoord", c.tex_coord}};
    if (c.transform)
        info["extensions"] = {{"KHR_texture_transform",
                               {{"offset", {0.5, 0.25}}, {"rotation", 1.5707963267948966}, {"scale", {2.0, 2.0}}}}};
    b.add_material({{"emissiveFactor", {1.0, 1.0, 1.0}}, {"emissiveTexture", info},
                    {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}}}});
    b.add_mesh({{"attributes", attributes}, {"indices", b.add_indices(indices)}, {"material", 0}});
    b.doc["samplers"] = {{{"wrapS", gl_wrap(c.wrap_s)}, {"wrapT", gl_wrap(c.wrap_t)},
                          {"magFilter", c.nearest ? 9728 : 9729}}};
    b.doc["images"] = {{{"uri", "data:image/png;base64," + encode_base64(encode_png(out.texels, TEX, TEX))}}};
    b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    if (c.transform) b.doc["extensionsUsed"] = {"KHR_texture_transform"};
    b.doc["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}}};
    const int quad = b.add_node({{"mesh", 0}});
    const int camera = b.add_node({{"camera", 0}, {"translation", {0, 0, 1}}});
    b.set_scene({quad, camera});
    out.file = b.write_gltf();
    return out;
}

// The reference at texture coordinates (u, v): nearest texel or bilinear of decoded texels.
glm::dvec3 reference_texel(const Scene2& s, const Case& c, double u, double v) {
    if (c.transform) {  // T(offset) R(pi/2) S(2): u' = 2 v + 0.5, v' = -2 u + 0.25
        const double u2 = 2.0 * v + 0.5, v2 = -2.0 * u + 0.25;
        u = u2;
        v = v2;
    }
    auto texel = [&](int i, int j) {
        const uint32_t t = s.texels[size_t(wrap_reference(j, TEX, c.wrap_t) * TEX + wrap_reference(i, TEX, c.wrap_s))];
        return glm::dvec3(srgb_decode(t & 255), srgb_decode((t >> 8) & 255), srgb_decode((t >> 16) & 255));
    };
    const double x = u * TEX, y = v * TEX;
    if (c.nearest) return texel(int(std::floor(x)), int(std::floor(y)));
    const double fx = std::floor(x - 0.5), fy = std::floor(y - 0.5);
    const double ax = x - 0.5 - fx, ay = y - 0.5 - fy;
    const int i = int(fx), j = int(fy);
    return (1 - ay) * ((1 - ax) * texel(i, j) + ax * texel(i + 1, j)) + ay * ((1 - ax) * texel(i, j + 1) + ax * texel(i + 1, j + 1));
}

// Largest per-channel difference between the render and the reference at pixel centres.
double render_and_compare(const Case& c, uint32_t spp) {
    const Scene2 s = make_scene(c, 7);
    const fh::Scene scene = load_gltf(s.file);
    const PackedScene packed = pack_scene(scene, build_bvh(scene.positions));
    EXPECT_NE(packed.effects.bits & gpu::EFFECT_EMISSIVE_TEXTURE, 0u);
    RenderSettings settings;
    settings.width = settings.height = PIXELS;
    settings.spp = spp;
    settings.max_depth = 1;
    Renderer renderer(context(), packed, scene.cameras.at(0), settings);
    renderer.render();
    const Image image = renderer.read_film();
    double worst = 0.0;
    for (int py = 0; py < PIXELS; ++py)
        for (int px = 0; px < PIXELS; ++px) {
            // Pixel centre -> quad position -> UV (u from -1 at the left, v from -1 at the top, range 3).
            const double u = -1.0 + 3.0 * (px + 0.5) / PIXELS, v = -1.0 + 3.0 * (py + 0.5) / PIXELS;
            const glm::dvec3 expected = reference_texel(s, c, u, v);
            for (int k = 0; k < 3; ++k)
                worst = std::max(worst, std::abs(image.rgb[3 * size_t(py * PIXELS + px) + size_t(k)] - expected[k]));
        }
    EXPECT_EQ(context().validation_message_count(), 0u);
    return worst;
}

TEST(Textures, NearestTexelsAreExactForEveryWrapMode) {
    for (const char* s : {"repeat", "clamp", "mirror"})
        for (const char* t : {"repeat", "clamp", "mirror"}) {
            Case c;
            c.wrap_s = s;
            c.wrap_t = t;
            EXPECT_LT(render_and_compare(c, 1), 1e-5) << "wrap " << s << "/" << t;
        }
}

TEST(Textures, TexCoord1AndTextureTransformAreApplied) {
    Case c;
    c.tex_coord = 1;
    EXPECT_LT(render_and_compare(c, 1), 1e-5) << "TEXCOORD_1";
    c.tex_coord = 0;
    c.transform = true;
    c.wrap_s = "mirror";
    EXPECT_LT(render_and_compare(c, 1), 1e-5) << "KHR_texture_transform";
}

// Bilinear filtering is linear inside each pixel here (no pixel straddles a line of texel centres), so the
// pixel's mean equals the bilinear value at its centre. Within a pixel the value varies by up to a quarter of
// a texel step, so 256 samples leave a noise of about 0.005 per pixel: the worst of 6912 values stays below
// 0.03, while nearest sampling (or a half-texel shift) is off by 0.1 to 0.5.
TEST(Textures, BilinearFilteringMatchesTheReference) {
    Case c;
    c.nearest = false;
    c.wrap_s = "mirror";
    c.wrap_t = "clamp";
    EXPECT_LT(render_and_compare(c, 256), 0.03);
}

}  // namespace
}  // namespace fh::test
