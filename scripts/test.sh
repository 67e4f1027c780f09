#!/usr/bin/env bash
# The test command: release build and all its tests, the Python package's tests (pytest), then
# the ASan/UBSan build and all its tests except those labelled package or nosan, then 60 s of each
# libFuzzer target (tests labelled fuzz, docs/fuzzing.md). Exits non-zero if any stage fails. Ends with one summary line per stage (with
# elapsed seconds) and the total of tests passed and failed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

ctest_args=(--output-on-failure -j2 --timeout 600 --no-tests=error)
ctest_env=()
ctest_log=ctest.log
summary=()
failed=0
tests_passed=0
tests_failed=0

# stage NAME COMMAND...: runs the command and records "NAME: ok|FAILED (exit N) in S s".
stage() {
  local name=$1 start=$SECONDS rc=0
  shift
  echo "=== $name: $*"
  "$@" || rc=$?
  if ((rc == 0)); then
    summary+=("$name: ok in $((SECONDS - start)) s")
  else
    summary+=("$name: FAILED (exit $rc) in $((SECONDS - start)) s")
    failed=1
  fi
  return "$rc"
}

# skip NAME REASON: records a stage that could not run (and so fails the run).
skip() {
  summary+=("$1: skipped, $2")
  failed=1
}

# run_ctest DIR [CTEST_ARG...]: ctest on DIR with ctest_env set; its output also goes to
# DIR/$ctest_log. Adds the counts from ctest's closing line to the totals.
# shellcheck disable=SC2317  # called through stage
run_ctest() {
  local dir=$1 rc=0 line
  shift
  env "${ctest_env[@]}" ctest --test-dir "$dir" "${ctest_args[@]}" "$@" 2>&1 |
    tee "$dir/$ctest_log" || rc=$?
  line=$(grep -E '[0-9]+ tests? failed out of [0-9]+' "$dir/$ctest_log" | tail -n 1 || true)
  if [[ $line =~ ([0-9]+)\ tests?\ failed\ out\ of\ ([0-9]+) ]]; then
    tests_failed=$((tests_failed + BASH_REMATCH[1]))
    tests_passed=$((tests_passed + BASH_REMATCH[2] - BASH_REMATCH[1]))
  fi
  return "$rc"
}

# run_pytest: installs the Python package (pip install --no-build-isolation, its extension from
# the release build) into build/python-venv, a virtual environment over Debian's packages, and runs
# python/tests with pytest. Adds its counts to the totals.
# shellcheck disable=SC2317  # called through stage
run_pytest() {
  local venv=build/python-venv rc=0 line
  [[ -x $venv/bin/python ]] || /usr/bin/python3 -m venv --system-site-packages "$venv"
  GEOVOR_CMAKE_BUILD_DIR=build "$venv/bin/pip" install --no-build-isolation --no-deps --no-index -q . || return
  # From build/, so that python/geovor (the sources, without the extension) is not imported.
  (cd build && python-venv/bin/python -m pytest -p no:cacheprovider -q ../python/tests) 2>&1 |
    tee build/pytest.log || rc=$?
  line=$(tail -n 1 build/pytest.log)
  [[ $line =~ ([0-9]+)\ passed ]] && tests_passed=$((tests_passed + BASH_REMATCH[1]))
  [[ $line =~ ([0-9]+)\ failed ]] && tests_failed=$((tests_failed + BASH_REMATCH[1]))
  [[ $line =~ ([0-9]+)\ error ]] && tests_failed=$((tests_failed + BASH_REMATCH[1]))
  return "$rc"
}

if stage build-release scripts/build.sh release; then
  stage test-release run_ctest build || true
  stage test-python run_pytest || true
else
  skip test-release "the release build failed"
  skip test-python "the release build failed"
fi

if stage build-asan scripts/build.sh asan; then
  ctest_env=(ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
             UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1)
  stage test-asan run_ctest build-asan -LE 'package|nosan|^fuzz$' || true
  # A failing target leaves its input in build-asan/tests/fuzz/<name>/artifacts/ (path in the log).
  ctest_log=ctest-fuzz.log
  stage fuzz run_ctest build-asan -L '^fuzz$' || true
else
  skip test-asan "the asan build failed"
  skip fuzz "the asan build failed"
fi

echo
echo "=== summary"
printf '%s\n' "${summary[@]}"
echo "tests: $tests_passed passed, $tests_failed failed"
exit "$failed"
