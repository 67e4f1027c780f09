"""The QGIS Processing provider (qgis/geovor/) against the geovor command, headless.

Usage: qgis_provider_test.py GEOVOR EXTENSION SOURCE_DIR WORK_DIR

Runs Debian's qgis_process (its .bin: the /usr/bin/qgis_process wrapper adds --noversioncheck,
which qgis_process rejects) with QGIS_PLUGINPATH=SOURCE_DIR/qgis and QT_QPA_PLATFORM=offscreen in
a profile of its own (HOME=WORK_DIR/home): `plugins enable geovor`, then geovor:cells,
geovor:delaunay (triangles and edges), geovor:nearest and geovor:balance on the bundled weather
stations as a GeoPackage point layer, and compares every output with the command's on the same
layer (GEOVOR cells / delaunay / nearest / balance -o *.gpkg, doubles in both): the same count,
the same ids in the same order, areas and distances equal within 1e-9 relative, geometries equal
(shapely equals_exact, 1e-9 degrees), the command's other fields equal. Also: sites in a projected
CRS, reprojected by the plugin (QgsCoordinateTransform) and by the command (OGR), to the same
cells; the error when the geovor package cannot be found; and, in this process through PyQGIS,
progress from 0 to 100 and cancel while reading or writing. The geovor package is the sources
of SOURCE_DIR/python/geovor with the EXTENSION just built, copied to WORK_DIR/pylib/geovor, which
GEOVOR_PYTHONPATH names.

Exit 77 (skipped) without qgis_process.bin or python3-qgis.
"""
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

QGIS_PROCESS = Path("/usr/bin/qgis_process.bin")
SKIP = 77

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print(f"FAIL: {message}", flush=True)
    return condition


def run(command, env=None, expect=0):
    start = time.monotonic()
    done = subprocess.run([str(c) for c in command], env=env, capture_output=True, text=True)
    seconds = time.monotonic() - start
    print(f"[{seconds:5.1f} s] {' '.join(str(c) for c in command)} -> {done.returncode}", flush=True)
    if expect is not None and done.returncode != expect:
        print(done.stdout[-4000:], done.stderr[-4000:], sep="\n")
        raise SystemExit(f"exit {done.returncode}, expected {expect}: {' '.join(str(c) for c in command)}")
    return done


