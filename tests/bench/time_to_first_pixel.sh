#!/usr/bin/env bash
# Time to first pixel: wall clock of a whole 1-spp 64x64 render (process start, load, Vulkan, pipelines, render,
# EXR), cold (Mesa's shader cache and Fredholm's cache of specialised SPIR-V both off) and warm (both filled by the
# run before), for scenes with more and more effects. Usage: tests/bench/time_to_first_pixel.sh [FREDHOLM]   (needs ../shared/scenes-thirdparty)
set -euo pipefail
cd "$(dirname "$0")/../.."
fredholm=${1:-build/fredholm}
models=../shared/scenes-thirdparty
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
run() {  # mode scene [args...]
    local mode=$1 scene=$2
    shift 2
    local start end
    start=$(date +%s.%N)
    if [ "$mode" = cold ]; then
        MESA_SHADER_CACHE_DISABLE=true FREDHOLM_SPIRV_CACHE=off "$fredholm" render "$scene" "$@" -o "$out/f.exr" --width 64 --height 64 --spp 1 \
            --stats "$out/s.json" >/dev/null 2>&1
    else
        "$fredholm" render "$scene" "$@" -o "$out/f.exr" --width 64 --height 64 --spp 1 --stats "$out/s.json" >/dev/null 2>&1
    fi
    end=$(date +%s.%N)
    [ "$mode" = fill ] && return  # a warm run that fills the caches, not reported
    python3 -c "import json, sys; j = json.load(open('$out/s.json'))
print(f'{sys.argv[1]:<34} {sys.argv[2]:<5} wall {float(sys.argv[4]) - float(sys.argv[3]):.2f} s, load {j[\"load_seconds\"]:.3f} s, '
      f'render (with the pipelines\' compile) {j[\"render_seconds\"]:.3f} s')" "$(basename "$scene")" "$mode" "$start" "$end"
}
env=(--env scenes/environments/courtyard.exr)
for mode in fill cold warm cold warm; do  # fill first, so that the first warm run is warm
    run $mode scenes/cornell.gltf
    run $mode "$models/DamagedHelmet/glTF/DamagedHelmet.gltf" "${env[@]}"
    run $mode "$models/GlassHurricaneCandleHolder/glTF/GlassHurricaneCandleHolder.gltf" "${env[@]}"
    run $mode "$models/IridescenceLamp/glTF/IridescenceLamp.gltf" "${env[@]}"
done
