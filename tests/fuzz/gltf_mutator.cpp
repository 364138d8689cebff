// A structure-aware libFuzzer mutator for glTF (linked into fuzz_load_gltf_structured; README.md here). Byte mutations
// seldom keep JSON valid, so they rarely reach what the loader does after parsing. This one parses the input's JSON
// (a .gltf, or a .glb's JSON chunk, whose BIN chunk is kept), changes its structure the way a hostile file would, and
// writes it back:
//   - numbers at the edges (0, -1, 2^31, 2^32 - 1, 2^53, 1e308, denormals) and references to missing objects;
//   - deep nesting and wide arrays; node cycles and shared children;
//   - accessors and buffer views placed at the very end of their buffers, or one element past;
//   - an extension object of every kind the loader reads, with hostile fields, and animation pointers;
//   - images whose headers (PNG, JPEG, WebP) declare huge sizes;
//   - a value of the wrong type, a deleted key, a value moved elsewhere.
// Half the time (or where the input is not JSON) libFuzzer's own byte mutation runs instead.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/gltf/json_limits.h"  // json_nesting_depth: the loader's own scan, no recursion

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

namespace {

using nlohmann::json;
using Random = std::mt19937_64;

constexpr size_t MAX_WALK_DEPTH = 64;  // values nested deeper are left alone (the walk recurses)
// Documents nested deeper are mutated as bytes: nlohmann copies and prints a value recursively, a dozen frames a level
// under AddressSanitizer, and a few thousand levels (a deep input, nested deeper again) overflowed the stack in this
// mutator, not in the loader (2026-11-30, CI).
constexpr size_t MAX_STRUCTURED_DEPTH = 1200;

size_t pick(Random& random, size_t n) { return n == 0 ? 0 : size_t(random() % n); }

template <typename T>
const T& pick_of(Random& random, const std::vector<T>& items) { return items[pick(random, items.size())]; }

json hostile_number(Random& random) {
    static const std::vector<double> edges = {0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 3.0, 4.0, 255.0, 256.0, 65535.0, 65536.0,
                                              2147483647.0, 2147483648.0, -2147483648.0, 4294967295.0, 4294967296.0,
                                              9007199254740992.0, 1.8446744073709552e19, 3.4e38, 3.5e38, 1e308, -1e308,
                                              1e-45, 1e-320, 0.9999999, 1.0000001};
    const double v = pick_of(random, edges);
    if (random() % 3 == 0 && std::abs(v) < 1e15 && v == double(int64_t(v))) return int64_t(v);
    return v;
}

json hostile_index(Random& random, size_t count) {
    switch (random() % 6) {
        case 0: return -1;
        case 1: return int64_t(count);  // one past the end
        case 2: return int64_t(count) + 1000000;
        case 3: return 4294967295u;
        default: return int64_t(pick(random, count + 1));
    }
}

// Every value in the document (up to MAX_WALK_DEPTH), with the key it sits under ("" in arrays).
struct Place {
    json* value;
    std::string key;
    json* parent;
};

void walk(json& value, const std::string& key, json* parent, size_t depth, std::vector<Place>& places) {
    places.push_back({&value, key, parent});
    if (depth >= MAX_WALK_DEPTH) return;
    if (value.is_object())
        for (auto it = value.begin(); it != value.end(); ++it) walk(it.value(), it.key(), &value, depth + 1, places);
    else if (value.is_array())
        for (json& item : value) walk(item, "", &value, depth + 1, places);
}

size_t count_of(const json& doc, const char* array) {
    return doc.contains(array) && doc[array].is_array() ? doc[array].size() : 0;
}

// A textureInfo with hostile fields (and sometimes KHR_texture_transform).
json texture_info(Random& random, const json& doc) {
    json info{{"index", hostile_index(random, count_of(doc, "textures"))}};
    if (random() % 2) info["texCoord"] = hostile_number(random);
    if (random() % 3 == 0) info["scale"] = hostile_number(random);
    if (random() % 3 == 0)
        info["extensions"]["KHR_texture_transform"] = {{"offset", {hostile_number(random), hostile_number(random)}},
                                                       {"rotation", hostile_number(random)},
                                                       {"scale", {hostile_number(random), hostile_number(random)}},
                                                       {"texCoord", hostile_number(random)}};
    return info;
}

// A value for an extension field, by its name's kind.
json field_value(Random& random, const json& doc, const std::string& field) {
    if (field.size() > 7 && field.compare(field.size() - 7, 7, "Texture") == 0) return texture_info(random, doc);
    if (field.find("Color") != std::string::npos || field == "diffuseFactor")
        return json::array({hostile_number(random), hostile_number(random), hostile_number(random), hostile_number(random)});
    return hostile_number(random);
}

struct ExtensionKind {
    const char* name;
    const char* on;  // "materials", "nodes", "textures", "bufferViews", "primitive", "root"
    std::vector<const char*> fields;
};

const std::vector<ExtensionKind>& extension_kinds() {
    static const std::vector<ExtensionKind> kinds = {
        {"KHR_materials_clearcoat", "materials", {"clearcoatFactor", "clearcoatTexture", "clearcoatRoughnessFactor", "clearcoatRoughnessTexture", "clearcoatNormalTexture"}},
        {"KHR_materials_sheen", "materials", {"sheenColorFactor", "sheenColorTexture", "sheenRoughnessFactor", "sheenRoughnessTexture"}},
        {"KHR_materials_specular", "materials", {"specularFactor", "specularTexture", "specularColorFactor", "specularColorTexture"}},
        {"KHR_materials_transmission", "materials", {"transmissionFactor", "transmissionTexture"}},
        {"KHR_materials_volume", "materials", {"thicknessFactor", "thicknessTexture", "attenuationDistance", "attenuationColor"}},
        {"KHR_materials_ior", "materials", {"ior"}},
        {"KHR_materials_iridescence", "materials", {"iridescenceFactor", "iridescenceTexture", "iridescenceIor", "iridescenceThicknessMinimum", "iridescenceThicknessMaximum", "iridescenceThicknessTexture"}},
        {"KHR_materials_anisotropy", "materials", {"anisotropyStrength", "anisotropyRotation", "anisotropyTexture"}},
        {"KHR_materials_dispersion", "materials", {"dispersion"}},
        {"KHR_materials_diffuse_transmission", "materials", {"diffuseTransmissionFactor", "diffuseTransmissionTexture", "diffuseTransmissionColorFactor", "diffuseTransmissionColorTexture"}},
        {"KHR_materials_emissive_strength", "materials", {"emissiveStrength"}},
        {"KHR_materials_unlit", "materials", {}},
        {"KHR_materials_pbrSpecularGlossiness", "materials", {"diffuseFactor", "diffuseTexture", "specularFactor", "glossinessFactor", "specularGlossinessTexture"}},
        {"KHR_node_visibility", "nodes", {"visible"}},
        {"KHR_lights_punctual", "nodes", {"light"}},
        {"EXT_mesh_gpu_instancing", "nodes", {}},
        {"EXT_texture_webp", "textures", {"source"}},
        {"KHR_texture_basisu", "textures", {"source"}},
        {"EXT_meshopt_compression", "bufferViews", {"buffer", "byteOffset", "byteLength", "byteStride", "count"}},
        {"KHR_draco_mesh_compression", "primitive", {"bufferView"}},
        {"KHR_materials_variants", "primitive", {}},
        {"KHR_lights_punctual", "root", {}},
        {"KHR_materials_variants", "root", {}},
    };
    return kinds;
}

json light(Random& random) {
    static const std::vector<const char*> types = {"point", "spot", "directional", "area", ""};
    return {{"type", pick_of(random, types)},
            {"color", {hostile_number(random), hostile_number(random), hostile_number(random)}},
            {"intensity", hostile_number(random)},
            {"range", hostile_number(random)},
            {"spot", {{"innerConeAngle", hostile_number(random)}, {"outerConeAngle", hostile_number(random)}}}};
}

// The extension object itself, for the kinds whose shape is more than fields.
json extension_object(Random& random, const json& doc, const ExtensionKind& kind) {
    json object = json::object();
    for (const char* field : kind.fields)
        if (random() % 4) object[field] = field_value(random, doc, field);
    const std::string name = kind.name, on = kind.on;
    if (name == "EXT_mesh_gpu_instancing")
        for (const char* a : {"TRANSLATION", "ROTATION", "SCALE"})
            if (random() % 2) object["attributes"][a] = hostile_index(random, count_of(doc, "accessors"));
    if (name == "KHR_lights_punctual" && on == "root")
        for (size_t i = 0, n = 1 + pick(random, 4); i < n; ++i) object["lights"].push_back(light(random));
    if (name == "KHR_materials_variants" && on == "root")
        for (size_t i = 0, n = 1 + pick(random, 3); i < n; ++i) object["variants"].push_back({{"name", "v" + std::to_string(i)}});
    if (name == "KHR_materials_variants" && on == "primitive")
        object["mappings"] = json::array({{{"material", hostile_index(random, count_of(doc, "materials"))},
                                           {"variants", {hostile_index(random, 3), hostile_index(random, 3)}}}});
    if (name == "KHR_draco_mesh_compression")
        object["attributes"] = {{"POSITION", hostile_index(random, 4)}, {"NORMAL", hostile_index(random, 4)}};
    if (name == "EXT_meshopt_compression") {
        static const std::vector<const char*> modes = {"ATTRIBUTES", "TRIANGLES", "INDICES", "OTHER"};
        static const std::vector<const char*> filters = {"NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL", "OTHER"};
        object["mode"] = pick_of(random, modes);
        object["filter"] = pick_of(random, filters);
    }
    return object;
}

void declare(json& doc, const std::string& name, Random& random) {
    for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
        if (std::string(list) == "extensionsRequired" && random() % 3) continue;
        if (!doc[list].is_array()) doc[list] = json::array();
        doc[list].push_back(name);
    }
}

