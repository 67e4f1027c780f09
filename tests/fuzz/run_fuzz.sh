#!/usr/bin/env bash
# Runs one fuzz target on its corpus (tests/fuzz/corpus/NAME) and regressions
# (tests/fuzz/regressions/NAME); ctest calls it (tests/fuzz/CMakeLists.txt).
#   run_fuzz.sh replay BINARY NAME SOURCE_DIR WORK_DIR
#     runs every corpus and regression input once (libFuzzer build or the replay main).
#   run_fuzz.sh fuzz BINARY NAME SOURCE_DIR WORK_DIR SECONDS
#     libFuzzer for SECONDS on a scratch copy of the corpus in WORK_DIR/corpus (the repository's
#     directories are only read); a crash leaves its input in WORK_DIR/artifacts/ and fails.
set -euo pipefail
mode=$1 bin=$2 name=$3 src=$4 work=$5
corpus=$src/corpus/$name
regressions=$src/regressions/$name
inputs=()
for dir in "$corpus" "$regressions"; do
  [[ -d $dir ]] && while IFS= read -r -d '' f; do inputs+=("$f"); done < <(find "$dir" -type f ! -name '.*' -print0 | sort -z)
done
case $mode in
  replay)
    ((${#inputs[@]} > 0)) || { echo "run_fuzz.sh: no input in $corpus" >&2; exit 1; }
    exec "$bin" "${inputs[@]}"
    ;;
  fuzz)
    seconds=$6
    rm -rf "$work"
    mkdir -p "$work/corpus" "$work/artifacts"
    cp "${inputs[@]}" "$work/corpus/"
    rc=0
    # -timeout is for hangs: a legitimate input can take 30 s under ASan (134 lunes of sites on
    # one meridian at 12 decimals: 2.45 million written positions, 10 s in a release build), and
    # a mutation of 177 sites on one meridian took 25 s in release, over 40 s under ASan beside
    # another fuzzer (fuzz.cells ran 103 s once); the test's limit is SECONDS + 300.
    "$bin" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=240 -print_final_stats=1 \
      -artifact_prefix="$work/artifacts/" "$work/corpus" || rc=$?
    if ((rc != 0)); then
      echo "run_fuzz.sh: $name failed (exit $rc); the input is in $work/artifacts/:" >&2
      ls -l "$work/artifacts/" >&2 || true
      echo "run_fuzz.sh: fix the bug, then add the input to tests/fuzz/regressions/$name/" >&2
    fi
    exit "$rc"
    ;;
  *)
    echo "usage: run_fuzz.sh replay|fuzz BINARY NAME SOURCE_DIR WORK_DIR [SECONDS]" >&2
    exit 2
    ;;
esac
