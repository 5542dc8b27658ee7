#!/usr/bin/env bash
# The main job: build, then render the default scene with every technique on every available
# backend (each in its own process), diff the backends, and write images, heat maps and
# summary.json to out/main (or the folder given as $1).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh parity
build/parity list
build/parity run --out "${1:-out/main}"