void add_extension(json& doc, Random& random) {
    const ExtensionKind& kind = pick_of(random, extension_kinds());
    const std::string on = kind.on;
    json* owner = nullptr;
    if (on == "root") {
        owner = &doc;
    } else if (on == "primitive") {
        if (count_of(doc, "meshes") == 0) return;
        json& mesh = doc["meshes"][pick(random, doc["meshes"].size())];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array() || mesh["primitives"].empty())
            return;
        owner = &mesh["primitives"][pick(random, mesh["primitives"].size())];
    } else {
        if (count_of(doc, on.c_str()) == 0) doc[on] = json::array({json::object()});
        owner = &doc[on][pick(random, doc[on].size())];
    }
    if (!owner->is_object()) return;
    (*owner)["extensions"][kind.name] = extension_object(random, doc, kind);
    declare(doc, kind.name, random);
}

void add_animation_pointer(json& doc, Random& random) {
    static const std::vector<std::string> pointers = {
        "/materials/N/pbrMetallicRoughness/baseColorFactor", "/materials/N/emissiveFactor",
        "/materials/N/pbrMetallicRoughness/roughnessFactor", "/materials/N/alphaCutoff",
        "/materials/N/extensions/KHR_materials_emissive_strength/emissiveStrength",
        "/materials/N/extensions/KHR_materials_transmission/transmissionFactor",
        "/materials/N/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/offset",
        "/nodes/N/translation", "/nodes/N/rotation", "/nodes/N/scale", "/nodes/N/weights",
        "/nodes/N/extensions/KHR_node_visibility/visible", "/cameras/N/perspective/yfov", "/cameras/N/orthographic/xmag",
        "/extensions/KHR_lights_punctual/lights/N/intensity", "/extensions/KHR_lights_punctual/lights/N/color",
        "/extensions/KHR_lights_punctual/lights/N/spot/outerConeAngle", "/meshes/N/weights", "/", "", "//", "/nodes",
        "/nodes/N", "/materials/N/unknown/path/N"};
    std::string pointer = pick_of(random, pointers);
    for (size_t at; (at = pointer.find("/N")) != std::string::npos;)  // each index: small, or hostile
        pointer.replace(at + 1, 1, random() % 5 ? std::to_string(pick(random, 3))
                                                : std::to_string(hostile_index(random, 3).get<int64_t>()));
    if (!doc["animations"].is_array() || doc["animations"].empty())
        doc["animations"] = json::array({{{"channels", json::array()}, {"samplers", json::array()}}});
    json& animation = doc["animations"][pick(random, doc["animations"].size())];
    if (!animation.is_object()) return;
    if (!animation["samplers"].is_array()) animation["samplers"] = json::array();
    const size_t accessors = count_of(doc, "accessors");
    static const std::vector<const char*> interpolations = {"LINEAR", "STEP", "CUBICSPLINE", "OTHER"};
    animation["samplers"].push_back({{"input", hostile_index(random, accessors)}, {"output", hostile_index(random, accessors)},
                                     {"interpolation", pick_of(random, interpolations)}});
    if (!animation["channels"].is_array()) animation["channels"] = json::array();
    animation["channels"].push_back(
        {{"sampler", hostile_index(random, animation["samplers"].size())},
         {"target", {{"path", "pointer"}, {"extensions", {{"KHR_animation_pointer", {{"pointer", pointer}}}}}}}});
    declare(doc, "KHR_animation_pointer", random);
}

