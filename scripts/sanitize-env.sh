# Sourced (`. scripts/sanitize-env.sh`) before running what build-asan/ or build-tsan/ holds: any ASan or UBSan
# finding ends the program with a stack trace, and leak reports from inside Mesa, EGL and OSMesa
# are suppressed (tests/sanitize/lsan.supp says which and why; none of hlodr's own).
_hlodr_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# Stack traces name functions only through llvm-symbolizer. clang's own copy is there whenever
# clang is, though Debian links it into PATH only with the llvm package; the TSan suppressions
# need the names.
_hlodr_symbolizer=$(command -v llvm-symbolizer || ls /usr/lib/llvm-*/bin/llvm-symbolizer 2>/dev/null | tail -n 1 || true)
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$_hlodr_root/tests/sanitize/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
# ThreadSanitizer (build-tsan/): a race fails the test; races inside Mesa's own threads, which
# hlodr does not build, are suppressed (tests/sanitize/tsan.supp says which).
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$_hlodr_root/tests/sanitize/tsan.supp${TSAN_OPTIONS:+:$TSAN_OPTIONS}"
if [ -n "$_hlodr_symbolizer" ]; then
  ASAN_OPTIONS="$ASAN_OPTIONS:external_symbolizer_path=$_hlodr_symbolizer"
  TSAN_OPTIONS="$TSAN_OPTIONS:external_symbolizer_path=$_hlodr_symbolizer"
fi
unset _hlodr_root _hlodr_symbolizer
