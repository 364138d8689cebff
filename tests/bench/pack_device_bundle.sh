#!/usr/bin/env bash
# Packs the Release build for a machine that has a GPU but not this one's libraries: the fredholm binary, the GPU-side
# test binaries and generated scenes (ctest -L 'render|stability|gpu|robustness' runs from it), the shared libraries
# they load (all but the C and C++ runtimes, which the other machine has), and Debian's Vulkan validation layer.
#   tests/bench/pack_device_bundle.sh OUT.tar.xz [BUILD_DIR]
# On the other machine: tar xJf OUT.tar.xz -C DIR; export LD_LIBRARY_PATH=DIR/lib VK_LAYER_PATH=DIR/layers; run
# DIR/build/fredholm. For ctest, first run `DIR/setup.sh` (as root) from the repository's root there: it makes the paths
# this build was configured with lead to that checkout, DIR/build, REFERENCES (default ../shared/references) and that
# machine's cmake and python3 (with numpy); it prints the exports above.
# tests/bench/RESULTS.md "On a GPU" reports what came of it.
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
# What ctest needs at the configured paths: the source tree, the build, ../shared/references, cmake (the render
# tests are cmake -P scripts), python3 (the scene generators) and CMake's GoogleTestAddTests.cmake (gtest_discover_tests).
cache() { sed -n "s#^$1:[A-Z]*=##p" "$build/CMakeCache.txt"; }
gtest_module=$( (grep -rho '"/[^"]*/GoogleTestAddTests.cmake"' --include='*_include.cmake' "$build" || true) |
               sort -u | head -n 1 | tr -d '"')
[ -n "$gtest_module" ] && cp "$gtest_module" "$stage/GoogleTestAddTests.cmake"
cat > "$stage/setup.sh" <<SETUP
#!/usr/bin/env bash
# Written by tests/bench/pack_device_bundle.sh. Run from the repository's root on the machine the bundle went to.
set -eu
here=\$(cd "\$(dirname "\$0")" && pwd)
# link TARGET PATH: PATH leads to TARGET, unless something other than a link is there already (then it is left alone)
# or the build recorded no such path.
link() {
    [ -n "\$2" ] || return 0
    if [ -e "\$2" ] && [ ! -L "\$2" ]; then
        [ "\$(realpath "\$1")" = "\$(realpath "\$2")" ] || echo "setup.sh: \$2 exists; left as it is" >&2
        return 0
    fi
    mkdir -p "\$(dirname "\$2")"; ln -sfn "\$1" "\$2"
}
[ "\$PWD" = "$(cache CMAKE_HOME_DIRECTORY)" ] || link "\$PWD" "$(cache CMAKE_HOME_DIRECTORY)"
[ "\$here/build" = "$(realpath -m "$build")" ] || link "\$here/build" "$(realpath -m "$build")"
# The reference EXRs (render.cornell_references): REFERENCES, or ../shared/references beside the checkout.
references=\${REFERENCES:-\$PWD/../shared/references}
[ ! -d "\$references" ] || link "\$references" "$(realpath -m "$(cache FH_REFERENCES)")"
link "\$(command -v cmake)" "$(cache CMAKE_COMMAND)"
python=\$(command -v python3)
# The scene generators need numpy; the NVIDIA machines lent here have it in /opt/torch/.venv.
"\$python" -c "import numpy" 2>/dev/null || [ ! -x /opt/torch/.venv/bin/python3 ] || python=/opt/torch/.venv/bin/python3
link "\$python" "$(cache _Python3_EXECUTABLE)"
[ -z "$gtest_module" ] || [ -e "$gtest_module" ] || { mkdir -p "$(dirname "$gtest_module")"; cp "\$here/GoogleTestAddTests.cmake" "$gtest_module"; }
echo "export LD_LIBRARY_PATH=\$here/lib VK_LAYER_PATH=\$here/layers"
SETUP
chmod +x "$stage/setup.sh"
find "$stage/build" -type f -perm -u+x -exec strip --strip-unneeded {} + 2>/dev/null || true
strip --strip-unneeded "$stage"/layers/*.so "$stage"/lib/*
XZ_OPT=-T2 tar cJf "$out.tmp" -C "$stage" . && mv "$out.tmp" "$out"
echo "$out: $(du -h "$out" | cut -f1)"