std::string base64(const std::string& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= uint8_t(bytes[i + 2]);
        out += digits[v >> 18 & 63];
        out += digits[v >> 12 & 63];
        out += i + 1 < bytes.size() ? digits[v >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? digits[v & 63] : '=';
    }
    return out;
}

std::string big_endian(uint32_t v, int bytes) {
    std::string s;
    for (int i = bytes - 1; i >= 0; --i) s += char(v >> (8 * i) & 0xff);
    return s;
}

// An image header declaring a hostile size, with little or nothing after it.
std::string hostile_image(Random& random, std::string& mime) {
    static const std::vector<uint32_t> sides = {0, 1, 16384, 16385, 30000, 65535, 65536, 2147483647u, 4294967295u};
    const uint32_t w = pick_of(random, sides), h = pick_of(random, sides);
    switch (random() % 3) {
        case 0: {
            mime = "image/png";
            const std::string ihdr = "IHDR" + big_endian(w, 4) + big_endian(h, 4) + std::string("\x08\x06\x00\x00\x00", 5);
            return std::string("\x89PNG\r\n\x1a\n", 8) + big_endian(13, 4) + ihdr + big_endian(0, 4);
        }
        case 1:
            mime = "image/jpeg";
            return std::string("\xff\xd8\xff\xc0\x00\x11\x08", 7) + big_endian(h & 0xffff, 2) + big_endian(w & 0xffff, 2) +
                   std::string("\x03\x01\x22\x00\x02\x11\x01\x03\x11\x01\xff\xd9", 12);
        default: {
            mime = "image/webp";
            // VP8L: 14-bit width - 1 and height - 1 after the signature byte 0x2f.
            const uint32_t bits = ((w - 1) & 0x3fff) | ((h - 1) & 0x3fff) << 14;
            std::string vp8l = std::string("\x2f", 1);
            for (int i = 0; i < 4; ++i) vp8l += char(bits >> (8 * i) & 0xff);
            std::string chunk = "VP8L" + std::string(1, char(vp8l.size())) + std::string(3, '\0') + vp8l;
            const uint32_t riff = uint32_t(4 + chunk.size());
            std::string le;
            for (int i = 0; i < 4; ++i) le += char(riff >> (8 * i) & 0xff);
            return "RIFF" + le + "WEBP" + chunk;
        }
    }
}

