#!/usr/bin/env bash
# Runs every libFuzzer target for SECONDS each (two at a time), from the seed corpora fuzz_seeds
# writes plus whatever corpus earlier runs left in BUILD/fuzz-corpus. Prints each target's
# executions; exits non-zero if any target found a crash, a sanitizer report, a leak, a timeout
# (10 s per input) or an input needing more than 2 GB (the reproducer is left in BUILD/fuzz-findings).
# usage: tests/fuzz/run.sh BUILD_DIR [SECONDS]        (long runs: SECONDS=3600, or run a target by hand:
#        BUILD/tests/fuzz/fuzz_ply BUILD/fuzz-corpus/ply -max_total_time=3600)
set -uo pipefail
build="$1" seconds="${2:-60}"
bin="$build/tests/fuzz"
corpus="$build/fuzz-corpus"
findings="$build/fuzz-findings"
mkdir -p "$corpus" "$findings"
"$bin/fuzz_seeds" "$build/fuzz-seeds" > /dev/null || exit 1

run() {  # run TARGET CORPUS_NAME
  local target="$1" name="$2" log="$build/fuzz-$2.log"
  mkdir -p "$corpus/$name"
  "$bin/$target" "$corpus/$name" "$build/fuzz-seeds/$name" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$findings/$name-" > "$log" 2>&1
  local rc=$?
  local execs
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  if [ "$rc" -eq 0 ]; then
    echo "fuzz: $name: ${execs:-?} executions in ${seconds} s, corpus $(ls "$corpus/$name" | wc -l) inputs, nothing found"
  else
    echo "fuzz: $name: FOUND A PROBLEM after ${execs:-?} executions (exit $rc); log $log, reproducer in $findings:"
    grep -E "ERROR|SUMMARY|Test unit written" "$log" | head -n 10
  fi
  return "$rc"
}

status=0
pairs=("fuzz_model_memory model_memory" "fuzz_model_payload model_payload" "fuzz_ply ply" "fuzz_obj obj" "fuzz_lnd lnd" "fuzz_pgm pgm"
       "fuzz_report report" "fuzz_tables tables" "fuzz_params params")
for ((i = 0; i < ${#pairs[@]}; i += 2)); do
  run ${pairs[i]} & a=$!
  b=""
  if [ $((i + 1)) -lt ${#pairs[@]} ]; then run ${pairs[i + 1]} & b=$!; fi
  wait "$a" || status=1
  if [ -n "$b" ]; then wait "$b" || status=1; fi
done
exit "$status"
