#!/usr/bin/env bash
# Runs every libFuzzer target of the sanitizer build for a while (docs/RELIABILITY.md).
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default 10 s, all targets)
# PARITY_FUZZ_SEED=N makes a run repeatable (libFuzzer's -seed; CI sets it); unset: a new seed.
# Needs the build of `PARITY_SANITIZE=1 bash scripts/test.sh` (or PARITY_BUILD_DIR pointing at a
# -DPARITY_FUZZ=ON build). Corpora grow in BUILD/fuzz-corpus/<target> (fuzz/seeds/<target> is only
# read); a crashing input is written to BUILD/fuzz-artifacts/ and the script exits non-zero: copy
# it to tests/fuzz_regressions/<target>/ with a name saying what it does, then fix the parser.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-10}"
shift || true
build="${PARITY_BUILD_DIR:-build-asan}"
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene_gltf scene_obj expectations tolerances script image)
# Always (re)built: incremental, and only the parsers' files (parity_fuzz_inputs).
export CC=clang CXX=clang++ PARITY_BUILD_DIR="$build"
export PARITY_CMAKE_ARGS="-DPARITY_SANITIZE=ON -DPARITY_FUZZ=ON"
ASAN_OPTIONS=detect_leaks=0 bash scripts/build.sh fuzz_all
# Leaks are not findings for a fuzzer (OpenImageIO keeps per-thread caches); memory limits are.
# Sanitizer reports go to files of their own (log_path, one per process): readImage sends file
# descriptor 2 to a temporary file while a decoder runs, which would swallow a report printed there.
asan_options="detect_leaks=0:${ASAN_OPTIONS:-}"
failed=0
mkdir -p "$build/fuzz-artifacts"
for t in "${targets[@]}"; do
  corpus="$build/fuzz-corpus/$t"
  mkdir -p "$corpus"
  log="$build/fuzz-artifacts/$t.log"
  rm -f "$build/fuzz-artifacts/$t-sanitizer".*
  export ASAN_OPTIONS="$asan_options:log_path=$build/fuzz-artifacts/$t-sanitizer"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$build/fuzz-artifacts/$t-sanitizer"
  # One process, one job: the run lengths are comparable between machines of the same speed.
  if "$build/fuzz/fuzz_$t" -seed="${PARITY_FUZZ_SEED:-0}" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=3072 -malloc_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$build/fuzz-artifacts/$t-" "$corpus" "fuzz/seeds/$t" >"$log" 2>&1; then
    echo "fuzz $t: $(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}') runs in ${seconds}s, no finding"
  else
    failed=1
    echo "fuzz $t: FINDING (log: $log)"
    grep -hE 'ERROR|SUMMARY|Test unit written' "$log" "$build/fuzz-artifacts/$t-sanitizer".* 2>/dev/null | head -5
  fi
done
exit $failed
