#!/usr/bin/python3
"""geovor serve (issue 34), the batch join and operations: POST /nearest gives the bytes of
`geovor nearest` (k, fields, columns named) for CSV, GeoJSON and GeoJSON sequences, malformed CSV is a 400 naming the line, a wrong media
type 415, a body over --max-body-mb 413; /metrics counts them; POST /admin/reload and SIGHUP swap
in a new index while 8 clients query without a single failed request, and a broken index file
leaves the old one serving (500 saying why); SIGTERM exits 0.
Usage: serve_ops_test.py GEOVOR SITES.csv WORKDIR"""
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request

geovor, sites, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def run(*args):
    return subprocess.run([geovor, *args], check=True, capture_output=True).stdout


index = os.path.join(work, "ops.gvi")
half_csv = os.path.join(work, "ops_half.csv")
with open(sites) as f:
    lines = f.read().splitlines()
with open(half_csv, "w") as f:
    f.write("\n".join(lines[: len(lines) // 2]) + "\n")
run("index", sites, "-o", index, "--overwrite", "-q")
half_index = os.path.join(work, "ops_half.gvi")
run("index", half_csv, "-o", half_index, "--overwrite", "-q")
full_copy = os.path.join(work, "ops_full.gvi")
shutil.copyfile(index, full_copy)

rng = random.Random(341)
qcsv = os.path.join(work, "ops_queries.csv")
with open(qcsv, "w") as f:
    f.write("id,lat,lon,note\n")
    for i in range(10000):
        f.write(f"q{i},{rng.uniform(-90, 90)!r},{rng.uniform(-180, 180)!r},\"n, {i}\"\n")
with open(qcsv, "rb") as f:
    body = f.read()

server = subprocess.Popen([geovor, "serve", index, "--port", "0", "--threads", "4", "--max-body-mb", "1"],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
try:
    base = "http://" + server.stdout.readline().split("http://")[1].split("/")[0]

    def request(path, data=None, ctype="text/csv"):
        req = urllib.request.Request(base + path, data=data, method="POST" if data is not None else "GET")
        if data is not None and ctype:
            req.add_header("Content-Type", ctype)
        try:
            with urllib.request.urlopen(req, timeout=60) as r:
                return r.status, r.headers.get("Content-Type"), r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.headers.get("Content-Type"), e.read()

    # POST /nearest = geovor nearest, byte for byte.
    for params, flags in [("", []), ("?k=3&fields=icao,name&metric=geodesic", ["--k", "3", "--site-fields", "icao,name", "--metric", "geodesic"]),
                          ("?max_distance_m=50000", ["--max-distance-m", "50000"])]:
        want = run("nearest", "--sites", index, "--queries", qcsv, *flags)
        status, ctype, got = request("/nearest" + params, body)
        check(status == 200 and ctype.startswith("text/csv"), f"POST {params}: {status} {ctype} {got[:200]}")
        check(got == want, f"POST /nearest{params}: differs from geovor nearest {flags} ({len(got)} vs {len(want)} bytes)")
    # GeoJSON in: a sequence (one feature per line, and RS records) and a FeatureCollection, answered
    # as geovor nearest writes .geojsonl, .geojsons and .geojson.
    points = [{"type": "Feature", "properties": {"id": f"g{i}", "n": i},
               "geometry": {"type": "Point", "coordinates": [rng.uniform(-180, 180), rng.uniform(-90, 90)]}} for i in range(3000)]
    for name, ctype, text, params, flags in [
            ("q.geojsonl", "application/geo+json-seq", "".join(json.dumps(p) + "\n" for p in points), "", []),
            ("q.geojsons", "application/geo+json-seq", "".join("\x1e" + json.dumps(p) + "\n" for p in points), "?k=2", ["--k", "2"]),
            ("q.geojson", "application/geo+json", json.dumps({"type": "FeatureCollection", "features": points}), "?fields=name",
             ["--site-fields", "name"])]:
        qfile, ofile = os.path.join(work, name), os.path.join(work, "out_" + name)
        with open(qfile, "w") as f:
            f.write(text)
        run("nearest", "--sites", index, "--queries", qfile, "-o", ofile, "--overwrite", *flags)
        with open(ofile, "rb") as f:
            want = f.read()
        status, got_type, got = request("/nearest" + params, text.encode(), ctype)
        check(status == 200 and got_type == ctype, f"POST {name}: {status} {got_type} {got[:200]}")
        check(got == want, f"POST {name}{params}: differs from geovor nearest -o {name} ({len(got)} vs {len(want)} bytes)")
    line = b'{"type":"Feature","geometry":{"type":"LineString","coordinates":[[0,0],[1,1]]},"properties":{}}\n'
    status, _, got = request("/nearest", line, "application/geo+json-seq")
    check(status == 400 and json.loads(got).get("feature") == 1 and "LineString" in json.loads(got)["error"].replace(" ", ""),
          f"a line in GeoJSON: {status} {got}")
    status, _, got = request("/nearest", b"garbage", "application/geo+json")
    check(status == 400 and "request body" in json.loads(got)["error"], f"not GeoJSON: {status} {got}")
    status, _, got = request("/nearest?lat_field=Y&lon_field=X", b"X,Y\n2.35,48.85\n")
    check(status == 200 and got.count(b"\n") == 2, f"named columns: {status} {got}")
    # Bad bodies.
    status, _, got = request("/nearest", b"lat,lon\n1,2\n3,x\n")
    err = json.loads(got)
    check(status == 400 and err.get("line") == 3 and "line 3" in err["error"], f"malformed line: {status} {got}")
    status, _, got = request("/nearest", b"lat,lon\n1,2\n", "application/xml")
    check(status == 415 and json.loads(got).get("parameter") == "Content-Type", f"media type: {status} {got}")
    status, _, got = request("/nearest", body * 3)  # over 1 MiB
    check(status == 413 and "larger than" in json.loads(got).get("error", ""), f"too large: {status} {got[:200]}")
    status, _, got = request("/nearest?lat_field=nope", b"lat,lon\n1,2\n")
    check(status == 400 and json.loads(got).get("parameter") == "lat_field", f"lat_field: {status} {got}")
    status, _, got = request("/nearest", b"")
    check(status == 400, f"empty body: {status} {got}")
    status, _, got = request("/healthz", b"x")
    check(status in (404, 405), f"POST /healthz: {status} {got}")

    # Reloads under load: 8 clients, every request answered 200 with a site of the index served.
    stop = threading.Event()
    results = []

    def client(seed):
        r = random.Random(seed)
        while not stop.is_set():
            s, _, b = request(f"/nearest?lat={r.uniform(-80, 80)!r}&lon={r.uniform(-180, 180)!r}")
            results.append(s)

    threads = [threading.Thread(target=client, args=(i,)) for i in range(8)]
    for t in threads:
        t.start()
    sites_seen = set()
    for i in range(6):
        shutil.copyfile(half_index if i % 2 == 0 else full_copy, index + ".tmp")
        os.replace(index + ".tmp", index)  # the file swapped whole, as an operator would
        if i % 3 == 2:
            server.send_signal(signal.SIGHUP)
            time.sleep(0.5)
        else:
            status, _, got = request("/admin/reload", b"", None)
            check(status == 200 and json.loads(got)["status"] == "reloaded", f"reload {i}: {status} {got}")
        sites_seen.add(json.loads(request("/healthz")[2])["sites"])
    with open(index, "wb") as f:
        f.write(b"not an index")
    status, _, got = request("/admin/reload", b"", None)
    check(status == 500 and "still served" in json.loads(got)["error"], f"broken index: {status} {got}")
    time.sleep(0.3)
    stop.set()
    for t in threads:
        t.join()
    check(len(results) > 100 and all(s == 200 for s in results),
          f"under reloads: {len(results)} requests, {sum(s != 200 for s in results)} not 200")
    check(len(sites_seen) == 2, f"reloads swapped the sites: {sites_seen}")
    status, _, got = request("/nearest?lat=1&lon=2")
    check(status == 200, f"after a failed reload the old index serves: {status}")
    # /metrics counts what happened.
    status, ctype, got = request("/metrics")
    text = got.decode()
    check(status == 200 and ctype.startswith("text/plain"), f"/metrics: {status} {ctype}")
    for needle in ['geovor_requests_total{route="POST /nearest",code="200"} 7', 'geovor_requests_total{route="POST /nearest",code="400"}',
                   'geovor_requests_total{route="POST /nearest",code="415"} 1', 'geovor_reloads_total{result="failed"} 1',
                   'geovor_request_duration_seconds_bucket{le="+Inf"}', "geovor_sites "]:
        check(needle in text, f"/metrics lacks {needle}")
finally:
    server.send_signal(signal.SIGTERM)
    try:
        code = server.wait(timeout=20)
    except subprocess.TimeoutExpired:
        server.kill()
        code = "hung"
err = server.stderr.read()
check(code == 0, f"SIGTERM: exit {code}, stderr {err[-300:]}")
check("reloaded" in err, f"SIGHUP says it reloaded: {err[-300:]}")
for f in failures:
    print("FAIL:", f)
print(f"serve_ops_test: {len(failures)} failures")
sys.exit(1 if failures else 0)
