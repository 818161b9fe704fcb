#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer: builds build-asan (-DSPAM_SANITIZE=ON) and runs
# the fast tests and the fuzz corpus there. Any sanitizer report from the project's code fails
# the run: reports are fatal (halt_on_error, no UB recovery) and change the exit code to 86,
# which no test expects; the fuzz test also scans stderr. Leaks inside OpenMPI's initialisation
# are suppressed by tests/lsan.supp (by library), leak checking stays on for everything else.
# Run after the normal build and tests (README's test command). With --build-only it
# configures and builds build-asan and stops (.ci/run builds it that way, under the idle
# scheduling policy, while the normal build's tests run). SPAM_ASAN_PREBUILD (set by .ci/run)
# names the directory of that background build (its process group, exit status and log):
# this run waits for it (alone on the machine, the idle policy takes every core) and fails if
# it failed.
set -euo pipefail
build_only=0
for flag in "$@"; do
  case "$flag" in
    --build-only) build_only=1 ;;
    *) echo "tools/sanitize.sh: unknown flag $flag (accepted: --build-only)" >&2; exit 2 ;;
  esac
done
cd "$(dirname "$0")/.."
root=$PWD
if [[ -n "${SPAM_ASAN_PREBUILD:-}" && $build_only == 0 ]]; then
  waited=$SECONDS
  while [[ ! -s "$SPAM_ASAN_PREBUILD/status" ]]; do sleep 2; done
  # What CI's time is made of: how long the tests waited for the background build.
  echo "tools/sanitize.sh: waited $((SECONDS - waited)) s for the background sanitizer build"
  tail -n 3 "$SPAM_ASAN_PREBUILD/log"
  if [[ $(cat "$SPAM_ASAN_PREBUILD/status") != 0 ]]; then
    cat "$SPAM_ASAN_PREBUILD/log"
    echo "tools/sanitize.sh: the background sanitizer build failed" >&2
    exit 1
  fi
fi
# fast_unwind_on_malloc=1: each allocation's stack by the frame pointers, which stop at the
# first frame of a library built without them (OpenMPI, HDF5, PETSc). The full unwinder at
# every allocation was most of the sanitized tests' CPU time (run_bad_input_solid: user 14.7 s
# with it, 6.6 s without; loaded machine). The tests whose leaks the suppressions must find
# below such a frame (OpenMPI's under mpiexec, HDF5's free lists) take the full stacks
# (tests/CMakeLists.txt, spam_full_alloc_stacks). allow_user_segv_handler=0 keeps ASan's
# SIGSEGV report instead of PETSc's handler.
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:exitcode=86:abort_on_error=0:handle_abort=1:allow_user_segv_handler=0:fast_unwind_on_malloc=1:malloc_context_size=30"
export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:print_suppressions=0:exitcode=86"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:report_error_type=1:exitcode=86"
# OpenMPI singleton start without its PMIx server (also set by ctest for every test).
export OMPI_MCA_ess_singleton_isolated=1
# The fuzz corpus under ASan: every curated case, every forged snapshot, every 4th forged
# checkpoint, and every 48th of the generated option values and file mutations
# (tests/run_fuzz.py, SPAM_FUZZ_STRIDE). The
# generated cases repeat the same few code paths with other values; the normal build runs
# them all, or, where .ci/run sets SPAM_FUZZ_SANITIZED_STRIDE, all but the cases this run
# takes, and this run then takes that stride (the two runs together are the whole corpus,
# each case once). The corpus's cases run without LeakSanitizer's exit scan (run_fuzz.py
# says why); every other test keeps it.
export SPAM_FUZZ_STRIDE="${SPAM_FUZZ_SANITIZED_STRIDE:-${SPAM_FUZZ_STRIDE:-48}}"
cmake -S . -B build-asan -DSPAM_SANITIZE=ON -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build-asan -j2
((build_only)) && exit 0
ctest --test-dir build-asan -L 'fast|fuzz' -j2 --output-on-failure
