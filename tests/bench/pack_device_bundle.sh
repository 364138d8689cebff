#!/usr/bin/env bash
# Packs the Release build for a machine that has a GPU but not this one's libraries: the fredholm binary, the GPU-side
# test binaries and generated scenes (ctest -L 'render|stability|gpu|robustness' runs from it), the shared libraries
# they load (all but the C and C++ runtimes, which the other machine has), and Debian's Vulkan validation layer.
#   tests/bench/pack_device_bundle.sh OUT.tar.xz [BUILD_DIR]
# On the other machine: tar xJf OUT.tar.xz -C DIR; export LD_LIBRARY_PATH=DIR/lib VK_LAYER_PATH=DIR/layers; run
# DIR/build/fredholm (and, for ctest, make the source tree and DIR/build reachable at the paths this build was
# configured with, /work/main and /work/main/build here). README "On a GPU" reports what came of it.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$(realpath -m "${1:?usage: pack_device_bundle.sh OUT.tar.xz [BUILD_DIR]}")
build=${2:-build}
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/lib" "$stage/layers"
for lib in $(ldd "$build/fredholm" "$build"/tests/*/test_* "$build"/tests/stability/*/test_* 2>/dev/null |
             awk '/=>/ {print $3}' | sort -u); do
    case $(basename "$lib") in
        libc.so* | libm.so* | libdl.so* | libpthread.so* | libgcc_s.so* | libstdc++.so* | ld-linux* | librt.so*) ;;
        *) cp -L "$lib" "$stage/lib/" ;;
    esac
done
cp -L /usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so "$stage/layers/"
sed 's#"library_path": *"[^"]*"#"library_path": "./libVkLayer_khronos_validation.so"#' \
    /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json > "$stage/layers/VkLayer_khronos_validation.json"
# Executables, the CTest files and the scenes the tests generate; not objects, the unit and fuzz tests (CPU only).
(cd "$build" && find . \( -name CMakeFiles -o -path ./test-output -o -path ./Testing -o -path ./tests/unit \
                          -o -path ./tests/fuzz -o -path ./engine -o -path ./shaders \) -prune -o \
    -type f \( -perm -u+x -o -name '*.cmake' -o -name '*.gltf' -o -name '*.bin' -o -name '*.png' -o -name '*.glb' \
               -o -name '*.exr' -o -name CMakeCache.txt \) -print) | sed 's#^\./##' > "$stage/files"
mkdir -p "$stage/build"
tar cf - -C "$build" -T "$stage/files" | tar xf - -C "$stage/build"
rm "$stage/files"
find "$stage/build" -type f -perm -u+x -exec strip --strip-unneeded {} + 2>/dev/null || true
strip --strip-unneeded "$stage"/layers/*.so "$stage"/lib/*
XZ_OPT=-T2 tar cJf "$out.tmp" -C "$stage" . && mv "$out.tmp" "$out"
echo "$out: $(du -h "$out" | cut -f1)"
