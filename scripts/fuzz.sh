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
targets="${FUZZ_TARGETS:-closure query mtlx alta ra_table study openmaterial luminaire}"
jobs="${FUZZ_JOBS:-$(nproc)}"

bash "$root/scripts/setup-debian.sh"
if ! command -v clang++ >/dev/null 2>&1; then
  echo "fuzz: clang++ is missing (scripts/setup-debian.sh installs clang and libclang-rt-14-dev)" >&2
  exit 1
fi
cmake -S "$root/fuzz" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
ninja -C "$build"

# Sanitizer reports are fatal and symbolised; leaks are reported (and fail the run).
# FUZZ_JOBS targets run at a time (default: the number of cores), each in one process.
export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:symbolize=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1:symbolize=1}"
if command -v llvm-symbolizer >/dev/null 2>&1; then
  export ASAN_SYMBOLIZER_PATH="$(command -v llvm-symbolizer)"
fi

# One run of target $1 for $2 seconds, its log in $3 (appended); returns libFuzzer's exit code.
fuzz_run() {
  local t="$1" secs="$2" log="$3"
  "$build/fuzz_$t" -max_total_time="$secs" -print_final_stats=1 -timeout=25 -rss_limit_mb=2048 \
    -artifact_prefix="$build/artifacts/$t/" "$build/corpus/$t" "$root/fuzz/corpus/$t" >>"$log" 2>&1
}

# Fuzzes target $1 for $seconds s; its summary line goes to $build/fuzz_$1.result.
fuzz_target() {
  local t="$1" corpus="$build/corpus/$1" artifacts="$build/artifacts/$1" log="$build/fuzz_$1.log"
  local start stalls rc input replay_start replay_rc replay_s execs cov line
  mkdir -p "$corpus" "$artifacts"
  : >"$log"
  echo "fuzz: $t for ${seconds} s"
  # libFuzzer's per-input timeout reads the wall clock (system_clock), which a virtual machine's
  # time synchronisation can step forward in the middle of an input. So a timeout is checked:
  # the input is run again in a fresh process (an empty series cache, so at least the same
  # work) under the same 25 s limit. A timeout that reproduces fails the run; one that does not
  # is reported with the replay's time, and fuzzing resumes for the rest of the target's time.
  # Twice at most: a third timeout fails whatever its replay does.
  start=$(date +%s)
  stalls=0
  while :; do
    set +e
    fuzz_run "$t" "$((seconds - ($(date +%s) - start)))" "$log"
    rc=$?
    set -e
    input=$(ls -t "$artifacts"/timeout-* 2>/dev/null | head -n 1 || true)
    if [ "$rc" -eq 0 ] || [ -z "$input" ] || ! tail -n 40 "$log" | grep -q 'libFuzzer: timeout' ||
      [ "$stalls" -ge 2 ]; then
      break
    fi
    replay_start=$(date +%s.%N)
    set +e
    "$build/fuzz_$t" -timeout=25 -rss_limit_mb=2048 "$input" >"$log.replay" 2>&1
    replay_rc=$?
    set -e
    replay_s=$(awk -v a="$replay_start" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f", b - a}')
    if [ "$replay_rc" -ne 0 ]; then
      echo "fuzz: $t: the timeout reproduces: $input (replay log $log.replay)" >&2
      break
    fi
    stalls=$((stalls + 1))
    echo "fuzz: $t: a timeout that did not reproduce: $input ran in ${replay_s} s in a fresh" \
      "process (a stall or a step of the wall clock); resuming" | tee -a "$log" >&2
    rm -f "$input"
    if [ $(($(date +%s) - start)) -ge "$seconds" ]; then
      rc=0
      break
    fi
  done
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | awk '{n += $1} END {print n}')
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 || true)
  if [ "$rc" -eq 0 ]; then
    line=$(printf '%-8s %12s executions in %s s, %s, corpus %s files: ok' "$t" "${execs:-?}" \
      "$seconds" "${cov:-cov: ?}" "$(ls "$corpus" | wc -l)")
    if [ "$stalls" -gt 0 ]; then line+=" ($stalls timeout(s) not reproduced, see the log)"; fi
  else
    line=$(printf '%-8s %12s executions: FAILED (exit %s), input in %s, log %s' "$t" \
      "${execs:-?}" "$rc" "$artifacts" "$log")
    grep -E 'VIOLATION|UNEXPECTED|ERROR: |runtime error|SUMMARY' "$log" | head -n 20 >&2 || true
  fi
  echo "$line"
  echo "$line" >"$build/fuzz_$t.result"
}

running=0
for t in $targets; do
  rm -f "$build/fuzz_$t.result"
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  fuzz_target "$t" &
  running=$((running + 1))
done
wait || true

status=0
echo
echo "fuzz summary (${seconds} s per target, $jobs at a time):"
for t in $targets; do
  if [ -f "$build/fuzz_$t.result" ]; then
    line=$(cat "$build/fuzz_$t.result")
  else
    line="$t: FAILED (no result: the run was interrupted)"
  fi
  case "$line" in *": ok"*) ;; *) status=1 ;; esac
  echo "$line"
done
exit "$status"
