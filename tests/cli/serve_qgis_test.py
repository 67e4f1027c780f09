#!/usr/bin/python3
"""geovor serve (issue 34): QGIS (Debian's python3-qgis, headless) reads the sites and the cells
as OGC API - Features layers: valid, every feature, Point and MultiPolygon, the sites' columns.
Exit 77 (skipped) without python3-qgis. Usage: serve_qgis_test.py GEOVOR SITES.csv WORKDIR"""
import json
import os
import signal
import subprocess
import sys

geovor, sites, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
os.environ.setdefault("XDG_RUNTIME_DIR", work)
try:
    from qgis.core import QgsApplication, QgsVectorLayer, QgsWkbTypes
except ImportError:
    print("serve_qgis_test: no python3-qgis; skipped")
    sys.exit(77)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


cells = os.path.join(work, "qgis_cells.geojson")
subprocess.run([geovor, "cells", sites, "-o", cells, "--overwrite", "-q"], check=True, capture_output=True)
with open(cells) as f:
    n_cells = len(json.load(f)["features"])
server = subprocess.Popen([geovor, "serve", sites, "--cells", cells, "--port", "0", "-q"], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True)
try:
    base = "http://" + server.stdout.readline().split("http://")[1].split("/")[0]
    QgsApplication.setPrefixPath("/usr", True)
    app = QgsApplication([], False)
    app.initQgis()
    for name, geometry, fields in [("sites", QgsWkbTypes.Point, ["site_index", "site_id", "icao", "name"]),
                                   ("cells", QgsWkbTypes.MultiPolygon, ["site_index", "site_id"])]:
        layer = QgsVectorLayer(f"url='{base}' typename='{name}'", name, "OAPIF")
        check(layer.isValid(), f"QGIS: {name} is not a valid layer")
        if not layer.isValid():
            continue
        features = list(layer.getFeatures())
        check(len(features) == n_cells, f"QGIS {name}: {len(features)} features of {n_cells}")
        check(QgsWkbTypes.flatType(layer.wkbType()) == geometry, f"QGIS {name}: geometry type {layer.wkbType()}")
        check(all(f in layer.fields().names() for f in fields), f"QGIS {name}: fields {layer.fields().names()}")
        check(all(not f.geometry().isNull() for f in features), f"QGIS {name}: a feature without geometry")
        del features, layer
finally:
    server.send_signal(signal.SIGTERM)
    try:
        server.wait(timeout=20)
    except subprocess.TimeoutExpired:
        server.kill()
for f in failures:
    print("FAIL:", f)
print(f"serve_qgis_test: {len(failures)} failures", flush=True)
os._exit(1 if failures else 0)  # not QGIS's teardown, which may crash at exit (QGIS 3.22 offscreen)
