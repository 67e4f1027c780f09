#!/usr/bin/python3
"""--threads on every command (issue 36): the same files, byte for byte, and the same lines on
stdout and stderr (timings left out) for --threads 1, 2, 3 and the default (one per core), on
the bundled weather stations and on a generated hostile table: a 0.001-degree grid across the
antimeridian beside the north pole (co-circular quadruples), a co-circular ring around the south
pole and the pole itself, sites on the equator, exact and 10 cm duplicates, rejected rows, quoted
ids with commas and quotes, spread among uniform sites; over 1 MB, so that the CSV scan cuts it
into a chunk per thread (256 KiB at least each).
Usage: threads_test.py GEOVOR WORKDIR COMMAND
COMMAND: info, delaunay, index, nearest, cells, relax or balance (serve answers over HTTP:
tests/cli/serve_test.py)."""
import math
import os
import random
import re
import subprocess
import sys

geovor, work, command = sys.argv[1:4]
work = os.path.join(work, command)
os.makedirs(work, exist_ok=True)
root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
stations = os.path.join(root, "datasets", "weather_stations.csv")
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what, flush=True)


def hostile_table(path):
    rng = random.Random(36)
    rows = []
    for i in range(60):  # the grid: lat 89.94 to 89.999, lon 179.97 to 180.029 (past 180: normalised)
        for j in range(60):
            rows.append((f"g{i}_{j}", f"{89.94 + 0.001 * i:.3f}", f"{179.97 + 0.001 * j:.3f}"))
    for k in range(64):
        rows.append((f"ring{k}", "-89.9", f"{-180 + 360 * k / 64:.6f}"))
    rows.append(("south_pole", "-90", "0"))
    for k in range(100):
        rows.append((f"eq{k}", "0", f"{-180 + 3.6 * k:.1f}"))
    for k in range(32000):
        lat = math.degrees(math.asin(2 * rng.random() - 1))
        rows.append((f"u{k}", f"{lat:.7f}", f"{360 * rng.random() - 180:.7f}"))
    for k in range(200):  # exact duplicates, and 10 cm away (one site at the default merge distance)
        _, lat, lon = rows[rng.randrange(len(rows))]
        rows.append((f"dup{k}", lat, lon))
        rows.append((f"near{k}", f"{float(lat) + 9e-7 if float(lat) < 89 else float(lat):.7f}", lon))
    for k in range(40):
        rows.append((f"bad{k}", ["nan", "91", "", "abc"][k % 4], "10"))
    for k in range(40):
        rows.append((f'"q{k}, ""x"""', f"{rng.uniform(-60, 60):.5f}", f"{rng.uniform(-180, 180):.5f}"))
    rng.shuffle(rows)
    with open(path, "w") as f:
        f.write("id,lat,lon\n")
        f.writelines(f"{i},{lat},{lon}\n" for i, lat, lon in rows)


hostile = os.path.join(work, "hostile.csv")
hostile_table(hostile + ".tmp")
os.replace(hostile + ".tmp", hostile)
check(os.path.getsize(hostile) > 3 * 256 * 1024, "the hostile table is cut into 3 chunks")

TIMING = re.compile(r"^(read|build|validate|save)_seconds: .*$", re.M)


def normalised(text):
    """The text without its timings: info's and index's *_seconds lines, the last column of the
    iteration lines of relax and balance."""
    text = TIMING.sub("", text)
    return "\n".join(re.sub(r"\s+\S+$", "", line) if re.match(r"^\s+\d+\s", line) else line
                     for line in text.split("\n"))


def run(args):
    r = subprocess.run([geovor, *args], capture_output=True)
    check(r.returncode == 0, f"geovor {' '.join(args)}: exit {r.returncode}: {r.stderr[-500:]!r}")
    return normalised(r.stdout.decode()), normalised(r.stderr.decode())


