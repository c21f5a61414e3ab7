#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, -fsanitize=fuzzer,address,undefined) and runs each for a fixed budget.
#   bash tests/fuzz/run.sh [SECONDS] [TARGET...]     targets: ply pcd obj off stl xyz config (default: all)
# SECONDS per target (default 30); FUZZ_JOBS targets at a time (default 2). BUILD_DIR overrides build-fuzz.
# Prints executions and crashes per target; exits 1 if any target crashed (the input is left in BUILD_DIR/crashes:
# minimise it with -minimize_crash=1 and add it to tests/nodes/io/regressions). Without clang or libFuzzer it
# skips with a message and exits 0, so CI stays within its time budget on machines without them.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
seconds=${1:-30}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(ply pcd obj off stl xyz config)
jobs=${FUZZ_JOBS:-2}
build=${BUILD_DIR:-$root/build-fuzz}

if ! command -v clang++ >/dev/null 2>&1 || ! dpkg-query -W -f='${Status}' libclang-rt-14-dev 2>/dev/null | grep -q "ok installed"; then
  # A fresh Debian machine has neither: install them when we may (root or sudo), as cmake/dev.sh does its packages.
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo=sudo
  if [ -z "$sudo" ] || command -v sudo >/dev/null 2>&1; then
    echo "fuzz: installing clang and libclang-rt-14-dev"
    $sudo apt-get update -qq >/dev/null 2>&1 || true
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev \
      >/dev/null 2>&1 || true
  fi
fi
if ! command -v clang++ >/dev/null 2>&1; then
  echo "fuzz: skipped: clang++ not found (Debian: apt-get install clang libclang-rt-14-dev)"
  exit 0
fi
probe=$(mktemp -d)
trap 'rm -rf "$probe"' EXIT
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' >"$probe/p.cpp"
if ! clang++ -fsanitize=fuzzer,address,undefined "$probe/p.cpp" -o "$probe/p" >/dev/null 2>&1; then
  echo "fuzz: skipped: clang++ cannot link -fsanitize=fuzzer (Debian: apt-get install libclang-rt-14-dev)"
  exit 0
fi

mkdir -p "$build"
launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# -O1 with line tables: quick to compile (the build is most of the CI budget), enough for symbolised reports.
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" -DSCANFILL_FUZZ=ON \
  -DSCANFILL_BUILD_TESTS=OFF -DSCANFILL_BUILD_BENCH=OFF "${launcher[@]}" >"$build/configure.log" 2>&1 ||
  { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j "${FUZZ_BUILD_JOBS:-$(nproc 2>/dev/null || echo 2)}" --target "${targets[@]/#/fuzz_}"

mkdir -p "$build/crashes" "$build/logs"
run_one() {  # target
  local t=$1 corpus="$build/corpus/$1"
  mkdir -p "$corpus"
  # Small inputs (the seeds are < 1 KB); 256 MB per allocation is far above what a file of 4 KB may need: a count
  # taken from the header without checking it against the file trips it.
  # malloc_context_size=0: no stack trace kept per allocation (the config loader allocates a lot; 2x the speed).
  ASAN_OPTIONS=${ASAN_OPTIONS:-malloc_context_size=0} "$build/tests/fuzz/fuzz_$t" "$corpus" "$root/tests/fuzz/corpus/$t" -dict="$root/tests/fuzz/dict/$t.dict" \
    -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=1024 -malloc_limit_mb=256 \
    -artifact_prefix="$build/crashes/$t-" -print_final_stats=1 >"$build/logs/$t.log" 2>&1 || true
}
running=0
for t in "${targets[@]}"; do
  run_one "$t" &
  running=$((running + 1))
  if ((running >= jobs)); then
    wait -n || true
    running=$((running - 1))
  fi
done
wait

failed=0
for t in "${targets[@]}"; do
  log="$build/logs/$t.log"
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  crashes=$(grep -c 'Test unit written to' "$log" || true)
  echo "fuzz_$t: ${execs:-0} executions in ${seconds} s, ${crashes} crashes"
  if ((crashes > 0)); then
    failed=1
    grep -m1 -E 'ERROR|deadly|out-of-memory|uncaught' "$log" || true
    grep 'Test unit written to' "$log" || true
  elif ((${execs:-0} == 0)); then
    failed=1
    echo "fuzz_$t: did not run; see $log"
  fi
done
exit $failed
