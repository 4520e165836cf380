#!/usr/bin/env bash
# The view-factor benchmark family (tools/make_formfactor_family.py): for each scene,
# tools/bench_formfactors on the cpu backend with shaft culling off, culling always (no cost
# model) and culling with the cost model, interleaved in one run so that load from other work
# hits all three alike. Prints one row a scene: the three pair-loop times, their ratios, the
# rays cast and what was skipped without rays (facing away, clear shafts, covered).
# Usage: tools/bench_formfactor_family.sh [BUILD_DIR] [--small] [--rays K] [--reverse]
# (--reverse: run the three modes in the opposite order; on a loaded machine, run it both ways
# and take the best of each.)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
shift || true
suffix=""
rays=4
reverse=0
while [[ $# -gt 0 ]]; do
    case "$1" in
        --small) suffix="_small" ;;
        --rays) rays="$2"; shift ;;
        --reverse) reverse=1 ;;
        *) echo "unknown argument $1" >&2; exit 2 ;;
    esac
    shift
done
family="$root/assets/scenes/formfactor_family"
if [[ -n "$suffix" ]]; then first="$family/blacklight_small.gltf"; else first="$root/assets/scenes/blacklight_box.gltf"; fi
scenes=("$first" "$family/blender_room$suffix.gltf" "$family/open$suffix.gltf"
        "$family/cluttered$suffix.gltf" "$family/far_triangle$suffix.gltf")
printf "%-22s %8s %8s %8s %9s %9s %12s %12s %12s %12s\n" scene off_s cull_s model_s model/best cull/off \
    rays_model facing_away clear_shafts covered
for scene in "${scenes[@]}"; do
    # CSV columns (bench_formfactors): 9 facing_away, 10 clear_cluster, 11 clear_pair,
    # 12 covered, 16 rays, 19 pair_s.
    if [[ $reverse == 0 ]]; then
        off=$("$build/bench_formfactors" "$scene" --rays "$rays" --no-culling)
        cull=$("$build/bench_formfactors" "$scene" --rays "$rays" --no-cost-model)
        model=$("$build/bench_formfactors" "$scene" --rays "$rays")
    else
        model=$("$build/bench_formfactors" "$scene" --rays "$rays")
        cull=$("$build/bench_formfactors" "$scene" --rays "$rays" --no-cost-model)
        off=$("$build/bench_formfactors" "$scene" --rays "$rays" --no-culling)
    fi
    awk -F, -v name="$(basename "$scene" .gltf)" -v off="$off" -v cull="$cull" -v model="$model" '
        BEGIN {
            split(off, o, ","); split(cull, c, ","); split(model, m, ",");
            best = o[19] < c[19] ? o[19] : c[19];
            printf "%-22s %8.2f %8.2f %8.2f %9.2f %9.2f %12d %12d %12d %12d\n", name, o[19], c[19],
                   m[19], m[19] / best, c[19] / o[19], m[16], m[9], m[10] + m[11], m[12];
        }'
done
