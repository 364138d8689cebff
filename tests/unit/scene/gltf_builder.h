// Test helper: builds small glTF 2.0 files (JSON with an embedded base64 buffer, or .glb) from C++ arrays.
#pragma once
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace fh::test {

inline std::string encode_base64(const std::vector<unsigned char>& data) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < data.size(); i += 3) {
        const uint32_t b0 = data[i], b1 = i + 1 < data.size() ? data[i + 1] : 0, b2 = i + 2 < data.size() ? data[i + 2] : 0;
        const uint32_t v = (b0 << 16) | (b1 << 8) | b2;
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += i + 1 < data.size() ? table[(v >> 6) & 63] : '=';
        out += i + 2 < data.size() ? table[v & 63] : '=';
    }
    return out;
}

// A valid 2x1 RGBA PNG: texel 0 opaque red, texel 1 half-transparent white (from Python's zlib, fixed bytes).
inline std::vector<unsigned char> png_2x1() {
    return {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00,
            0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06, 0x00, 0x00, 0x00, 0xf4, 0x22, 0x7f, 0x8a, 0x00,
            0x00, 0x00, 0x0f, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0xf8, 0xcf, 0xc0, 0xf0, 0x1f, 0x08, 0x1a,
            0x00, 0x16, 0x73, 0x05, 0x7c, 0x26, 0x97, 0x01, 0xd2, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44,
            0xae, 0x42, 0x60, 0x82};
}

// A unique path in the test temp directory for the running test.
inline std::filesystem::path temp_path(const std::string& extension) {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    return std::filesystem::path(testing::TempDir()) /
           ("fh_scene_" + std::string(info->test_suite_name()) + "_" + info->name() + extension);
}

class GltfBuilder {
public:
    nlohmann::json doc = {{"asset", {{"version", "2.0"}}}};
    std::vector<unsigned char> bin;

    int add_view(const void* data, size_t bytes, int stride = 0) {
        while (bin.size() % 4 != 0) bin.push_back(0);
        nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (stride > 0) view["byteStride"] = stride;
        const auto* p = static_cast<const unsigned char*>(data);
        bin.insert(bin.end(), p, p + bytes);
        return push("bufferViews", view);
    }
    int add_accessor(int view, int component_type, size_t count, const std::string& type, size_t offset = 0) {
        nlohmann::json a = {{"componentType", component_type}, {"count", count}, {"type", type}};
        if (view >= 0) a["bufferView"] = view;
        if (offset > 0) a["byteOffset"] = offset;
        return push("accessors", a);
    }
    int add_vec3(const std::vector<glm::vec3>& v) {
        return add_accessor(add_view(v.data(), v.size() * 12), 5126, v.size(), "VEC3");
    }
    template <typename T>
    int add_indices(const std::vector<T>& v) {
        const int type = sizeof(T) == 1 ? 5121 : (sizeof(T) == 2 ? 5123 : 5125);
        return add_accessor(add_view(v.data(), v.size() * sizeof(T)), type, v.size(), "SCALAR");
    }
    int add_mesh(const nlohmann::json& primitive) {
        return push("meshes", {{"primitives", nlohmann::json::array({primitive})}});
    }
    // A mesh with one primitive: positions (+ normals when given, + indices when given).
    int add_simple_mesh(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals = {},
                        const std::vector<uint32_t>& indices = {}, int mode = 4, int material = -1) {
        nlohmann::json prim = {{"attributes", {{"POSITION", add_vec3(positions)}}}, {"mode", mode}};
        if (!normals.empty()) prim["attributes"]["NORMAL"] = add_vec3(normals);
        if (!indices.empty()) prim["indices"] = add_indices(indices);
        if (material >= 0) prim["material"] = material;
        return add_mesh(prim);
    }
    int add_node(const nlohmann::json& node) { return push("nodes", node); }
    int add_material(const nlohmann::json& material) { return push("materials", material); }
    void set_scene(const std::vector<int>& roots) {
        doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
        doc["scene"] = 0;
    }

    std::filesystem::path write_gltf() {
        nlohmann::json d = doc;
        if (!bin.empty())
            d["buffers"] = nlohmann::json::array(
                {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + encode_base64(bin)}}});
        const auto path = temp_path(".gltf");
        std::ofstream(path) << d.dump(1);
        return path;
    }
    std::filesystem::path write_glb() {
        nlohmann::json d = doc;
        d["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
        std::string json = d.dump();
        while (json.size() % 4 != 0) json += ' ';
        std::vector<unsigned char> data = bin;
        while (data.size() % 4 != 0) data.push_back(0);
        const uint32_t total = uint32_t(12 + 8 + json.size() + 8 + data.size());
        const auto path = temp_path(".glb");
        std::ofstream out(path, std::ios::binary);
        auto put = [&](uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
        put(0x46546C67u);  // "glTF"
        put(2u);
        put(total);
        put(uint32_t(json.size()));
        put(0x4E4F534Au);  // "JSON"
        out.write(json.data(), std::streamsize(json.size()));
        put(uint32_t(data.size()));
        put(0x004E4942u);  // "BIN\0"
        out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size()));
        return path;
    }

private:
    int push(const char* key, const nlohmann::json& value) {
        if (!doc.contains(key)) doc[key] = nlohmann::json::array();
        doc[key].push_back(value);
        return int(doc[key].size()) - 1;
    }
};

// Expects load_gltf with `options` to refuse `file` with a message containing `needle`.
inline void expect_load_refused_with(const std::filesystem::path& file, const fh::LoadOptions& options,
                                     const std::string& needle) {
    try {
        fh::load_gltf(file, options);
        ADD_FAILURE() << "loaded " << file;
    } catch (const fh::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

// Expects load_gltf to refuse `file` with a message containing `needle`.
inline void expect_load_refused(const std::filesystem::path& file, const std::string& needle) {
    expect_load_refused_with(file, fh::LoadOptions{}, needle);
}

}  // namespace fh::test
