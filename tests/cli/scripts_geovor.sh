#!/usr/bin/env bash
# scripts/geovor says on stderr that it is building (and where the log is) when there is no
# command yet or the build takes more than 2 seconds, and says nothing otherwise. Runs a copy of
# the script beside a stand-in build.sh (no real build): usage: scripts_geovor.sh SOURCE_DIR
set -euo pipefail
src=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/scripts"
cp "$src/scripts/geovor" "$tmp/scripts/geovor"
# The stand-in: sleeps $BUILD_S seconds, then installs a command that prints "ran: ARGS".
cat >"$tmp/scripts/build.sh" <<'STUB'
#!/usr/bin/env bash
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
sleep "${BUILD_S:-0}"
mkdir -p "$root/build/tools"
printf '#!/bin/sh\necho "ran: $*"\n' >"$root/build/tools/geovor"
chmod +x "$root/build/tools/geovor"
STUB
chmod +x "$tmp/scripts/build.sh"
fail() { echo "scripts_geovor.sh: $*" >&2; exit 1; }

# A fresh checkout: no command yet, the notice at once.
out=$(BUILD_S=0 "$tmp/scripts/geovor" info x 2>"$tmp/err1")
[[ $out == "ran: info x" ]] || fail "fresh: stdout '$out'"
grep -q "building geovor first.*log: $tmp/build/geovor-build.log" "$tmp/err1" || fail "fresh: no notice: $(cat "$tmp/err1")"
# Up to date: silent.
out=$(BUILD_S=0 "$tmp/scripts/geovor" cells y 2>"$tmp/err2")
[[ $out == "ran: cells y" && ! -s $tmp/err2 ]] || fail "up to date: stdout '$out', stderr '$(cat "$tmp/err2")'"
# A build of 3 seconds: the notice after 2.
BUILD_S=3 "$tmp/scripts/geovor" cells z >/dev/null 2>"$tmp/err3"
grep -q "building geovor first" "$tmp/err3" || fail "slow build: no notice"
# A failing build: its log on stderr, exit 1.
printf '#!/usr/bin/env bash\necho "compiler says no"\nexit 3\n' >"$tmp/scripts/build.sh"
if "$tmp/scripts/geovor" cells w >/dev/null 2>"$tmp/err4"; then fail "a failed build ran the command"; fi
grep -q "compiler says no" "$tmp/err4" && grep -q "the build failed (log: " "$tmp/err4" || fail "failed build: $(cat "$tmp/err4")"
echo "scripts_geovor.sh: ok"
