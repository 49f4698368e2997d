#!/usr/bin/env bash
# Builds the cargo-fuzz targets in fuzz/ (libFuzzer, stable Rust) and runs
# each for a fixed time over its checked-in seed corpus (fuzz/corpus/T),
# which holds every reproducer of issue 22 as a regression case.
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]
#   SW_FUZZ_BUILD_ONLY=1 bash scripts/fuzz.sh   only builds (test.sh builds
#       in the background while the tests run, then runs the targets)
#   SW_FUZZ_JOBS=N   runs N targets at a time (default: one per core)
# Defaults: 45 s, the CI targets below. Prints executions and findings per
# target; exits 1 when any target found a crash, a leak of the limits or a
# timeout (the reproducer is in fuzz/out/artifacts/T/: turn it into a test
# and add it to fuzz/corpus/T).
#
# Why not `cargo fuzz`: it is not installed on a fresh machine, and it
# only passes these flags to cargo. The sanitizer-coverage flags are
# stable codegen options, so no nightly is needed; without a sanitizer a
# finding is a panic, an abort, an out-of-memory (-rss_limit_mb /
# -malloc_limit_mb) or a timeout. With cargo-fuzz installed the same
# targets run as `cd fuzz && cargo fuzz run mesh_readers --sanitizer none`.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
secs="${1:-45}"
shift || true
# CI runs the readers; usd_load and op_script with SW_FUZZ_APPLY=1 apply ops,
# whose budgets are other lanes' work (issue 22): run them in long runs.
targets=("$@")
[ "${#targets[@]}" -gt 0 ] || targets=(mesh_readers usd_layer usd_import op_script trace session_entry session_presence session_snapshot)
triple="$(rustc -vV | sed -n 's/^host: //p')"
export RUSTFLAGS="--cfg fuzzing -Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares -Cdebug-assertions -Coverflow-checks"
target_dir="${SW_FUZZ_TARGET_DIR:-$root/fuzz/target}"
# SW_FUZZ_QUICK_BUILD=1 (CI's short runs): optimise less, for a shorter
# build, in its own target dir; long runs keep the full build.
if [ "${SW_FUZZ_QUICK_BUILD:-}" = 1 ]; then
  export CARGO_PROFILE_RELEASE_OPT_LEVEL=1
  target_dir="${SW_FUZZ_TARGET_DIR:-$root/fuzz/target-quick}"
fi
echo "== fuzz: building ${targets[*]} ($triple)"
(cd "$root/fuzz" && cargo build --release -q --target "$triple" --target-dir "$target_dir" \
  $(printf -- '--bin %s ' "${targets[@]}"))
[ "${SW_FUZZ_BUILD_ONLY:-}" = 1 ] && exit 0
out="$root/fuzz/out"
# One target per core at a time: libFuzzer runs one thread.
jobs="${SW_FUZZ_JOBS:-$(nproc)}"
fuzz_one() {
  local t=$1 work="$out/corpus/$1" art="$out/artifacts/$1" log="$out/$1.log" rc
  mkdir -p "$work" "$art"
  # -timeout: one input may take at most 20 s; -rss_limit_mb and
  # -malloc_limit_mb turn a runaway allocation into a finding instead of
  # an abort of the machine.
  set +e
  "$target_dir/$triple/release/$t" "$work" "$root/fuzz/corpus/$t" \
    -max_total_time="$secs" -timeout=20 -rss_limit_mb=4096 -malloc_limit_mb=4096 \
    -artifact_prefix="$art/" -print_final_stats=1 >"$log" 2>&1
  rc=$?
  set -e
  echo "$rc" >"$out/$t.rc"
}
pending=("${targets[@]}")
while [ "${#pending[@]}" -gt 0 ]; do
  batch=("${pending[@]:0:$jobs}")
  pending=("${pending[@]:$jobs}")
  for t in "${batch[@]}"; do fuzz_one "$t" & done
  wait
done
failed=0
for t in "${targets[@]}"; do
  rc="$(cat "$out/$t.rc")"
  log="$out/$t.log"
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  found="$(find "$out/artifacts/$t" -type f | wc -l)"
  echo "fuzz $t: ${execs:-?} executions in ${secs} s, $found findings (exit $rc)"
  if [ "$rc" -ne 0 ] || [ "$found" -ne 0 ]; then
    failed=1
    tail -n 30 "$log"
  fi
done
exit "$failed"
