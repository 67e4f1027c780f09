#!/usr/bin/python3
"""Row accounting over every CSV fixture (issue 16): each data row ends exactly once as a site, a
row merged into a listed cell, or a rejected row with its reason.

For each FILE given: the data rows are counted here with Python's csv module (the delimiter
chosen by the documented sniff: the most frequent of , ; TAB | in the header outside quotes, ties
in that order), never by geovor. Then
- `geovor cells FILE --report R -o C.geojson`: exit 0 with R holding exactly one line per data row
  (rows 1..N, each once, status site/merged/rejected, a rejected row with a reason); one cell per
  `site` row, with that row's id as site_id; each `merged` row's id listed in the `ids` of the
  cell at its site_index; n_rows adding up to sites + merged;
- `geovor info FILE`: rows/sites/merged/rejected equal to the report's counts;
- `geovor nearest --sites FILE`: stderr lists exactly the report's rejected rows (row numbers);
or, for a file refused as a whole (exit 3: no usable site, a bad header), no output written, the
file named, and, for `no usable site`, every data row rejected and listed.

Usage: check_fixture_accounting.py GEOVOR OUTDIR FILE...
Last line: `accounting: N files passed, M failed`.
"""
import csv
import io
import json
import os
import re
import subprocess
import sys


def sniff(header):
    counts = {d: 0 for d in ",;\t|"}
    inside = False
    for ch in header:
        if ch == '"':
            inside = not inside
        elif not inside and ch in counts:
            counts[ch] += 1
    best = ","
    for d in ",;\t|":
        if counts[d] > counts[best]:
            best = d
    return best


def data_rows(path):
    text = open(path, "rb").read().decode("utf-8", "replace")
    if text.startswith("\ufeff"):
        text = text[1:]
    if not text.strip("\r\n"):
        return None  # empty: no header
    header = re.split(r"\r?\n", text, maxsplit=1)[0]
    records = list(csv.reader(io.StringIO(text, newline=""), delimiter=sniff(header)))
    return sum(1 for r in records[1:] if r)  # an empty line is no row (user-guide, "Delimited text")


def escaped(text):
    """A value as messages and the --report write it: control characters escaped (user-guide)."""
    names = {"\0": "\\0", "\n": "\\n", "\t": "\\t", "\r": "\\r"}
    return "".join(names.get(ch, f"\\x{ord(ch):02X}" if ord(ch) < 0x20 or ord(ch) == 0x7F else ch) for ch in text)


def run(cmd):
    return subprocess.run(cmd, capture_output=True, timeout=120)


def check(geovor, out, path):
    fails = []
    n = data_rows(path)
    base = os.path.join(out, os.path.basename(path))
    cells, rep = base + ".geojson", base + ".report.csv"
    for f in (cells, rep):
        if os.path.exists(f):
            os.remove(f)
    p = run([geovor, "cells", path, "-o", cells, "--report", rep, "-q"])
    err = p.stderr.decode("utf-8", "replace")
    if p.returncode == 3:
        if os.path.exists(cells) or os.path.exists(rep):
            fails.append("exit 3 but an output was written")
        if path not in err:
            fails.append(f"exit 3 without naming the file: {err.strip()}")
        m = re.search(r"no usable site \((\d+) rows, (\d+) rejected\)", err)
        if m:
            listed = len(re.findall(r": row \d+ \(line \d+\) rejected: ", err))
            if int(m.group(1)) != (n or 0) or int(m.group(2)) != (n or 0) or listed != (n or 0):
                fails.append(f"no usable site: {m.group(0)}, {listed} listed; expected all {n} data rows rejected")
        return fails, f"refused (exit 3): {err.strip().splitlines()[-1] if err.strip() else ''}"
    if p.returncode != 0:
        return [f"cells exited {p.returncode}: {err.strip()}"], ""
    with open(rep, newline="", encoding="utf-8") as f:
        report = list(csv.DictReader(f))
    rows = sorted(int(r["row"]) for r in report)
    if rows != list(range(1, n + 1)):
        fails.append(f"report rows {rows}, expected 1..{n} each once (the csv module counts {n} data rows)")
    with open(cells, encoding="utf-8") as f:
        feats = {ft["properties"]["site_index"]: ft["properties"] for ft in json.load(f)["features"]}
    count = {"site": 0, "merged": 0, "rejected": 0}
    for r in report:
        st = r["status"]
        if st not in count:
            fails.append(f"row {r['row']}: status {st!r}")
            continue
        count[st] += 1
        if st == "rejected":
            if not r["detail"]:
                fails.append(f"row {r['row']}: rejected without a reason")
            continue
        cell = feats.get(int(r["site_index"]))
        if cell is None:
            fails.append(f"row {r['row']}: {st} in site {r['site_index']}, which has no cell")
        elif st == "site" and escaped(cell["site_id"]) != r["id"]:
            fails.append(f"row {r['row']}: site {r['site_index']} has site_id {cell['site_id']!r}, the row's id is {r['id']!r}")
        elif st == "merged" and r["id"] not in [escaped(i) for i in cell["ids"]]:
            fails.append(f"row {r['row']}: merged into site {r['site_index']}, whose ids {cell['ids']} lack {r['id']!r}")
    if len(feats) != count["site"]:
        fails.append(f"{len(feats)} cells, {count['site']} site rows")
    if sum(c["n_rows"] for c in feats.values()) != count["site"] + count["merged"]:
        fails.append("n_rows do not add up to sites + merged")
    p = run([geovor, "info", path])
    info = dict(re.findall(r"^(\w+): (\S+)$", p.stdout.decode("utf-8", "replace"), re.M))
    want = {"rows": n, "sites": count["site"], "merged": count["merged"], "rejected": count["rejected"]}
    got = {k: int(info.get(k, -1)) for k in want}
    if p.returncode != 0 or got != want:
        fails.append(f"info (exit {p.returncode}): {got}, the report says {want}")
    q = base + ".queries.csv"
    with open(q, "w") as f:
        f.write("lat,lon\n0,0\n")
    p = run([geovor, "nearest", "--sites", path, "--queries", q, "-o", os.devnull, "-q"])
    listed = sorted(int(x) for x in re.findall(r": row (\d+) \(line \d+\) rejected: ", p.stderr.decode("utf-8", "replace")))
    rejected = sorted(int(r["row"]) for r in report if r["status"] == "rejected")
    if p.returncode != 0 or listed != rejected:
        fails.append(f"nearest (exit {p.returncode}) lists rejected rows {listed}, the report {rejected}")
    return fails, f"{n} rows = {count['site']} sites + {count['merged']} merged + {count['rejected']} rejected"


def main():
    geovor, out, files = sys.argv[1], sys.argv[2], sys.argv[3:]
    os.makedirs(out, exist_ok=True)
    passed = failed = 0
    for path in files:
        fails, what = check(geovor, out, path)
        if fails:
            failed += 1
            print(f"FAIL {path}")
            for f in fails:
                print("  " + f)
        else:
            passed += 1
            print(f"ok {path}: {what}")
    print(f"accounting: {passed} files passed, {failed} failed")
    return 1 if failed or not files else 0


if __name__ == "__main__":
    sys.exit(main())
