// Limits checked on JSON text before a recursive parser sees it (issue: a 60 KB file of 30,000 nested arrays
// overflowed the stack while tinygltf parsed or destroyed it).
#pragma once
#include <cstddef>
#include <string_view>

namespace fh {

// Deeper nesting than any glTF needs (its schema nests a few levels; `extras` are the user's): refused.
inline constexpr size_t MAX_JSON_DEPTH = 1000;

// The deepest nesting of arrays and objects in `text`, counted without parsing (brackets inside strings, escapes
// included, do not count). Stops counting once past `limit`, so it returns at most limit + 1.
size_t json_nesting_depth(std::string_view text, size_t limit = MAX_JSON_DEPTH);

// Throws SceneError ("JSON nested N levels deep, more than the limit of ...") when `text` nests deeper than
// MAX_JSON_DEPTH; `what` names the text ("the glTF JSON", "the GLB's JSON chunk").
void check_json_nesting(std::string_view text, const char* what);

}  // namespace fh
