#!/bin/sh
# has_fields.sh FILE 'NAME: TYPE'...: GDAL's ogrinfo lists each field of FILE's layers with that
# type (as "NAME: TYPE (width.precision)"); prints what it found otherwise and fails.
f=$1
shift
s=$(ogrinfo -ro -so -al "$f") || exit 1
for t in "$@"; do
  if ! printf '%s\n' "$s" | grep -q "^$t ("; then
    printf 'no field %s in %s:\n%s\n' "$t" "$f" "$s"
    exit 1
  fi
done
