#!/usr/bin/env bash
# Installs the Debian 12 packages parity builds and runs with. Idempotent: apt-get is
# only called for packages that are not installed yet. Run as root.
set -euo pipefail
packages=(
  build-essential cmake pkg-config git
  libglm-dev glslang-dev glslang-tools spirv-tools
  libspirv-cross-c-shared-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers
  libegl-dev libegl1-mesa-dev libgl-dev libosmesa6-dev libgl1-mesa-dri
  libopenimageio-dev
  libglfw3-dev libgtest-dev
  xvfb xauth  # xvfb-run: `parity view` runs headless in tests/viewer_test.cpp
  nlohmann-json3-dev libcli11-dev libtinygltf-dev libtinyobjloader-dev
  chromium  # the report test opens DIR/report/index.html headless
  clang libclang-rt-14-dev  # fuzz/ (libFuzzer), docs/RELIABILITY.md
  file  # cpack -G DEB: CPack finds the executables for dpkg-shlibdeps with file(1)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
