#!/usr/bin/env bash
# The speed figures the README reports per device, in one run on whatever Vulkan device fredholm picks (a GPU, or
# lavapipe): the Cornell box at three sizes, the efficiency render, wave sizes, the displaced-sphere ladder (extend
# rays/s over 500,000 diffuse rays, and over 4,000,000 at S = 8 sorted and in file order; render time per sample), a
# textured asset, the three integrators on the hard scenes, time to first pixel.
#   tests/bench/device_figures.sh OUT_DIR [FREDHOLM] [MODELS]
# OUT_DIR gets figures.log (everything printed), JSON per measurement, and cornell_256_64spp.exr (to score against
# the reference elsewhere). MODELS is ../shared/scenes-thirdparty (the DamagedHelmet figure is skipped without it).
# Needs numpy in python3 (or in $PYTHON): the sphere and its rays. Each step is timed by fredholm itself (--stats, bench).
set -uo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: device_figures.sh OUT_DIR [FREDHOLM] [MODELS]}
fredholm=${2:-build/fredholm}
python=${PYTHON:-python3}
models=${3:-../shared/scenes-thirdparty}
mkdir -p "$out"
log="$out/figures.log"
say() { echo "$*" | tee -a "$log"; }
run() { say "\$ $*"; "$@" 2>&1 | tee -a "$log"; }
seconds() { "$python" -c "import json,sys; print(json.load(open(sys.argv[1]))['render_seconds'])" "$1"; }

say "== Cornell box: bench, 64 spp, max depth 10, median of 5"
run "$fredholm" bench --sizes 256 512 1024 --spp 64 --max-depth 10 --repeats 5 --json "$out/cornell_bench.json"

say "== Cornell box 256 x 256, 64 spp, depth 10, seed 0 (the efficiency render): render_seconds of 5 runs"
times=()
for i in 1 2 3 4 5; do
    "$fredholm" render scenes/cornell.gltf -o "$out/cornell_$i.exr" --width 256 --height 256 --spp 64 --max-depth 10 \
        --seed 0 --stats "$out/cornell_$i.json" --quiet 2>&1 | tee -a "$log"
    times+=("$(seconds "$out/cornell_$i.json")")
done
say "render_seconds: ${times[*]}"
mv "$out/cornell_1.exr" "$out/cornell_256_64spp.exr"
say "bit-identical reruns: $(cmp -s "$out/cornell_256_64spp.exr" "$out/cornell_2.exr" && echo yes || echo NO)"
rm -f "$out"/cornell_[2-5].exr "$out"/cornell_[2-5].json

say "== Wave size: Cornell box 1024 x 1024, 64 spp, depth 10 (--wave-paths)"
for wave in 65536 262144 1048576 4194304; do
    "$fredholm" render scenes/cornell.gltf -o "$out/wave.exr" --width 1024 --height 1024 --spp 64 --max-depth 10 \
        --wave-paths $wave --stats "$out/wave.json" --quiet 2>&1 | tee -a "$log"
    say "wave $wave: render_seconds $(seconds "$out/wave.json")"
done
rm -f "$out/wave.exr" "$out/wave.json"

# write_rays MESH FILE COUNT: COUNT diffuse-bounce rays over MESH's surfaces, as compare_embree.py makes them.
write_rays() {
    "$python" - "$1" "$2" "$3" <<'EOF'
import sys, types
import numpy as np
sys.modules["embreex"] = types.ModuleType("embreex")  # only the ray generator is used
for name in ("embreex.rtcore_scene", "embreex.mesh_construction"):
    sys.modules[name] = types.ModuleType(name)
sys.modules["embreex.mesh_construction"].TriangleMesh = None
sys.path.insert(0, "tests/bench")
import compare_embree
triangles = compare_embree.read_triangles(sys.argv[1])
o, d = compare_embree.diffuse_rays(triangles, int(sys.argv[3]), 1)
np.concatenate([o, d], axis=1).astype("<f4").tofile(sys.argv[2])
EOF
}

say "== Displaced sphere in an open box (tests/bench/make_displaced_sphere.py), S = 3..8"
for s in 3 4 5 6 7 8; do
    scene="$out/sphere_$s.glb"
    "$python" tests/bench/make_displaced_sphere.py --subdivisions $s -o "$scene" >/dev/null || { say "sphere $s: failed"; continue; }
    write_rays "$scene" "$out/rays_$s.bin" 500000
    run "$fredholm" bench "$scene" --trace-rays "$out/rays_$s.bin" --repeats 3 --json "$out/trace_$s.json"
    if [ $s = 8 ]; then  # enough rays to fill a GPU, in both orders (tests/bench/RESULTS.md "On a GPU": a figure that varied 4.5x)
        write_rays "$scene" "$out/rays_8_4m.bin" 4000000
        for order in on off; do
            run "$fredholm" bench "$scene" --trace-rays "$out/rays_8_4m.bin" --sort-rays $order --repeats 5 \
                --json "$out/trace_8_4m_sort_$order.json"
        done
        rm -f "$out/rays_8_4m.bin"
    fi
    run "$fredholm" bench "$scene" --sizes 128 1024 --spp 16 --max-depth 10 --repeats 3 --json "$out/sphere_bench_$s.json"
    rm -f "$scene" "$out/rays_$s.bin"
done

if [ -d "$models/DamagedHelmet" ]; then
    say "== DamagedHelmet + courtyard environment, 512 x 512, 64 spp"
    run "$fredholm" bench "$models/DamagedHelmet/glTF/DamagedHelmet.gltf" --env scenes/environments/courtyard.exr \
        --sizes 512 --spp 64 --repeats 3 --json "$out/helmet_bench.json"
fi

say "== Path tracing, light tracing and BDPT on the three hard scenes, 1024 x 1024, 16 spp, depth 8"
for scene in door_gap lamp_shade glass_caustic; do
    for integrator in path light bdpt; do
        run "$fredholm" bench scenes/$scene.gltf --integrator $integrator --sizes 1024 --spp 16 --max-depth 8 --repeats 3 \
            --json "$out/${scene}_$integrator.json"
    done
done

say "== Time to first pixel: 1 spp 64 x 64, whole process (cold: driver shader caches off)"
for mode in cold warm cold warm; do
    start=$(date +%s.%N)
    if [ $mode = cold ]; then
        MESA_SHADER_CACHE_DISABLE=true __GL_SHADER_DISK_CACHE=0 "$fredholm" render scenes/cornell.gltf -o "$out/f.exr" \
            --width 64 --height 64 --spp 1 --quiet
    else
        "$fredholm" render scenes/cornell.gltf -o "$out/f.exr" --width 64 --height 64 --spp 1 --quiet
    fi
    end=$(date +%s.%N)
    say "cornell $mode: $("$python" -c "print(f'{$end - $start:.3f}')") s"
done
rm -f "$out/f.exr"
say "== done"
