#!/usr/bin/env bash
# Usage: scripts/build.sh [release|asan] [TARGET...]
#   release (default): build/, Release, tests, benchmarks and the Python extension (python/).
#   asan: build-asan/, Clang 14, RelWithDebInfo at -O1 with AddressSanitizer + UBSan, no
#     benchmarks; also the libFuzzer targets of tests/fuzz/ (GEOVOR_BUILD_FUZZ).
# Installs missing packages (install-deps.sh), configures with Ninja when needed and builds the
# given targets (default: all) with -j2. Re-running only rebuilds what changed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

mode=${1:-release}
(($# > 0)) && shift
case $mode in
  release)
    dir=build
    # The Python extension with Debian's Python (a python3 earlier in PATH may be another build).
    args=(-DCMAKE_BUILD_TYPE=Release -DGEOVOR_BUILD_TESTS=ON -DGEOVOR_BUILD_BENCH=ON
          -DGEOVOR_SANITIZE=OFF -DGEOVOR_BUILD_PYTHON=ON -DPython_EXECUTABLE=/usr/bin/python3)
    ;;
  asan)
    dir=build-asan
    args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g -DNDEBUG"
          -DGEOVOR_BUILD_TESTS=ON -DGEOVOR_BUILD_BENCH=OFF -DGEOVOR_SANITIZE=ON
          -DCMAKE_CXX_COMPILER=clang++-14 -DGEOVOR_BUILD_FUZZ=ON)
    ;;
  *)
    echo "usage: scripts/build.sh [release|asan] [TARGET...]" >&2
    exit 2
    ;;
esac

scripts/install-deps.sh

mkdir -p "$dir"
# One build at a time in a build directory (scripts/geovor may run while a build is going on).
exec 9>"$dir/.build.lock"
flock 9

if [[ -f $dir/CMakeCache.txt ]] && ! grep -qx 'CMAKE_GENERATOR:INTERNAL=Ninja' "$dir/CMakeCache.txt"; then
  echo "build.sh: $dir/ was configured with another generator than Ninja; remove it first" >&2
  exit 1
fi

# Configure when the directory is new or the options changed; otherwise Ninja re-runs CMake
# itself when a CMakeLists.txt changes.
stamp=$dir/.build-sh-args
if [[ ! -f $dir/build.ninja || ! -f $stamp || "$(cat "$stamp")" != "${args[*]}" ]]; then
  rm -f "$stamp"
  # A fresh configuration (and so a full rebuild): CMake cannot switch the compiler of a
  # configured directory.
  rm -rf "$dir/CMakeCache.txt" "$dir/CMakeFiles"
  cmake -S . -B "$dir" -G Ninja "${args[@]}"
  printf '%s' "${args[*]}" >"$stamp"
fi

targets=()
for target in "$@"; do
  targets+=(--target "$target")
done
cmake --build "$dir" -j2 "${targets[@]}"
