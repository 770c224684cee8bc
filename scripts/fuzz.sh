#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang into build-fuzz/ and runs each for a bounded
# time: FUZZ_SECONDS (default 60) per target. A longer run is the same command with a larger
# value, e.g. FUZZ_SECONDS=3600 bash scripts/fuzz.sh; FUZZ_TARGETS="closure query" runs some.
# Each run starts from the checked-in seeds (fuzz/corpus/<target>/) and keeps what it finds in
# build-fuzz/corpus/<target>/ (reused by the next run; the checked-in seeds are not touched).
# Prints the executions per target; fails on any crash, sanitizer report or violated property,
# leaving the input that triggered it in build-fuzz/artifacts/<target>/ (replay it with
# build-fuzz/fuzz_<target> FILE; add it to fuzz/corpus/<target>/ as a regression input).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${FUZZ_BUILD_DIR:-$root/build-fuzz}"
seconds="${FUZZ_SECONDS:-60}"
targets="${FUZZ_TARGETS:-closure query mtlx alta ra_table study}"

bash "$root/scripts/setup-debian.sh"
if ! command -v clang++ >/dev/null 2>&1; then
  echo "fuzz: clang++ is missing (scripts/setup-debian.sh installs clang and libclang-rt-14-dev)" >&2
  exit 1
fi
cmake -S "$root/fuzz" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
ninja -C "$build"

# Sanitizer reports are fatal and symbolised; leaks are reported (and fail the run).
export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:symbolize=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1:symbolize=1}"
if command -v llvm-symbolizer >/dev/null 2>&1; then
  export ASAN_SYMBOLIZER_PATH="$(command -v llvm-symbolizer)"
fi

status=0
summary=""
for t in $targets; do
  corpus="$build/corpus/$t"
  artifacts="$build/artifacts/$t"
  log="$build/fuzz_$t.log"
  mkdir -p "$corpus" "$artifacts"
  echo "fuzz: $t for ${seconds} s"
  set +e
  "$build/fuzz_$t" -max_total_time="$seconds" -print_final_stats=1 -timeout=25 -rss_limit_mb=2048 \
    -artifact_prefix="$artifacts/" "$corpus" "$root/fuzz/corpus/$t" >"$log" 2>&1
  rc=$?
  set -e
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 || true)
  if [ "$rc" -eq 0 ]; then
    line=$(printf '%-8s %12s executions in %s s, %s, corpus %s files: ok' "$t" "${execs:-?}" \
      "$seconds" "${cov:-cov: ?}" "$(ls "$corpus" | wc -l)")
  else
    status=1
    line=$(printf '%-8s %12s executions: FAILED (exit %s), input in %s, log %s' "$t" \
      "${execs:-?}" "$rc" "$artifacts" "$log")
    grep -E 'VIOLATION|UNEXPECTED|ERROR: |runtime error|SUMMARY' "$log" | head -n 20 >&2 || true
  fi
  echo "$line"
  summary+="$line"$'\n'
done
echo
echo "fuzz summary (${seconds} s per target):"
printf '%s' "$summary"
exit "$status"
