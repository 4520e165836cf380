#!/usr/bin/env bash
# Builds the scene-loader fuzzer with clang, AddressSanitizer and UndefinedBehaviorSanitizer,
# seeds it with the committed scenes and test fixtures, and fuzzes for SECONDS (default 120).
# Crashing inputs are written to build-fuzz/crashes/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-120}
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DDAISY_BUILD_FUZZERS=ON -DBUILD_TESTING=OFF \
    -DCMAKE_CXX_FLAGS="$sanitize -fsanitize=fuzzer-no-link" \
    -DCMAKE_EXE_LINKER_FLAGS="$sanitize" >/dev/null
cmake --build build-fuzz --target scene_loader_fuzz -j2
corpus=build-fuzz/corpus
mkdir -p "$corpus" build-fuzz/crashes
# Seeds: the first byte picks the format (0 .gltf, 1 .glb, 2 .obj), the rest is the file.
i=0
while IFS= read -r -d '' f; do
    case "$f" in
    *.gltf) tag='\x00' ;; *.glb) tag='\x01' ;; *.obj) tag='\x02' ;; *) continue ;;
    esac
    { printf "$tag"; cat "$f"; } >"$corpus/seed_$i"
    i=$((i + 1))
done < <(find assets tests/data -type f -print0 2>/dev/null)
build-fuzz/scene_loader_fuzz "$corpus" -max_total_time="$seconds" -max_len=65536 \
    -artifact_prefix=build-fuzz/crashes/ -print_final_stats=1
