// tinygltf compiled from its header into the fuzz build, so that the sanitizers and libFuzzer's coverage see
// inside the JSON parsing too (the normal build links Debian's libtinygltf.so, built from the same header).
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <tiny_gltf.h>
