#!/bin/bash
# geovor runs itself again at start with glibc.malloc.hugetlb=1 added to GLIBC_TUNABLES
# (tools/geovor.cpp, rerun_with_huge_pages), keeping a hugetlb tunable the user set.
# Each case starts `geovor nearest` on queries from a FIFO held open: once it blocks reading the
# FIFO (after any second start), its environment is read from /proc (glibc may have cut the
# tunables' list there at its ':'s as it parsed it: each tunable is looked for on its own).
# Usage: huge_pages.sh GEOVOR SITES_CSV WORK_DIR
set -euo pipefail
geovor=$1 sites=$2 work=$3
mkdir -p "$work"
fail=0
check() {  # check "EXPECTED_TUNABLE..." ENV_ASSIGNMENT... (ENV_ASSIGNMENT "-" for none)
  local want=$1 fifo=$work/queries.fifo pid got waited=0
  shift
  rm -f "$fifo"
  mkfifo "$fifo"
  if [[ $1 == - ]]; then
    env -u GLIBC_TUNABLES "$geovor" nearest --sites "$sites" --queries - -q <"$fifo" >/dev/null &
  else
    env "$@" "$geovor" nearest --sites "$sites" --queries - -q <"$fifo" >/dev/null &
  fi
  pid=$!
  exec 3>"$fifo"
  # Blocked in a read of the FIFO: the kernel's wait channel names the pipe (a kernel that
  # hides it says 0: then two seconds, far more than a start takes).
  until grep -q pipe "/proc/$pid/wchan" 2>/dev/null || { [[ $(cat "/proc/$pid/wchan" 2>/dev/null) == 0 ]] && ((waited >= 40)); }; do
    sleep 0.05
    waited=$((waited + 1))
    ((waited < 600)) || { echo "geovor did not block on its queries"; kill "$pid"; exit 1; }
  done
  got=$(tr '\0' '\n' <"/proc/$pid/environ" | sed -n 's/^GLIBC_TUNABLES=//p; t; /^glibc\./p' | tr '\n' ' ')
  exec 3>&-
  wait "$pid"
  local ok=1 t
  for t in $want; do [[ " $got" == *" $t "* ]] || ok=0; done
  # Never both values of hugetlb, nor the tunable when not expected.
  [[ $got == *hugetlb=0* && $got == *hugetlb=1* ]] && ok=0
  if ((ok)); then
    echo "ok: $* -> $got"
  else
    echo "FAIL: $* -> '$got', expected '$want'"
    fail=1
  fi
}
check "glibc.malloc.hugetlb=1" -
check "glibc.malloc.hugetlb=1" GLIBC_TUNABLES=
check "glibc.malloc.arena_max=2 glibc.malloc.hugetlb=1" GLIBC_TUNABLES=glibc.malloc.arena_max=2
check "glibc.malloc.hugetlb=0" GLIBC_TUNABLES=glibc.malloc.hugetlb=0
exit $fail
