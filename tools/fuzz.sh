#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/*_fuzz.cpp) with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer, regenerates their seed corpora (tools/make_fuzz_corpus.py) and
# fuzzes TARGET for SECONDS: tools/fuzz.sh [TARGET|all] [SECONDS] [LIBFUZZER-FLAG...]. Defaults:
# all, 120 s each. Each target grows build-fuzz/corpus/<target> from tests/fuzz/corpus/<target>;
# crashing inputs go to build-fuzz/crashes/<target>/ (copy them to tests/fuzz/crashes/<target>/
# once fixed: ctest replays them). Extra flags go to every fuzzer, e.g. `-fork=1
# -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1` to keep going past a finding.
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:-all}
seconds=${2:-120}
extra=("${@:3}")
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DDAISY_BUILD_FUZZERS=ON -DBUILD_TESTING=OFF -DDAISY_ENABLE_VULKAN=OFF -DDAISY_ENABLE_CUDA=OFF \
    -DDAISY_BUILD_VIEWER=OFF -DCMAKE_CXX_FLAGS="$sanitize -fsanitize=fuzzer-no-link" \
    -DCMAKE_EXE_LINKER_FLAGS="$sanitize" >/dev/null
python3 tools/make_fuzz_corpus.py
targets=()
for source in tests/fuzz/*_fuzz.cpp; do
    name=$(basename "$source" _fuzz.cpp)
    if [[ $target == all || $target == "$name" ]]; then targets+=("$name"); fi
done
cmake --build build-fuzz -j2 --target "${targets[@]/%/_fuzz}"
for name in "${targets[@]}"; do
    mkdir -p "build-fuzz/corpus/$name" "build-fuzz/crashes/$name"
    dict=tests/fuzz/gltf.dict
    [[ $name == obj ]] && dict=tests/fuzz/obj.dict
    [[ $name == options ]] && dict=tests/fuzz/options.dict
    # -max_len: the largest seed (blacklight_box.glb, about 220 KB) fits whole.
    "build-fuzz/tests/fuzz/${name}_fuzz" "build-fuzz/corpus/$name" "tests/fuzz/corpus/$name" \
        -dict="$dict" -max_total_time="$seconds" -max_len=262144 -rss_limit_mb=2048 \
        -timeout=20 -artifact_prefix="build-fuzz/crashes/$name/" -print_final_stats=1 "${extra[@]}"
done
