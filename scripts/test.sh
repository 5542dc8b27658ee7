#!/usr/bin/env bash
# Builds, then runs the whole test suite with CTest. Both backends are required here (the
# set-up installs Mesa's llvmpipe and lavapipe): a backend that cannot be created fails the
# tests instead of skipping them. Override with PARITY_REQUIRE_BACKENDS=gl (say) elsewhere.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
export PARITY_REQUIRE_BACKENDS="${PARITY_REQUIRE_BACKENDS-gl,vk}"
ctest --test-dir build --output-on-failure -j"$(nproc)"
