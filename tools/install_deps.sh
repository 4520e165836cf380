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

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"

# Mesa's lavapipe from 25.0 on has VK_KHR_ray_query and runs the view-factor shaders about 3x
# faster than Debian 12's 22.3. On Debian 12 it comes from Debian's own bookworm-backports suite:
# the suite is added with backports' default low priority and only the Mesa Vulkan drivers are
# installed from it (`-t bookworm-backports`), so nothing else is upgraded. Later Debian releases
# have a new enough Mesa in their main archive.
. /etc/os-release
if [ "${VERSION_CODENAME:-}" = bookworm ]; then
    mesa_version=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
    if [ -z "$mesa_version" ] || dpkg --compare-versions "$mesa_version" lt 25; then
        backports=/etc/apt/sources.list.d/daisy-bookworm-backports.sources
        if [ ! -f "$backports" ]; then
            printf '%s\n' "Types: deb" "URIs: http://deb.debian.org/debian" \
                "Suites: bookworm-backports" "Components: main" \
                "Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg" | $sudo tee "$backports" >/dev/null
        fi
        echo "install_deps: installing mesa-vulkan-drivers from bookworm-backports"
        $sudo apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
            -t bookworm-backports mesa-vulkan-drivers
    fi
fi

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
    echo "install_deps: installing ${missing[*]}"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
