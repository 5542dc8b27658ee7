#!/usr/bin/env bash
# Installs the dependencies (scripts/deps.sh), configures and builds into build/: the targets
# given as arguments, or everything.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j"$(nproc)" ${1:+--target "$@"}
