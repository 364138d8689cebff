// libFuzzer entry point: feeds arbitrary bytes to fh::load_gltf as a scene file.
//
// A SceneError is the loader doing its job; anything else (another exception, an abort, an ASan or UBSan
// report, a timeout, running out of memory) is a finding. The bytes go to a file because load_gltf takes a
// path: `input.gltf` in a directory of this process's own (GLB is recognised by its magic, not the name).
// tinygltf looks up URIs in that directory (joining even absolute ones onto it), then in the working directory,
// and `..` climbs out of both; but the loader only ever reads, and only regular files up to a size limit (a
// FIFO, device or directory is refused), so a URI can neither block, write, nor exhaust memory.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "scene/scene.h"

namespace {

const std::filesystem::path& input_path() {
    static const std::filesystem::path path = [] {
        const auto dir = std::filesystem::temp_directory_path() / ("fh_fuzz_" + std::to_string(getpid()));
        std::filesystem::create_directories(dir);
        return dir / "input.gltf";
    }();
    // Registered after `path` is built, so the clean-up runs before `path` is destroyed.
    static const bool clean_up_at_exit = std::atexit([] {
        std::error_code ec;
        std::filesystem::remove_all(input_path().parent_path(), ec);
    }) == 0;
    (void)clean_up_at_exit;
    return path;
}

void write_input(const uint8_t* data, size_t size) {
    std::FILE* file = std::fopen(input_path().c_str(), "wb");
    if (!file) __builtin_trap();  // the harness itself is broken: stop at once rather than fuzz nothing
    if (size > 0 && std::fwrite(data, 1, size, file) != size) __builtin_trap();
    std::fclose(file);
}

}  // namespace

// Textures may take this much (--memory-limit): a few images of 16384^2 texels are a valid file, but more than the
// fuzzer's 2 GiB; refusing them is the loader's job, and what the limit is for.
constexpr uint64_t FUZZ_MEMORY_LIMIT = uint64_t(512) << 20;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    write_input(data, size);
    fh::LoadOptions plain;
    plain.memory_limit = FUZZ_MEMORY_LIMIT;
    try {
        (void)fh::load_gltf(input_path(), plain);
    } catch (const fh::SceneError&) {
    }
    // Posed by its first animation too (glTF animation, skins and morph weights at a time inside and past the keys), the
    // first time with a shutter open over it (motion blur: moving nodes become moving instances, the camera moves).
    for (double time : {0.37, 1e6}) {
        fh::LoadOptions posed = plain;
        posed.animate = true;
        posed.time = time;
        if (time < 1.0) {
            posed.shutter_open = -0.3;
            posed.shutter_close = 0.2;
        }
        try {
            (void)fh::load_gltf(input_path(), posed);
        } catch (const fh::SceneError&) {
        }
    }
    return 0;
}
