#!/usr/bin/env bash
# Installs every Debian package DaisyRiot builds, tests and runs with. Idempotent and
# non-interactive: packages already present are left alone, and `apt-get update` runs only when
# something is missing. Nothing is vendored and nothing is downloaded at build time.
# Not from here: the CUDA toolkit (nvcc 13, NVIDIA's packages; CI has it in /usr/local/cuda). The
# cuda backend builds when CMake finds nvcc and is left out otherwise (docs/gpu.md).
set -euo pipefail

packages=(
    # toolchain
    build-essential cmake ninja-build pkg-config clang-format python3
    # core libraries
    libcli11-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libtinyobjloader-dev
    libembree-dev libtbb-dev libopenexr-dev libmeshoptimizer-dev
    libdraco-dev
    # Vulkan compute and the viewer
    libvulkan-dev libvulkan-volk-dev glslang-tools spirv-tools mesa-vulkan-drivers vulkan-tools
    libglfw3-dev libglm-dev libimgui-dev xvfb xauth
    # the validation layer for DAISY_VULKAN_VALIDATION=1 runs (docs/viewer.md)
    vulkan-validationlayers
    # tests and benchmarks
    libgtest-dev libgmock-dev libbenchmark-dev
    # docs plots
    python3-matplotlib python3-numpy
)

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    echo "install_deps: installing ${missing[*]}"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
