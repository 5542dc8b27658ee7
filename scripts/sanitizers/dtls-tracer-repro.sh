#!/usr/bin/env bash
# Shows why scripts/test.sh sets ASAN_OPTIONS=intercept_tls_get_addr=0 (docs/RELIABILITY.md), and
# says whether the installed clang still needs it. A thread of a dlopen'ed library keeps a heap
# pointer in dynamic TLS, then the process exits with the leak check on:
#   default options:            LeakSanitizer's tracer crashes (clang 14 on glibc 2.36)
#   intercept_tls_get_addr=0:   no crash and no leak report (the pointer is still found)
#   the same without keeping it: a leak is reported (the check is alive)
set -euo pipefail
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
cat >"$dir/lib.c" <<'C'
#include <stdlib.h>
static __thread char big[100000];  /* too big for static TLS: the block comes from malloc */
__thread void* kept;
void hold(int keep) { big[0] = 1; void* p = malloc(4321); if (keep) kept = p; }
C
cat >"$dir/main.c" <<'C'
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
static void (*hold)(int);
static volatile int ready;
static void* worker(void* arg) { hold(getenv("KEEP") != NULL); ready = 1; for (;;) pause(); return arg; }
int main(int argc, char** argv) {
  (void)argc;
  void* lib = dlopen(argv[1], RTLD_NOW);
  if (!lib) return puts(dlerror()), 1;
  hold = (void (*)(int))dlsym(lib, "hold");
  pthread_t t;
  pthread_create(&t, NULL, worker, NULL);
  while (!ready) usleep(1000);
  return 0;
}
C
clang -shared -fPIC -O1 "$dir/lib.c" -o "$dir/lib.so"
clang -fsanitize=address -O1 "$dir/main.c" -o "$dir/main" -ldl -lpthread
verdict() {
  local out
  out="$("$@" 2>&1 || true)"
  if grep -q "LeakSanitizer has encountered a fatal error" <<<"$out"; then echo "tracer crashed"
  elif grep -q "byte(s) leaked" <<<"$out"; then echo "leak reported"
  else echo "clean"; fi
}
echo "kept in dynamic TLS, default options:          $(KEEP=1 ASAN_OPTIONS=detect_leaks=1 verdict "$dir/main" "$dir/lib.so")"
echo "kept in dynamic TLS, intercept_tls_get_addr=0: $(KEEP=1 ASAN_OPTIONS=detect_leaks=1:intercept_tls_get_addr=0 verdict "$dir/main" "$dir/lib.so")"
echo "not kept,            intercept_tls_get_addr=0: $(ASAN_OPTIONS=detect_leaks=1:intercept_tls_get_addr=0 verdict "$dir/main" "$dir/lib.so")"
