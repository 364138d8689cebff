// json_nesting_depth: one pass over the bytes, iterative, so no input can exhaust the stack here.
#include "scene/gltf/json_limits.h"

#include <string>

#include "scene/scene.h"

namespace fh {

size_t json_nesting_depth(std::string_view text, size_t limit) {
    size_t depth = 0, deepest = 0;
    bool in_string = false, escaped = false;
    for (const char c : text) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
            continue;
        }
        if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > deepest) deepest = depth;
            if (deepest > limit) return deepest;
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

void check_json_nesting(std::string_view text, const char* what) {
    if (json_nesting_depth(text) > MAX_JSON_DEPTH)
        throw SceneError(std::string(what) + " nests arrays and objects more than " + std::to_string(MAX_JSON_DEPTH) +
                         " levels deep (the limit)");
}

}  // namespace fh
