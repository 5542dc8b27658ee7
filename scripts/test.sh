#!/usr/bin/env bash
# Builds, then runs the whole test suite with CTest. Both backends are required here (the
# set-up installs Mesa's llvmpipe and lavapipe): a backend that cannot be created fails the
# tests instead of skipping them. Override with PARITY_REQUIRE_BACKENDS=gl (say) elsewhere.
# Every GPU test runs with the Khronos Vulkan validation layer and a GL debug context (KHR_debug)
# and fails on any message (tests/test_support.cpp).
#
# PARITY_SANITIZE=1: the same suite built with AddressSanitizer + UndefinedBehaviorSanitizer into
# build-asan/ (docs/RELIABILITY.md); a finding fails its test. Extra ctest arguments are passed
# on, e.g. `PARITY_SANITIZE=1 bash scripts/test.sh -R 'Reliability|Scene'`.
set -euo pipefail
cd "$(dirname "$0")/.."
export PARITY_REQUIRE_BACKENDS="${PARITY_REQUIRE_BACKENDS-gl,vk}"
if [ "${PARITY_SANITIZE:-0}" = 1 ]; then
  # clang: the same instrumented build also holds the libFuzzer targets (fuzz/, scripts/fuzz.sh).
  export CC=clang CXX=clang++ PARITY_BUILD_DIR="${PARITY_BUILD_DIR:-build-asan}"
  export PARITY_CMAKE_ARGS="-DPARITY_SANITIZE=ON -DPARITY_FUZZ=ON"
  # Test discovery runs the test binaries during the build; leaks of a listing run are not findings.
  ASAN_OPTIONS=detect_leaks=0 bash scripts/build.sh parity parity_tests parity_rhi_tests fuzz_all
  supp="$PWD/scripts/sanitizers"
  # Mesa's drivers and the loaders are not instrumented: their leaks and their
  # out-of-process-looking allocations are suppressed by library (evidence in the files).
  export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
  # abort_on_error: a finding ends the process with SIGABRT, as a crash does without the
  # sanitizer, so `parity run` still classifies a dying case as Crash (tests/harness_run_test.cpp
  # injects SIGSEGV and memory exhaustion); allocator_may_return_null: a failed allocation throws
  # std::bad_alloc, as it does without the sanitizer, instead of ASan's own out-of-memory report.
  # intercept_tls_get_addr=0: clang 14's runtime takes a dynamic TLS block that starts 16 bytes
  # into a page (ASan's own chunk header puts many there) for a glibc <= 2.18 block with a header,
  # reads its bounds from the two words before it, and LeakSanitizer's tracer dies scanning that
  # range at exit ("Tracer caught signal 11 ... LeakSanitizer has encountered a fatal error"): a
  # runtime bug, not a finding (evidence in docs/RELIABILITY.md; scripts/sanitizers/dtls-tracer-repro.sh shows it).
  # With it off, a pointer held only in a thread's dynamic TLS is still not reported as a leak.
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:allocator_may_return_null=1:detect_odr_violation=0:intercept_tls_get_addr=0:${ASAN_OPTIONS:-}"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp"
  ctest --test-dir "$PARITY_BUILD_DIR" --output-on-failure -j"$(nproc)" --timeout 900 -LE '^case$' "$@"
else
  bash scripts/build.sh
  # -LE case: the matrix's cases run once, in the test parity.matrix, not each in a test of its own
  # (tests/parity_cases.cmake; `ctest -L case` runs them one by one).
  ctest --test-dir build --output-on-failure -j"$(nproc)" -LE '^case$' "$@"
fi