void add_hostile_image(json& doc, Random& random) {
    std::string mime;
    const std::string bytes = hostile_image(random, mime);
    if (!doc["images"].is_array()) doc["images"] = json::array();
    doc["images"].push_back({{"uri", "data:" + mime + ";base64," + base64(bytes)}});
    if (!doc["textures"].is_array()) doc["textures"] = json::array();
    doc["textures"].push_back({{"source", doc["images"].size() - 1}});
    if (count_of(doc, "materials") == 0) doc["materials"] = json::array({json::object()});
    json& material = doc["materials"][pick(random, doc["materials"].size())];
    if (material.is_object()) material["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", doc["textures"].size() - 1}};
}

// An accessor or buffer view placed at the end of what holds it, or one element past.
void place_at_edge(json& doc, Random& random) {
    if (count_of(doc, "accessors") == 0 || count_of(doc, "bufferViews") == 0) return;
    json& accessor = doc["accessors"][pick(random, doc["accessors"].size())];
    if (!accessor.is_object() || !accessor.contains("bufferView") || !accessor["bufferView"].is_number_unsigned()) return;
    const uint64_t v = accessor["bufferView"].get<uint64_t>();
    if (v >= doc["bufferViews"].size() || !doc["bufferViews"][v].is_object()) return;
    json& view = doc["bufferViews"][v];
    const json& byte_length = view.contains("byteLength") ? view["byteLength"] : json(0);
    const double length_value = byte_length.is_number() ? byte_length.get<double>() : 0.0;
    const int64_t length = length_value >= 0.0 && length_value < 1e15 ? int64_t(length_value) : 0;
    const int64_t element = 12;  // a VEC3 of floats, the commonest
    const int64_t past = int64_t(random() % 2);
    if (random() % 2) {
        accessor["byteOffset"] = std::max<int64_t>(0, length - element + past * 4);
        accessor["count"] = 1;
    } else {
        accessor["count"] = length / element + past;
        accessor.erase("byteOffset");
    }
    if (random() % 3 == 0) view["byteOffset"] = length / 2 + past;
}