def main():
    if len(sys.argv) != 5:
        raise SystemExit(__doc__)
    geovor, extension, source, work = (Path(a).resolve() for a in sys.argv[1:])
    if not QGIS_PROCESS.is_file():
        print(f"{QGIS_PROCESS} is absent (Debian's qgis package): skipped")
        return SKIP
    try:
        import qgis.core  # noqa: F401  (python3-qgis: the plugin's Python side)
    except ImportError:
        print("python3-qgis is absent: skipped")
        return SKIP
    import geopandas as gpd
    import numpy as np
    import pandas as pd

    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    package = work / "pylib" / "geovor"
    package.mkdir(parents=True)
    for f in (source / "python" / "geovor").glob("*.py"):
        shutil.copy2(f, package)
    shutil.copy2(extension, package)
    (work / "runtime").mkdir(mode=0o700)
    env = dict(os.environ, HOME=str(work / "home"), XDG_RUNTIME_DIR=str(work / "runtime"),
               QGIS_PLUGINPATH=str(source / "qgis"), QT_QPA_PLATFORM="offscreen",
               GEOVOR_PYTHONPATH=str(work / "pylib"))
    env.pop("PYTHONPATH", None)

    # The layers: the stations as GeoPackage points (ogr2ogr), with a capacity column, and in
    # EPSG:4087 (WGS 84 / World Equidistant Cylindrical: the poles are points of it); queries:
    # random points, the stations' own positions and a feature without a geometry.
    stations_csv = source / "datasets" / "weather_stations.csv"
    stations = work / "stations.gpkg"
    run(["ogr2ogr", "-f", "GPKG", stations, stations_csv, "-oo", "X_POSSIBLE_NAMES=lon_deg",
         "-oo", "Y_POSSIBLE_NAMES=lat_deg", "-a_srs", "EPSG:4326", "-nln", "stations"])
    capacities = work / "stations_capacity.gpkg"
    run(["ogr2ogr", "-f", "GPKG", capacities, stations, "-dialect", "SQLite", "-nln", "stations",
         "-sql", "SELECT *, 1 + (fid % 5) AS capacity FROM stations"])
    projected = work / "stations_4087.gpkg"
    run(["ogr2ogr", "-f", "GPKG", projected, stations, "-t_srs", "EPSG:4087", "-nln", "stations"])
    sites = gpd.read_file(stations)
    rng = np.random.default_rng(35)
    n = 2000
    lat = np.degrees(np.arcsin(rng.uniform(-1, 1, n)))
    lon = rng.uniform(-180, 180, n)
    picked = rng.choice(len(sites), 50, replace=False)
    lat = np.concatenate([lat, sites.geometry.y.to_numpy()[picked]])
    lon = np.concatenate([lon, sites.geometry.x.to_numpy()[picked]])
    geometry = list(gpd.points_from_xy(lon, lat)) + [None]
    queries = work / "queries.gpkg"
    gpd.GeoDataFrame({"query_id": [f"q{i}" for i in range(len(geometry))],
                      "value": np.arange(len(geometry), dtype=np.int64) * 3},
                     geometry=geometry, crs="EPSG:4326").to_file(queries, layer="queries", driver="GPKG")

    # qgis_process: the plugin enabled in this profile, then each algorithm.
    done = run([QGIS_PROCESS, "plugins", "enable", "geovor"], env)
    listed = run([QGIS_PROCESS, "plugins"], env).stdout
    check(any(line.split() == ["*", "geovor"] for line in listed.splitlines()),
          f"qgis_process plugins does not list geovor as loaded:\n{listed}")
    algorithms = run([QGIS_PROCESS, "list"], env).stdout
    for name in ("cells", "delaunay", "nearest", "balance"):
        check(f"geovor:{name}" in algorithms, f"qgis_process list has no geovor:{name}")
    helped = run([QGIS_PROCESS, "help", "geovor:nearest"], env).stdout
    for parameter in ("INPUT", "SITES", "K", "MAX_DISTANCE_M", "SITE_FIELDS", "OUTPUT"):
        check(parameter in helped, f"geovor:nearest's help lists no {parameter}")

    def qgis(algorithm, **parameters):
        args = [QGIS_PROCESS, "run", f"geovor:{algorithm}", "--"]
        for key, value in parameters.items():
            for v in value if isinstance(value, list) else [value]:
                args.append(f"{key}={v}")
        return run(args, env)

    def cli(*args):
        return run([geovor, *args, "-q"])

    for old in work.glob("[qc]_clip.gpkg"):
        old.unlink()
    out = {name: work / f"{name}.gpkg" for name in (
        "q_cells", "c_cells", "q_triangles", "q_edges", "c_triangles", "c_edges", "q_nearest", "c_nearest",
        "q_balance", "c_balance", "q_cells_4087", "c_cells_4087")}
    qgis("cells", INPUT=stations, OUTPUT=out["q_cells"])
    cli("cells", stations, "-o", out["c_cells"])
    qgis("delaunay", INPUT=stations, OUTPUT=out["q_triangles"], EDGES=out["q_edges"])
    cli("delaunay", stations, "-o", out["c_triangles"], "--edges", out["c_edges"])
    qgis("nearest", INPUT=queries, SITES=stations, K=3, MAX_DISTANCE_M=800000, SITE_FIELDS=["name", "lat_deg"],
         OUTPUT=out["q_nearest"])
    cli("nearest", "--sites", stations, "--queries", queries, "--k", "3", "--max-distance-m", "800000",
        "--site-fields", "name,lat_deg", "-o", out["c_nearest"])
    qgis("balance", INPUT=capacities, CAPACITY="capacity", OUTPUT=out["q_balance"])
    cli("balance", capacities, "--capacity-field", "capacity", "-o", out["c_balance"])
    # CLIP: the stations cut by Natural Earth's countries (Debian's python3-geopandas).
    countries = work / "countries.gpkg"
    gpd.read_file(gpd.datasets.get_path("naturalearth_lowres")).to_file(countries, layer="countries", driver="GPKG")
    out["q_clip"], out["c_clip"] = work / "q_clip.gpkg", work / "c_clip.gpkg"
    qgis("cells", INPUT=stations, CLIP=countries, OUTPUT=out["q_clip"])
    cli("cells", stations, "--clip", countries, "-o", out["c_clip"])
    qgis("cells", INPUT=projected, OUTPUT=out["q_cells_4087"])
    cli("cells", projected, "-o", out["c_cells_4087"])

    def compare(what, ours, theirs, keys, close=(), geometry_tolerance=1e-9, relative=1e-9, exempt=()):
        """The features of `ours` (QGIS) and `theirs` (the command), in order; the rows `exempt`
        (by position) only in their geometry and `close` fields."""
        a, b = gpd.read_file(ours), gpd.read_file(theirs)
        print(f"{what}: {len(a)} features from QGIS, {len(b)} from the command")
        if not check(len(a) == len(b), f"{what}: {len(a)} features, the command {len(b)}"):
            return
        rows = np.setdiff1d(np.arange(len(a)), np.asarray(exempt, dtype=int) % max(len(a), 1))
        check(a.crs is not None and a.crs.to_epsg() == 4326, f"{what}: the output's CRS is {a.crs}, not EPSG:4326")
        missing = [c for c in b.columns if c not in a.columns]
        check(not missing, f"{what}: the command's fields {missing} are missing")
        for key in keys:
            x, y = a[key].astype(str).to_numpy()[rows], b[key].astype(str).to_numpy()[rows]
            bad = np.flatnonzero(x != y)
            check(len(bad) == 0, f"{what}: {len(bad)} features differ in {key}, first {bad[:1]}: "
                                 f"{x[bad[:1]]} != {y[bad[:1]]}")
        for column in close:
            x, y = (pd.to_numeric(f[column], errors="coerce").to_numpy(dtype=float) for f in (a, b))
            same_null = np.isnan(x) == np.isnan(y)
            check(same_null.all(), f"{what}: {column} is null in different features")
            ok = np.isnan(x) | (np.abs(x - y) <= relative * np.maximum(np.abs(y), 1e-300))
            check(ok.all(), f"{what}: {(~ok).sum()} features differ in {column} by more than {relative} relative")
        others = [c for c in b.columns if c not in keys and c not in close and c != "geometry" and c in a.columns]
        for column in others:
            x, y = a[column].iloc[rows], b[column].iloc[rows]
            if x.dtype.kind == "f" or y.dtype.kind == "f":
                equal = np.allclose(pd.to_numeric(x, errors="coerce").to_numpy(dtype=float),
                                    pd.to_numeric(y, errors="coerce").to_numpy(dtype=float), rtol=1e-12, atol=0, equal_nan=True)
            else:
                equal = (x.astype(str).str.replace(r"\.0$", "", regex=True).to_numpy()
                         == y.astype(str).str.replace(r"\.0$", "", regex=True).to_numpy()).all()
            check(equal, f"{what}: field {column} differs")
        # No geometry: QGIS's GeoPackage writer stores a feature without one as an empty point.
        def none(g):
            return g is None or g.is_empty

        geometry_ok = [none(ga) and none(gb) or not none(ga) and not none(gb) and ga.equals_exact(gb, geometry_tolerance)
                       for ga, gb in zip(a.geometry, b.geometry)]
        bad = [i for i, ok in enumerate(geometry_ok) if not ok]
        check(not bad, f"{what}: {len(bad)} geometries differ (tolerance {geometry_tolerance} degrees), first at {bad[:3]}")

    compare("cells", out["q_cells"], out["c_cells"], ["site_index", "site_id", "ids", "neighbors"],
            ["area_m2", "area_sr"])
    compare("cells clipped to countries", out["q_clip"], out["c_clip"], ["site_index", "site_id", "region_index", "region_id"],
            ["area_m2", "region_share"])
    compare("delaunay triangles", out["q_triangles"], out["c_triangles"],
            ["tri_index", "kind", "site_a", "site_b", "site_c", "id_a", "id_b", "id_c"],
            ["area_m2", "area_sr", "circumradius_m"])
    compare("delaunay edges", out["q_edges"], out["c_edges"], ["edge_index", "site_a", "site_b", "id_a", "id_b"],
            ["length_m", "geodesic_m"])
    # The query without a point: the command writes its feature number as query_id and no
    # attributes; the plugin keeps its id and attributes (a QGIS join keeps every input feature).
    compare("nearest", out["q_nearest"], out["c_nearest"], ["query_id", "rank", "site_index", "site_id", "name"],
            ["distance_m", "lat_deg"], exempt=[-1])
    last = gpd.read_file(out["q_nearest"]).iloc[-1]
    check(last.src_query_id == f"q{len(geometry) - 1}" and last.query_id == last.src_query_id
          and last.value == 3 * (len(geometry) - 1) and (last.geometry is None or last.geometry.is_empty)
          and np.isnan(last.site_index),
          f"nearest: the query without a point: {dict(last)}")
    compare("balance", out["q_balance"], out["c_balance"], ["site_index", "site_id", "neighbors"],
            ["area_m2", "area_sr", "target_m2"])
    # The radii: equal within 1e-9 of the largest (the smallest is 0).
    a, b = gpd.read_file(out["q_balance"]), gpd.read_file(out["c_balance"])
    if len(a) == len(b):
        check(np.max(np.abs(a.weight_m - b.weight_m)) <= 1e-9 * b.weight_m.max(), "balance: the radii differ")
    compare("cells of sites in EPSG:4087", out["q_cells_4087"], out["c_cells_4087"], ["site_index", "site_id"],
            ["area_m2"])
    nearest = gpd.read_file(out["q_nearest"])
    check(nearest.site_id.isna().sum() > 1 and (nearest.geometry.isna() | nearest.geometry.is_empty).sum() == 1,
          "nearest: expected queries without a site within 800 km and one without a point")

    # Without the package: a clear error, not a traceback (unless geovor is installed into
    # QGIS's own Python, where it is found).
    lost = dict(env, GEOVOR_PYTHONPATH=str(work / "nowhere"))
    done = run([QGIS_PROCESS, "run", "geovor:cells", "--", f"INPUT={stations}", f"OUTPUT={work / 'lost.gpkg'}"],
               lost, expect=None)
    if done.returncode == 0:
        print("note: the geovor package is installed in QGIS's Python path; the missing-package error is not checked")
    else:
        check("GEOVOR_PYTHONPATH" in done.stdout + done.stderr,
              f"without the package: no message naming GEOVOR_PYTHONPATH:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}")

    check_progress_and_cancel(source, work, stations, env)

    if failures:
        print(f"{len(failures)} checks failed")
        return 1
    print("all checks passed")
    return 0


