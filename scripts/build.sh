#!/usr/bin/env bash
# Installs the dependencies (scripts/deps.sh), configures and builds into build/: the targets
# given as arguments, or everything. PARITY_BUILD_DIR and PARITY_CMAKE_ARGS select another
# folder and configuration (scripts/test.sh uses them for the sanitizer build).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
build="${PARITY_BUILD_DIR:-build}"
# shellcheck disable=SC2086  # PARITY_CMAKE_ARGS is a list of -D options
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo ${PARITY_CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j"$(nproc)" ${1:+--target "$@"}