void make_node_cycle(json& doc, Random& random) {
    const size_t n = count_of(doc, "nodes");
    if (n == 0) return;
    for (size_t k = 0, edges = 1 + pick(random, 3); k < edges; ++k) {
        json& node = doc["nodes"][pick(random, n)];
        if (!node.is_object()) continue;
        if (!node["children"].is_array()) node["children"] = json::array();
        node["children"].push_back(pick(random, n));  // perhaps itself, an ancestor or a node shared with another
    }
}

void nest_deeply(json& target, Random& random) {
    static const std::vector<size_t> depths = {64, 999, 1000, 1001, 4000};
    const size_t depth = pick_of(random, depths);
    json value = target;
    for (size_t i = 0; i < depth; ++i) value = json::array({std::move(value)});
    target = std::move(value);
}

void widen(json& target, Random& random) {
    if (!target.is_array() || target.empty()) return;
    const size_t copies = size_t(1) << (1 + pick(random, 6));
    const json item = target[pick(random, target.size())];
    for (size_t i = 0; i < copies; ++i) target.push_back(item);
}

json wrong_type(Random& random) {
    switch (random() % 6) {
        case 0: return nullptr;
        case 1: return true;
        case 2: return "x";
        case 3: return json::object();
        case 4: return json::array();
        default: return json::array({hostile_number(random)});
    }
}

bool is_reference_key(const std::string& key) {
    static const std::vector<std::string> keys = {"mesh", "camera", "skin", "material", "indices", "bufferView", "buffer",
                                                  "source", "sampler", "index", "node", "input", "output", "scene",
                                                  "POSITION", "NORMAL", "TANGENT", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0",
                                                  "JOINTS_0", "WEIGHTS_0", "inverseBindMatrices", "skeleton", "light"};
    for (const std::string& k : keys)
        if (k == key) return true;
    return false;
}