def check_progress_and_cancel(source, work, stations, env):
    """In this process (PyQGIS, no qgis_process): geovor:cells reports progress from 0 to 100 through
    the feedback object, and stops when the feedback is canceled while it reads the layer (no
    output) or writes the cells (fewer than all written, no result)."""
    os.environ.update({k: env[k] for k in ("HOME", "XDG_RUNTIME_DIR", "QT_QPA_PLATFORM", "GEOVOR_PYTHONPATH")})
    from qgis.core import QgsApplication, QgsProcessingContext, QgsProcessingFeedback, QgsVectorLayer

    app = QgsApplication([], False)
    app.initQgis()
    sys.path.insert(0, str(source / "qgis"))
    import geovor  # the plugin

    plugin = geovor.classFactory(None)
    plugin.initProcessing()
    algorithm = QgsApplication.processingRegistry().createAlgorithmById("geovor:cells")
    if not check(algorithm is not None, f"in-process: no geovor:cells ({geovor.__file__}, providers "
                 f"{[p.id() for p in QgsApplication.processingRegistry().providers()]})"):
        return

    def run_until(cancel_at, output):
        feedback, context, seen = QgsProcessingFeedback(), QgsProcessingContext(), []

        def progressed(value):
            seen.append(value)
            if cancel_at is not None and value >= cancel_at:
                feedback.cancel()

        feedback.progressChanged.connect(progressed)
        results = algorithm.run({"INPUT": str(stations), "OUTPUT": str(output)}, context, feedback)
        if isinstance(results, tuple):  # (results, ok) where the bindings return both
            results = results[0]
        layer = QgsVectorLayer(str(output), "out", "ogr")
        count = layer.featureCount() if output.exists() and layer.isValid() else 0
        return results, seen, count

    results, seen, count = run_until(None, work / "progress.gpkg")
    check(count == 5631 and "OUTPUT" in results, f"in-process cells: {count} cells, results {results}")
    check(seen and seen == sorted(seen) and seen[-1] == 100 and len(seen) > 10,
          f"progress: not rising to 100 in steps: {seen[:5]} ... {seen[-5:]}")
    results, seen, count = run_until(5, work / "cancel_reading.gpkg")
    check(not results and count == 0 and max(seen) < 20, f"canceled while reading: results {results}, "
          f"{count} cells, progress up to {max(seen)}")
    results, seen, count = run_until(80, work / "cancel_writing.gpkg")
    check(not results and 0 < count < 5631 and max(seen) < 90, f"canceled while writing: results {results}, "
          f"{count} cells, progress up to {max(seen)}")
    print(f"cancel: {count} of 5631 cells written when canceled at 80%")
    app.exitQgis()


if __name__ == "__main__":
    sys.exit(main())
