#!/usr/bin/env bash
# The main job: build, then `parity run` the default matrix (every technique, platform and
# available backend on the scenes with goldens, each case in its own process) against golden/ and across backends, and
# write results.json, junit.xml and report/index.html to out/main (or the folder given as $1).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh parity
build/parity list
build/parity run --out "${1:-out/main}"