// One mutation; true when it nested a value deeply (the document takes no more mutations, nor copies of that value).
bool mutate_document(json& doc, Random& random) {
    std::vector<Place> places;
    walk(doc, "", nullptr, 0, places);
    Place place = pick_of(random, places);
    switch (random() % 12) {
        case 0:
        case 1: {  // a number at an edge, or a reference to an object that may not exist
            std::vector<Place> numbers;
            for (const Place& p : places)
                if (p.value->is_number()) numbers.push_back(p);
            if (numbers.empty()) break;
            const Place& n = pick_of(random, numbers);
            *n.value = is_reference_key(n.key) && random() % 2 ? hostile_index(random, 8) : hostile_number(random);
            break;
        }
        case 2: nest_deeply(*place.value, random); return true;
        case 3: widen(*place.value, random); break;
        case 4: make_node_cycle(doc, random); break;
        case 5: place_at_edge(doc, random); break;
        case 6:
        case 7: add_extension(doc, random); break;
        case 8: add_animation_pointer(doc, random); break;
        case 9: add_hostile_image(doc, random); break;
        case 10: *place.value = wrong_type(random); break;
        default:  // delete a key, or copy one value over another (a structure where another is expected)
            if (place.parent && place.parent->is_object() && random() % 2) place.parent->erase(place.key);
            else *place.value = json(*pick_of(random, places).value);
            break;
    }
    return false;
}

uint32_t load_le32(const uint8_t* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24; }
void store_le32(std::string& s, uint32_t v) {
    for (int i = 0; i < 4; ++i) s += char(v >> (8 * i) & 0xff);
}

// The JSON text of a .gltf or of a .glb's JSON chunk, and what follows the chunk (a .glb's BIN chunk).
bool split_input(const uint8_t* data, size_t size, std::string& text, std::string& rest, bool& glb) {
    glb = size >= 20 && std::memcmp(data, "glTF", 4) == 0;
    if (!glb) {
        text.assign(reinterpret_cast<const char*>(data), size);
        return true;
    }
    const uint64_t length = load_le32(data + 12);
    if (load_le32(data + 16) != 0x4E4F534Au || 20 + length > size) return false;
    text.assign(reinterpret_cast<const char*>(data + 20), size_t(length));
    rest.assign(reinterpret_cast<const char*>(data + 20 + length), size_t(size - 20 - length));
    return true;
}

std::string join_output(std::string text, const std::string& rest, bool glb) {
    if (!glb) return text;
    while (text.size() % 4) text += ' ';
    std::string out = "glTF";
    store_le32(out, 2);
    store_le32(out, uint32_t(20 + text.size() + rest.size()));
    store_le32(out, uint32_t(text.size()));
    store_le32(out, 0x4E4F534Au);
    return out + text + rest;
}

}  // namespace

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size, unsigned int seed) {
    Random random(seed);
    std::string text, rest;
    bool glb = false;
    if (random() % 2 == 0 || !split_input(data, size, text, rest, glb) ||
        fh::json_nesting_depth(text, MAX_STRUCTURED_DEPTH) > MAX_STRUCTURED_DEPTH)
        return LLVMFuzzerMutate(data, size, max_size);
    json doc = json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return LLVMFuzzerMutate(data, size, max_size);
    std::string out;
    try {  // a mutation meets values of any type: where nlohmann refuses one, the bytes are mutated instead
        for (size_t i = 0, n = 1 + pick(random, 3); i < n; ++i)
            if (mutate_document(doc, random)) break;
        out = join_output(doc.dump(), rest, glb);
    } catch (const nlohmann::json::exception&) {
        return LLVMFuzzerMutate(data, size, max_size);
    }
    if (out.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
    std::memcpy(data, out.data(), out.size());
    return out.size();
}
