#!/usr/bin/python3
"""geovor serve (issue 34): starts the server on a free loopback port over an index, and checks
GET /nearest against `geovor nearest` on the same queries (same sites, same distances, k = 3 in
order), under concurrent requests, bad requests (400 with the parameter named, 404), /healthz,
and that SIGTERM ends it with exit 0.
Usage: serve_test.py GEOVOR SITES.csv WORKDIR"""
import csv
import json
import math
import os
import random
import signal
import subprocess
import sys
import urllib.error
import urllib.request
from concurrent.futures import ThreadPoolExecutor

geovor, sites, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
index = os.path.join(work, "serve.gvi")
subprocess.run([geovor, "index", sites, "-o", index, "--overwrite", "-q"], check=True, capture_output=True)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


rng = random.Random(34)
queries = [(rng.uniform(-89.9, 89.9), rng.uniform(-180, 180)) for _ in range(300)] + [(90, 0), (-90, 0), (0, 180), (0, -180)]
qcsv = os.path.join(work, "serve_queries.csv")
with open(qcsv, "w") as f:
    f.write("id,lat,lon\n")
    for i, (la, lo) in enumerate(queries):
        f.write(f"q{i},{la!r},{lo!r}\n")
expected = {}
for k in (1, 3):
    out = subprocess.run([geovor, "nearest", "--sites", index, "--queries", qcsv, "--k", str(k)],
                         check=True, capture_output=True, text=True).stdout
    for row in csv.DictReader(out.splitlines()):
        expected.setdefault((row["query_id"], k), []).append((int(row["site_index"]), float(row["distance_m"])))

server = subprocess.Popen([geovor, "serve", index, "--port", "0", "--threads", "4"], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True)
try:
    line = server.stdout.readline()
    check("http://127.0.0.1:" in line, f"the first line gives the address: {line!r}")
    base = line.split("http://")[1].split("/")[0]

    def get(path):
        try:
            with urllib.request.urlopen(f"http://{base}{path}", timeout=10) as r:
                return r.status, r.headers.get("Content-Type"), r.read().decode()
        except urllib.error.HTTPError as e:
            return e.code, e.headers.get("Content-Type"), e.read().decode()

    def answer(i_k):
        i, k = i_k
        la, lo = queries[i]
        status, ctype, body = get(f"/nearest?lat={la!r}&lon={lo!r}&k={k}")
        if status != 200:
            return f"q{i} k={k}: status {status} {body}"
        feats = json.loads(body)["features"]
        got = [(f["properties"]["site_index"], f["properties"]["distance_m"]) for f in feats]
        want = expected[(f"q{i}", k)]
        if got != want:
            return f"q{i} k={k}: {got} vs geovor nearest {want}"
        if ctype != "application/geo+json":
            return f"content type {ctype}"
        return None

    with ThreadPoolExecutor(max_workers=8) as pool:  # concurrent requests, every one checked
        wrong = [w for w in pool.map(answer, [(i, k) for k in (1, 3) for i in range(len(queries))]) if w]
    check(not wrong, f"GET /nearest = geovor nearest: {len(wrong)} differ: {wrong[:3]}")
    # Brute force, sharing no code with geovor: the angle between the geocentric directions of the
    # WGS84 positions (geovor's sphere metric) to every site; the answer's within 1e-9 of the least.
    def unit(lat_deg, lon_deg):
        p, l = math.radians(lat_deg), math.radians(lon_deg)
        e2 = 0.0066943799901413165
        n = 1 / math.sqrt(1 - e2 * math.sin(p) ** 2)
        v = (n * math.cos(p) * math.cos(l), n * math.cos(p) * math.sin(l), n * (1 - e2) * math.sin(p))
        norm = math.sqrt(sum(c * c for c in v))
        return tuple(c / norm for c in v)

    def angle(a, b):
        cross = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
        return math.atan2(math.sqrt(sum(c * c for c in cross)), sum(x * y for x, y in zip(a, b)))

    with open(sites) as f:
        pts = [unit(float(r["lat_deg"]), float(r["lon_deg"])) for r in csv.DictReader(f)]
    bad = []
    for i, (la, lo) in enumerate(queries[:120]):
        q = unit(la, lo)
        best = min(angle(q, p) for p in pts) * 6371008.771415
        got = json.loads(get(f"/nearest?lat={la!r}&lon={lo!r}")[2])["features"][0]["properties"]["distance_m"]
        if abs(got - best) > 1e-9 * max(best, 1.0):
            bad.append((i, got, best))
    check(not bad, f"GET /nearest = brute force: {len(bad)} differ: {bad[:3]}")
    for path, param in [("/nearest?lon=2", "lat"), ("/nearest?lat=95&lon=2", "lat"), ("/nearest?lat=1&lon=abc", "lon"),
                        ("/nearest?lat=1&lon=2&k=0", "k"), ("/nearest?lat=1&lon=2&k=1000", "k"),
                        ("/nearest?lat=1&lon=2&metric=taxi", "metric"), ("/nearest?lat=1&lon=2&fields=nope", "fields"),
                        ("/nearest?lat=1&lon=2&lat=3", "lat"), ("/nearest?lat=1&lon=2&bogus=1", "bogus")]:
        status, ctype, body = get(path)
        ok = status == 400 and ctype == "application/json"
        try:
            ok = ok and json.loads(body).get("parameter") == param and param in json.loads(body).get("error", "")
        except ValueError:
            ok = False
        check(ok, f"{path}: expected 400 naming {param}, got {status} {ctype} {body}")
    status, _, body = get("/no/such")
    check(status == 404 and "error" in json.loads(body), f"/no/such: {status} {body}")
    status, _, body = get("/healthz")
    check(status == 200 and json.loads(body)["status"] == "ok", f"/healthz: {status} {body}")
finally:
    server.send_signal(signal.SIGTERM)
    try:
        code = server.wait(timeout=10)
    except subprocess.TimeoutExpired:
        server.kill()
        code = "hung"
check(code == 0, f"SIGTERM: exit {code}, stderr {server.stderr.read()[-300:]}")
for f in failures:
    print("FAIL:", f)
print(f"serve_test: {len(failures)} failures")
sys.exit(1 if failures else 0)
