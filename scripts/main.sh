#!/usr/bin/env bash
# The main job: build, then `parity run` the default matrix (every technique, platform and
# available backend on the scenes with goldens, several cases to a child process, a case that
# crashes or hangs its child run again alone) against golden/ and across backends, and
# write results.json, junit.xml and report/index.html to out/main (or the folder given as $1; further
# arguments go to `parity run`, e.g. `bash scripts/main.sh out/main --strict`).
# Both backends are required (the set-up installs Mesa's llvmpipe and lavapipe): a backend that
# cannot be created fails the run with one line naming it. PARITY_REQUIRE_BACKENDS=gl (say)
# elsewhere.
set -euo pipefail
cd "$(dirname "$0")/.."
export PARITY_REQUIRE_BACKENDS="${PARITY_REQUIRE_BACKENDS-gl,vk}"
bash scripts/build.sh parity
build/parity list
build/parity run --out "${1:-out/main}" "${@:2}"
