#!/usr/bin/env bash
# Long fuzzing runs with libFuzzer (coverage-guided, AddressSanitizer + UBSan), docs/fuzzing.md.
#
#   tools/fuzz.sh build                    clang build of the fuzz executables in build-fuzz/
#   tools/fuzz.sh run TARGET|all [RUNS]    RUNS executions per target (default 1000000), one
#                                          target at a time on JOBS workers (default: cores)
#   tools/fuzz.sh list                     the targets
#
# Outputs under out/fuzz/: corpus/<target>/ (grows run to run), crashes/<target>-* (inputs that
# crashed, hung or made a sanitizer report), logs/<target>.log, summary.tsv (target, runs,
# seconds, executions/s, coverage edges, features, corpus size, crashes).
# Environment: JOBS, MAX_LEN (bytes, default 8192), TIMEOUT (s an input, default 20),
# RSS_LIMIT_MB (memory in use, default 4096), MALLOC_LIMIT_MB (one request, default 1 TiB:
# a request the machine cannot satisfy gets a null pointer, as without the sanitizer, and VTK
# reports it; memory actually used stays under RSS_LIMIT_MB).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD="$ROOT/build-fuzz"
OUT="$ROOT/out/fuzz"
JOBS=${JOBS:-$(nproc)}
log() { printf '[fuzz] %s\n' "$*" >&2; }

build() {
  "$ROOT/tools/bootstrap.sh" deps
  for p in clang libclang-rt-14-dev; do
    if [ "$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null)" != "installed" ]; then
      apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev
      break
    fi
  done
  local generator=()
  command -v ninja >/dev/null && generator=(-G Ninja)
  if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    CC=clang CXX=clang++ cmake -S "$ROOT" -B "$BUILD" "${generator[@]}" -DBARYLAB_FUZZ=ON \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" \
      -DBARYLAB_BUILD_BENCHMARKS=OFF
  fi
  # the driver first: it lists the targets
  cmake --build "$BUILD" -j "$JOBS" --target barylab_fuzz
  local targets=()
  for t in $(targets); do targets+=("barylab_libfuzz_$t"); done
  cmake --build "$BUILD" -j "$JOBS" --target "${targets[@]}"
}

targets() {
  "$BUILD/bin/barylab_fuzz" list | awk '{print $1}'
}

run_one() { # target runs
  local t=$1 runs=$2
  local exe="$BUILD/bin/barylab_libfuzz_$t"
  [ -x "$exe" ] || { log "no $exe: run tools/fuzz.sh build"; exit 2; }
  mkdir -p "$OUT/corpus/$t" "$OUT/crashes" "$OUT/logs" "$OUT/seeds"
  "$BUILD/bin/barylab_fuzz" seeds "$OUT/seeds" "$t" >/dev/null
  local per=$(( (runs + JOBS - 1) / JOBS ))
  local before
  before=$(find "$OUT/crashes" -name "$t-*" | wc -l)
  local start=$(date +%s)
  local args=(-runs="$per" -max_len="${MAX_LEN:-8192}" -timeout="${TIMEOUT:-20}"
    -rss_limit_mb="${RSS_LIMIT_MB:-4096}" -malloc_limit_mb="${MALLOC_LIMIT_MB:-1048576}"
    -print_final_stats=1
    -artifact_prefix="$OUT/crashes/$t-" "$OUT/corpus/$t" "$OUT/seeds/$t")
  # VTK 9.1's XML readers leak on malformed files (testing/fuzz/lsan.supp); their suppressions
  # need full malloc stacks, which cost 5-10x the speed, so the two XML targets run without
  # leak detection here (ctest's fuzz.readers checks them with the suppressions)
  local leaks=1
  case "$t" in vtp|vtu) leaks=0 ;; esac
  args+=(-detect_leaks="$leaks")
  local pids=()
  for j in $(seq 1 "$JOBS"); do
    ( cd "$OUT" && ASAN_OPTIONS=detect_leaks=$leaks:allocator_may_return_null=1 \
      UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      LSAN_OPTIONS=suppressions="$ROOT/testing/fuzz/lsan.supp" \
      "$exe" -seed="$j" "${args[@]}" >"$OUT/logs/$t.$j.log" 2>&1 ) &
    pids+=($!)
  done
  local failed=0
  for p in "${pids[@]}"; do wait "$p" || failed=1; done
  local seconds=$(( $(date +%s) - start ))
  local executed=0 cov=0 ft=0
  for j in $(seq 1 "$JOBS"); do
    local f="$OUT/logs/$t.$j.log"
    executed=$(( executed + $(awk '/stat::number_of_executed_units/ {n=$2} END {print n+0}' "$f") ))
    local c f2
    c=$(grep -ao 'cov: [0-9]*' "$f" | tail -1 | awk '{print $2+0}')
    f2=$(grep -ao 'ft: [0-9]*' "$f" | tail -1 | awk '{print $2+0}')
    cov=$(( ${c:-0} > cov ? ${c:-0} : cov ))
    ft=$(( ${f2:-0} > ft ? ${f2:-0} : ft ))
  done
  cat "$OUT"/logs/"$t".*.log > "$OUT/logs/$t.log"
  local crashes=$(( $(find "$OUT/crashes" -name "$t-*" | wc -l) - before ))
  local corpus
  corpus=$(find "$OUT/corpus/$t" -type f | wc -l)
  printf '%s\t%d\t%d\t%d\t%d\t%d\t%d\t%d\n' "$t" "$executed" "$seconds" \
    $(( seconds > 0 ? executed / seconds : executed )) "$cov" "$ft" "$corpus" "$crashes" >> "$OUT/summary.tsv"
  log "$t: $executed executions in $seconds s, cov $cov, ft $ft, corpus $corpus, crashes $crashes"
  return $failed
}

cmd=${1:-}
case "$cmd" in
  build) build ;;
  list) targets ;;
  run)
    what=${2:-all}
    runs=${3:-1000000}
    mkdir -p "$OUT"
    [ -f "$OUT/summary.tsv" ] || printf 'target\texecutions\tseconds\texec/s\tcov\tft\tcorpus\tcrashes\n' > "$OUT/summary.tsv"
    status=0
    if [ "$what" = all ]; then
      for t in $(targets); do run_one "$t" "$runs" || status=1; done
    else
      run_one "$what" "$runs" || status=1
    fi
    exit $status
    ;;
  *)
    sed -n '2,/^set -euo/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
