#!/usr/bin/env bash
# Fails when a tracked C++/CUDA/GLSL source is not formatted by the repository's .clang-format
# (clang-format 14). Fix with: clang-format -i <files>.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.h' '*.cpp' '*.cu' '*.glsl')
((${#files[@]})) || exit 0
if ! clang-format --dry-run -Werror "${files[@]}"; then
    echo "check_format: the files above are not clang-formatted" >&2
    exit 1
fi
echo "check_format: ${#files[@]} files clean"
