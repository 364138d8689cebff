#!/usr/bin/env bash
# The long fuzz run outside CI (README.md here, "The long run"): both targets, the structure-aware one for most of the
# time, in libFuzzer's fork mode so that a finding is kept and the run goes on. Prints executions, coverage and
# findings; the inputs that broke the loader are under build-fuzz/long/findings/ (make each a regression test).
#
#   tests/fuzz/long_run.sh [SECONDS]     # default 3600; one core
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-3600}
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz >/dev/null
work=build-fuzz/long
mkdir -p "$work/corpus" "$work/findings"
rm -rf "$work/seeds" && mkdir -p "$work/seeds"
python3 tests/fuzz/make_seed_corpus.py . "$work/seeds" >/dev/null
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
run() {  # target, seconds, log
  build-fuzz/tests/fuzz/$1 -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -max_total_time="$2" \
    -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 -dict=tests/fuzz/gltf.dict \
    -artifact_prefix="$work/findings/" "$work/corpus" "$work/seeds" tests/fuzz/regressions >"$3" 2>&1 || true
}
structured=$((seconds * 3 / 4))
run fuzz_load_gltf_structured "$structured" "$work/structured.log"
run fuzz_load_gltf $((seconds - structured)) "$work/bytes.log"
for log in structured bytes; do  # libFuzzer's last status line: executions, coverage, corpus, oom/timeout/crash
  echo "$log: $(grep -E "^#[0-9]+" "$work/$log.log" | tail -n 1 || true)"
done
echo "findings: $(ls "$work/findings" | wc -l) in $work/findings"
