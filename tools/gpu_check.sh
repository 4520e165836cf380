#!/usr/bin/env bash
# The check of the cuda backend on an NVIDIA machine (docs/gpu.md), after building:
#
#   bash tools/gpu_check.sh [BUILD_DIR] [REPORT_FILE]      (defaults: build, gpu_check_report.txt)
#
# Prints the device; runs the cuda tests and then the vulkan and backend tests with
# DAISY_REQUIRE_CUDA=1 DAISY_REQUIRE_VULKAN=1 (a skip is a failure); validates cuda against the
# reference backend on the demo scenes; times the 7,712-patch black-light box matrix on cuda,
# vulkan (on the NVIDIA Vulkan driver when there is one: its ray queries, and the BVH walk) and
# cpu; validates the vulkan backend's ray queries against the reference and cuda backends;
# writes all of it, and a summary,
# to one report file. Each step runs under a time limit and no step starts after 400 s, so the
# whole check ends within 8 minutes. Exit status: 0 every step passed, 1 some step failed or
# timed out, 2 no build or no usable CUDA device (the report says which).
set -uo pipefail
cd "$(dirname "$0")/.." || exit 2
build=${1:-build}
report=${2:-gpu_check_report.txt}
daisy="$build/daisy"
tests="$build/tests/daisy_tests"
budget=400
start=$(date +%s)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export XDG_CACHE_HOME="$work/cache"  # nothing read from an earlier run's cache of F
summary=()
failed=0

: >"$report"
log() { printf '%s\n' "$*" | tee -a "$report"; }

# step NAME LIMIT COMMAND...: runs COMMAND under `timeout` (LIMIT seconds, less when the budget
# is nearly spent), its output to the terminal and the report, and records the outcome.
step() {
    local name=$1 limit=$2
    shift 2
    local left=$((budget - ($(date +%s) - start)))
    if ((left <= 0)); then
        log "" "== $name: NOT RUN (the ${budget} s budget is spent)"
        summary+=("NOT RUN  $name")
        failed=1
        return
    fi
    ((limit > left + 50)) && limit=$((left + 50))
    log "" "== $name (limit ${limit} s)" "\$ $*"
    local t0 t1 rc status
    t0=$(date +%s.%N)
    timeout --kill-after=5 "$limit" "$@" 2>&1 | tee -a "$report"
    rc=${PIPESTATUS[0]}
    t1=$(date +%s.%N)
    case $rc in
        0) status="PASS   " ;;
        124 | 137) status="TIMEOUT" ;;
        *) status="FAIL($rc)" ;;
    esac
    ((rc == 0)) || failed=1
    summary+=("$status  $name  ($(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') s)")
}

# The build time F took on a backend, from formfactors' stage line "view factors: N non-zeros in
# T on BACKEND" (what step output holds in the report).
timeF() {
    local backend=$1
    shift
    step "time the 7,712-patch matrix on $backend${*:+ $*}" 240 \
        "$daisy" formfactors assets/scenes/blacklight_box.gltf --backend "$backend" --no-cache \
        -o "$work/F_$backend.mtx" "$@"
    rm -f "$work/F_$backend.mtx"
}

log "gpu_check: $(date -u '+%Y-%m-%d %H:%M:%S UTC') on $(hostname)"
log "source: $(git rev-parse --short HEAD 2>/dev/null || echo 'not a git checkout')"
if [[ ! -x $daisy || ! -x $tests ]]; then
    log "gpu_check: no $daisy or $tests: build first (docs/gpu.md)"
    exit 2
fi
log "$("$daisy" --version)"
if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=index,name,driver_version,memory.total,compute_cap \
        --format=csv 2>&1 | tee -a "$report"
else
    log "nvidia-smi: not found"
fi

# The device as the backend sees it (--verbose: SMs, memory, the kernel's registers and stack).
if ! "$daisy" formfactors assets/scenes/cornell_box.gltf --backend cuda --no-cache --verbose \
    -o "$work/probe.mtx" >"$work/probe.txt" 2>&1; then
    tee -a "$report" <"$work/probe.txt"
    log "gpu_check: no usable CUDA device; nothing else was run"
    exit 2
fi
grep '^cuda:' "$work/probe.txt" | tee -a "$report"

# Without a GPU's Vulkan driver the vulkan steps run on lavapipe, as in CI (slower, still checked).
vulkanDevice=()
if "$daisy" formfactors assets/scenes/cornell_box.gltf --backend vulkan --device nvidia \
    --no-cache --quiet -o "$work/probe.mtx" >/dev/null 2>&1; then
    vulkanDevice=(--device nvidia)
    log "vulkan: the NVIDIA Vulkan driver is installed: vulkan is timed on the GPU"
else
    log "vulkan: no NVIDIA Vulkan driver: vulkan runs on whatever Vulkan device there is"
fi

export DAISY_REQUIRE_CUDA=1 DAISY_REQUIRE_VULKAN=1
step "cuda tests" 120 "$tests" \
    --gtest_filter='*Cuda*:*cuda*'
for scene in cornell_box colored_lights furnace_box parallel_plates perpendicular_plates; do
    step "validate cuda against reference: $scene" 60 \
        "$daisy" validate "assets/scenes/$scene.gltf" --backend cuda --against reference
done
step "validate cuda against reference: cornell_box, 3,800 patches" 90 \
    "$daisy" validate assets/scenes/cornell_box.gltf --subdivide 0.0492 --backend cuda \
    --against reference
timeF cuda --verbose
timeF cpu
timeF vulkan "${vulkanDevice[@]}" --vulkan-rays software --verbose
# The ray-query variant (docs/backends.md, "Ray queries"): `auto` picks it on a GPU, the NVIDIA
# Vulkan driver's hardware ray tracing; on lavapipe it is forced here to be checked all the same.
for scene in cornell_box colored_lights furnace_box; do
    step "validate vulkan ray queries against reference: $scene" 90 \
        "$daisy" validate "assets/scenes/$scene.gltf" --backend vulkan "${vulkanDevice[@]}" \
        --vulkan-rays query --against reference
done
step "validate vulkan ray queries against cuda: cornell_box, 3,800 patches" 150 \
    "$daisy" validate assets/scenes/cornell_box.gltf --subdivide 0.0492 --backend vulkan \
    --vulkan-rays query --against cuda
timeF vulkan "${vulkanDevice[@]}" --vulkan-rays query --verbose
step "validate cuda against reference: blacklight_box, 7,712 patches" 150 \
    "$daisy" validate assets/scenes/blacklight_box.gltf --backend cuda --against reference
step "vulkan and backend tests" 150 "$tests" \
    --gtest_filter='*Vulkan*:*vulkan*:Backend.*:Backends/*:ValidateCli.*:-*cuda*:*Cuda*'

log "" "== summary ($(($(date +%s) - start)) s)"
for line in "${summary[@]}"; do
    log "$line"
done
log "" "The build times of F are the 'view factors: ... non-zeros in T on BACKEND' lines above."
log "gpu_check: report written to $report"
exit "$failed"
