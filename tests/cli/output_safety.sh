#!/bin/sh
# Output-safety cases that need a process in the middle of its run (output_safety_tests.cmake):
#   output_safety.sh CASE GEOVOR DIR SITES
# geovor reads its queries (nearest) or sites (cells) from a FIFO in DIR, so it waits there with
# its output's temporary file created; the script then acts, and exits with geovor's status.
#   race:  a file appears at the target meanwhile; geovor must not replace it (exit 4), and the
#          file must still hold "precious".
#   TERM, INT, HUP: the signal is sent; geovor must leave no temporary (the status is 128 + the
#          signal's number, as the shell reports it).
#   report_TERM: the same with `cells --report` (the report's temporary), SIGTERM.
set -u
case_=$1 geovor=$2 d=$3 sites=$4
rm -rf "$d" && mkdir -p "$d" && mkfifo "$d/in.csv" || exit 90

# Waits until the output directory holds more than the FIFO and the error log (a temporary).
wait_for_temporary() {
  i=0
  while [ "$(ls -A "$d" | grep -cv '^in\.csv$\|^err$')" -eq 0 ]; do
    i=$((i + 1))
    [ $i -gt 400 ] && { echo "no temporary appeared" >&2; kill -KILL "$pid"; exit 91; }
    sleep 0.05
  done
}

sig=
case $case_ in
  race)
    "$geovor" nearest --sites "$sites" --queries "$d/in.csv" -o "$d/out.csv" 2>"$d/err" &
    ;;
  TERM | INT | HUP)
    sig=$case_
    # A background job of a non-interactive shell ignores SIGINT: restore the default first.
    env --default-signal=INT "$geovor" nearest --sites "$sites" --queries "$d/in.csv" -o "$d/out.csv" 2>"$d/err" &
    ;;
  report_TERM)
    sig=TERM
    "$geovor" cells "$d/in.csv" -o "$d/out.geojson" --report "$d/report.csv" -q 2>"$d/err" &
    ;;
  *)
    echo "unknown case $case_" >&2
    exit 92
    ;;
esac
pid=$!
exec 3>"$d/in.csv"  # geovor's open of the FIFO returns
wait_for_temporary
if [ -n "$sig" ]; then
  kill -s "$sig" "$pid"
  wait "$pid"
  rc=$?
  exec 3>&-
  cat "$d/err" >&2
  left=$(ls -A "$d" | grep -v '^in\.csv$\|^err$')
  [ -z "$left" ] || { echo "left behind: $left" >&2; exit 93; }
  exit $rc
fi
printf 'precious' >"$d/out.csv"
printf 'lat,lon\n1,2\n' >&3
exec 3>&-
wait "$pid"
rc=$?
cat "$d/err" >&2
[ "$(cat "$d/out.csv")" = precious ] || { echo "out.csv was replaced" >&2; exit 94; }
left=$(ls -A "$d" | grep -v '^in\.csv$\|^err$\|^out\.csv$')
[ -z "$left" ] || { echo "left behind: $left" >&2; exit 93; }
exit $rc