def same_on_any_threads(name, make_args, files):
    """Runs make_args(tag) with --threads 1, 2, 3 and without --threads; every file of
    files(tag), stdout and stderr (each with its tag replaced) are the same as with 1."""
    results = {}
    for threads in ["1", "2", "3", None]:
        tag = f"t{threads or 'default'}"
        args = make_args(tag) + ([] if threads is None else ["--threads", threads])
        out, err = run(args)
        contents = [open(f, "rb").read() for f in files(tag)]
        results[tag] = (out.replace(tag, "T"), err.replace(tag, "T"), contents)
    ref = results["t1"]
    check(all(len(c) > 0 for c in ref[2]), f"{name}: outputs written")
    for tag, got in results.items():
        check(got[0] == ref[0], f"{name}: stdout with {tag} is that of --threads 1")
        check(got[1] == ref[1], f"{name}: stderr with {tag} is that of --threads 1")
        for i, (a, b) in enumerate(zip(got[2], ref[2])):
            check(a == b, f"{name}: {files(tag)[i]} is byte-identical to --threads 1's")


def path(*parts):
    return os.path.join(work, "_".join(parts))


inputs = {"stations": stations, "hostile": hostile}
for label, sites in inputs.items():
    name = f"{command} {label}"
    if command == "info":
        same_on_any_threads(name, lambda t: ["info", sites], lambda t: [])
    elif command == "delaunay":
        same_on_any_threads(name, lambda t: ["delaunay", sites, "-o", path(label, t, "tri.geojson"), "--edges",
                                             path(label, t, "edges.geojson"), "--overwrite"],
                            lambda t: [path(label, t, "tri.geojson"), path(label, t, "edges.geojson")])
    elif command == "index":
        same_on_any_threads(name, lambda t: ["index", sites, "-o", path(label, t, "sites.gvi"), "--overwrite"],
                            lambda t: [path(label, t, "sites.gvi")])
    elif command == "nearest":
        index = path(label, "sites.gvi")
        run(["index", sites, "-o", index, "--overwrite", "-q", "--threads", "1"])
        for queries_label, queries in inputs.items():
            # From the index file, then from the site table (read and built by nearest itself).
            for source_label, source in [("index", index), ("table", sites)]:
                same_on_any_threads(f"{name} {source_label}, queries {queries_label}",
                                    lambda t: ["nearest", "--sites", source, "--queries", queries, "-o",
                                               path(label, source_label, queries_label, t, "nearest.csv"), "--overwrite"],
                                    lambda t: [path(label, source_label, queries_label, t, "nearest.csv")])
        same_on_any_threads(f"{name} k 3", lambda t: ["nearest", "--sites", index, "--queries", stations, "--k", "3", "-o",
                                                      path(label, t, "k3.csv"), "--overwrite"],
                            lambda t: [path(label, t, "k3.csv")])
    elif command == "cells":
        same_on_any_threads(name, lambda t: ["cells", sites, "-o", path(label, t, "cells.geojson"), "--report",
                                             path(label, t, "report.csv"), "--overwrite"],
                            lambda t: [path(label, t, "cells.geojson"), path(label, t, "report.csv")])
    elif command == "relax":
        same_on_any_threads(name, lambda t: ["relax", sites, "-n", "2", "-o", path(label, t, "relaxed.geojson"),
                                             "--sites-output", path(label, t, "sites.csv"), "--overwrite"],
                            lambda t: [path(label, t, "relaxed.geojson"), path(label, t, "sites.csv")])
    elif command == "balance":
        if label == "hostile":
            continue  # equal areas for a 0.001-degree grid: radii beyond any tolerance; the stations suffice
        same_on_any_threads(name, lambda t: ["balance", sites, "-o", path(label, t, "balanced.geojson"),
                                             "--sites-output", path(label, t, "sites.csv"), "--overwrite"],
                            lambda t: [path(label, t, "balanced.geojson"), path(label, t, "sites.csv")])
    else:
        sys.exit(f"unknown command {command}")

if failures:
    sys.exit(f"{len(failures)} failures")
print("ok")
