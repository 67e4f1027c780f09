#!/usr/bin/python3
"""geovor serve (issue 34), OGC API - Features: the landing page, /conformance, /collections,
items with limit, offset, bbox and their next links, and items/{id}, over the sites and the cells
of `geovor cells` (--cells); GDAL's OAPIF driver (ogrinfo, ogr2ogr) reads both layers back with
the features and geometries of the files; bad parameters are 400 naming them, unknown ids 404.
Usage: serve_features_test.py GEOVOR SITES.csv WORKDIR"""
import json
import os
import signal
import subprocess
import sys
import urllib.error
import urllib.request

geovor, sites, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


cells = os.path.join(work, "features_cells.geojson")
subprocess.run([geovor, "cells", sites, "-o", cells, "--overwrite", "-q"], check=True, capture_output=True)
with open(cells) as f:
    cell_file = json.load(f)["features"]
server = subprocess.Popen([geovor, "serve", sites, "--cells", cells, "--port", "0", "--threads", "2", "-q"],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
try:
    line = server.stdout.readline()
    base = "http://" + line.split("http://")[1].split("/")[0]

    def get(path):
        try:
            with urllib.request.urlopen(base + path, timeout=30) as r:
                return r.status, r.headers.get("Content-Type"), json.loads(r.read())
        except urllib.error.HTTPError as e:
            return e.code, e.headers.get("Content-Type"), json.loads(e.read())

    status, _, landing = get("/")
    rels = {l["rel"] for l in landing.get("links", [])}
    check(status == 200 and {"self", "conformance", "data"} <= rels, f"landing: {status} {landing}")
    check("service-desc" in rels, "landing: a service-desc link (QGIS needs it)")
    status, _, api = get("/api")
    check(status == 200 and "/collections/{collectionId}/items" in api.get("paths", {}), f"/api: {status}")
    status, _, conf = get("/conformance")
    check("http://www.opengis.net/spec/ogcapi-features-1/1.0/conf/core" in conf.get("conformsTo", []), f"conformance {conf}")
    status, _, colls = get("/collections")
    ids = [c["id"] for c in colls["collections"]]
    check(ids == ["sites", "cells"], f"collections: {ids}")

    # Paging through every cell by next links gives the file's features, in order.
    url, got = "/collections/cells/items?limit=1000", []
    while url:
        status, ctype, page = get(url)
        check(status == 200 and ctype == "application/geo+json", f"{url}: {status} {ctype}")
        got += page["features"]
        check(page["numberMatched"] == len(cell_file), f"numberMatched {page['numberMatched']}")
        nxt = [l["href"] for l in page["links"] if l["rel"] == "next"]
        url = nxt[0][len(base):] if nxt else None
    check(len(got) == len(cell_file), f"paged {len(got)} cells of {len(cell_file)}")
    check(all(g["geometry"] == c["geometry"] for g, c in zip(got, cell_file)), "paged cells' geometries = the file's")
    check(all(g["properties"]["site_index"] == c["properties"]["site_index"] for g, c in zip(got, cell_file)),
          "paged cells' properties = the file's")
    # bbox: every feature whose bbox meets the box, by brute force over the sites' points.
    status, _, all_sites = get("/collections/sites/items?limit=10000")
    for box in [(0, 40, 20, 55), (170, -50, -170, -10), (-180, 80, 180, 90)]:
        w, s, e, n = box

        def inside(lon, lat):
            return s <= lat <= n and ((w <= lon <= e) if w <= e else (lon >= w or lon <= e))

        want = [f["id"] for f in all_sites["features"] if inside(*f["geometry"]["coordinates"])]
        status, _, page = get(f"/collections/sites/items?limit=10000&bbox={w},{s},{e},{n}")
        check(status == 200 and [f["id"] for f in page["features"]] == want and want,
              f"bbox {box}: {len(page.get('features', []))} vs {len(want)}")
    status, _, one = get("/collections/cells/items/5")
    check(status == 200 and one["id"] == 5 and one["geometry"] == cell_file[5]["geometry"], f"items/5: {status}")
    status, _, site = get("/collections/sites/items/17")
    check(status == 200 and site["properties"]["site_index"] == 17, f"sites/items/17: {status} {site}")
    for path, code, param in [("/collections/sites/items?limit=0", 400, "limit"), ("/collections/sites/items?limit=x", 400, "limit"),
                              ("/collections/sites/items?bbox=1,2,3", 400, "bbox"), ("/collections/sites/items?bbox=0,10,5,5", 400, "bbox"),
                              ("/collections/sites/items?foo=1", 400, "foo"), ("/collections/nope/items", 404, None),
                              ("/collections/sites/items/999999", 404, None), ("/collections/nope", 404, None)]:
        status, ctype, body = get(path)
        check(status == code and (param is None or body.get("parameter") == param), f"{path}: {status} {body}")

    # GDAL's OAPIF driver reads both layers.
    info = subprocess.run(["ogrinfo", "-ro", "-q", f"OAPIF:{base}"], capture_output=True, text=True)
    check(info.returncode == 0 and "sites" in info.stdout and "cells" in info.stdout, f"ogrinfo: {info.stdout} {info.stderr}")
    for layer, count in [("cells", len(cell_file)), ("sites", len(all_sites["features"]))]:
        out = os.path.join(work, f"oapif_{layer}.geojson")
        if os.path.exists(out):
            os.remove(out)
        r = subprocess.run(["ogr2ogr", "-f", "GeoJSON", "-lco", "COORDINATE_PRECISION=15", "-oo", "PAGE_SIZE=1000", out, f"OAPIF:{base}", layer],
                           capture_output=True, text=True)
        check(r.returncode == 0, f"ogr2ogr {layer}: {r.stderr}")
        if r.returncode == 0:
            with open(out) as f:
                read = json.load(f)["features"]
            check(len(read) == count, f"OAPIF {layer}: {len(read)} features of {count}")
            if layer == "cells" and len(read) == count:
                check(all(a["geometry"]["type"] == b["geometry"]["type"] for a, b in zip(read, cell_file)),
                      "OAPIF cells' geometry types = the file's")
finally:
    server.send_signal(signal.SIGTERM)
    try:
        code = server.wait(timeout=20)
    except subprocess.TimeoutExpired:
        server.kill()
        code = "hung"
check(code == 0, f"SIGTERM: exit {code}: {server.stderr.read()[-300:]}")
for f in failures:
    print("FAIL:", f)
print(f"serve_features_test: {len(failures)} failures")
sys.exit(1 if failures else 0)
