#!/usr/bin/python3
"""Independent randomized oracle for weighted sites: `geovor cells --weight-field` (power cells).

Site i is a circle of radius r_i metres about its geocentric direction p_i = normalize(ECEF(lat,
lon, 0)); its power cell is where cos d(x, p_i) / cos(r_i / R) is largest (docs/weighted.md).
Generates degenerate-but-ordinary weighted site sets (random radii, equal radii, one huge circle
hiding small ones, nested circles and exact duplicates, radii near 0 and up to 9,000 km, grids
with two radii, one parallel, the poles, the antimeridian, clusters) plus a few rows with a bad
radius, runs geovor and checks its output against oracles that share no code with geovor:
GEOS validity (shapely), brute-force argmax of the power (numpy, long double), an LP for whether
a cell is empty (scipy's HiGHS: the hidden sites), WGS84 polygon areas (pyproj's GeographicLib),
byte identity with the unweighted cells for equal radii, row accounting, `geovor info`; and
`geovor index --weight-field` + `geovor nearest` against the same brute force and the cells.

Usage: /usr/bin/python3 weighted_oracle.py --geovor build/tools/geovor --seed 1 [--cases K] [--quick] [--tmp DIR]
Exit 0 when every check passes, 1 otherwise (each failure listed with its seed, case, recipe and
command); last line `weighted-oracle: N passed, M failed` (checks). See README.md beside this file.
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
import warnings

warnings.filterwarnings("ignore", message="STRtree will be changed")

try:
    import numpy as np
    from shapely.geometry import shape, Point
    from shapely.validation import explain_validity
    from shapely.prepared import prep
    from shapely.strtree import STRtree
    from pyproj import Geod
    from scipy.optimize import linprog
except ImportError as exc:  # pragma: no cover
    print(f"weighted-oracle: cannot run: {exc}; install python3-shapely python3-pyproj python3-numpy "
          f"python3-scipy and run with /usr/bin/python3", file=sys.stderr)
    print("weighted-oracle: 0 passed, 1 failed")
    sys.exit(1)

# ---------------------------------------------------------------- constants (WGS84; not from geovor)
WGS84_A = 6378137.0
WGS84_F = 1.0 / 298.257223563
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)
R_EARTH = 6371008.771415                    # the sphere the radii are measured on (docs/weighted.md)
R_LIMIT = math.pi * R_EARTH / 2.0            # radii must be < this
ELLIPSOID_AREA = 510065621724088.5          # m^2 (GeographicLib's WGS84 EllipsoidArea)
GEOD = Geod(ellps="WGS84")
TIMEOUT_S = 30
DEG = math.pi / 180.0
MERGE_CHORD = 2.0 ** -24                     # merge distance, in Earth radii (docs/user-guide.md)
THIN_DECIMALS = 7                            # thin cells are snap rounded to this grid at finer precisions


# ---------------------------------------------------------------- geometry (our own)
def directions(lat_deg, lon_deg, dtype=np.longdouble):
    """normalize(ECEF(lat, lon, 0)) of WGS84, as (n, 3) in `dtype`."""
    lat = np.asarray(lat_deg, dtype=dtype) * dtype(math.pi) / dtype(180)
    lon = np.asarray(lon_deg, dtype=dtype) * dtype(math.pi) / dtype(180)
    e2 = dtype(WGS84_E2)
    sl = np.sin(lat)
    n = dtype(WGS84_A) / np.sqrt(dtype(1) - e2 * sl * sl)
    v = np.stack([n * np.cos(lat) * np.cos(lon), n * np.cos(lat) * np.sin(lon), n * (dtype(1) - e2) * sl], axis=-1)
    return v / np.sqrt(np.sum(v * v, axis=-1))[..., None]


def lonlat_of(v):
    """Directions (n, 3) -> geodetic (lon, lat) degrees of the ellipsoid point they point at."""
    v = np.asarray(v, dtype=float)
    psi = np.arctan2(v[:, 2], np.hypot(v[:, 0], v[:, 1]))             # geocentric latitude
    lat = np.degrees(np.arctan2(np.sin(psi), (1.0 - WGS84_E2) * np.cos(psi)))
    lon = np.degrees(np.arctan2(v[:, 1], v[:, 0]))
    return lon, lat


def lifted(lat, lon, radius_m):
    """q_i = p_i / cos(r_i / R) in long double."""
    p = directions(lat, lon)
    c = np.cos(np.asarray(radius_m, dtype=np.longdouble) / np.longdouble(R_EARTH))
    return p / c[:, None], p, c


def ring_area_estimate(coords):
    """Rough area (m^2, CCW positive) of a lon/lat ring: -sum dlon * mean(sin lat), scaled to the ellipsoid.
    Only used to choose GeographicLib's representative modulo the ellipsoid's area."""
    c = np.asarray(coords, dtype=float)
    dl = np.radians(c[1:, 0] - c[:-1, 0])
    s = (np.sin(np.radians(c[1:, 1])) + np.sin(np.radians(c[:-1, 1]))) / 2.0
    return float(-(dl * s).sum()) * ELLIPSOID_AREA / (4.0 * math.pi)


def geod_ring_area(coords):
    c = coords[:-1] if len(coords) > 1 and tuple(coords[0]) == tuple(coords[-1]) else coords
    a, _ = GEOD.polygon_area_perimeter([p[0] for p in c], [p[1] for p in c])
    k = round((ring_area_estimate(coords) - a) / ELLIPSOID_AREA)
    return a + k * ELLIPSOID_AREA


def rings_of(gj):
    t = gj.get("type")
    polys = gj["coordinates"] if t == "MultiPolygon" else [gj["coordinates"]] if t == "Polygon" else []
    return [[(float(p[0]), float(p[1])) for p in ring] for poly in polys for ring in poly]


def is_empty_geom(gj):
    return gj is None or not gj.get("coordinates")


# ---------------------------------------------------------------- generators
def wrap(lon):
    lon = math.fmod(lon + 180.0, 360.0)
    if lon < 0:
        lon += 360.0
    return lon - 180.0


def rand_point(rng):
    v = rng.normal(size=3)
    v /= np.linalg.norm(v)
    return float(math.degrees(math.asin(max(-1.0, min(1.0, v[2]))))), float(math.degrees(math.atan2(v[1], v[0])))


def destination(lat, lon, dist_deg, bearing_deg):
    """Spherical destination (good enough to place sites)."""
    if abs(lat) == 90.0:
        return lat - math.copysign(dist_deg, lat), wrap(bearing_deg)
    p, l, d, b = (math.radians(x) for x in (lat, lon, dist_deg, bearing_deg))
    sp = math.sin(p) * math.cos(d) + math.cos(p) * math.sin(d) * math.cos(b)
    p2 = math.asin(max(-1.0, min(1.0, sp)))
    l2 = l + math.atan2(math.sin(b) * math.sin(d) * math.cos(p), math.cos(d) - math.sin(p) * sp)
    return math.degrees(p2), wrap(math.degrees(l2))


def km_deg(km):
    return km * 1000.0 / R_EARTH / DEG


def rand_radius(rng, hi_km=500.0, zero=0.25):
    if rng.random() < zero:
        return 0.0
    return float(rng.uniform(0.0, hi_km * 1000.0))


def size(rng, quick, lo, hi):
    return int(rng.integers(lo, max(lo + 1, (hi // 3) if quick else hi)))


def gen_random(rng, quick):
    n = size(rng, quick, 8, 160)
    return f"random n={n} radii 0..500 km", [(*rand_point(rng), rand_radius(rng)) for _ in range(n)]


def gen_equal(rng, quick):
    n = size(rng, quick, 4, 150)
    r = float(rng.choice([0.0, 0.05, 1.0, 1000.0, 300000.0, float(rng.uniform(0, 9e6))]))
    pts = [(*rand_point(rng), r) for _ in range(n)]
    if rng.random() < 0.5:   # a grid instead: co-circular sites, ties
        nl = int(rng.integers(2, 8 if quick else 12))
        nm = int(rng.integers(2, 8 if quick else 14))
        d = min(float(rng.choice([1.0, 5.0, 15.0])), 110.0 / nl)  # the grid within +-60 degrees of latitude
        la0, lo0 = float(rng.uniform(-60, 60 - nl * d)), float(rng.uniform(-180, 180))
        pts = [(la0 + i * d, wrap(lo0 + j * d), r) for i in range(nl) for j in range(nm)]
    if rng.random() < 0.5 and pts:
        pts.append(pts[int(rng.integers(0, len(pts)))])     # an exact duplicate
    return f"equal radii r={r!r} n={len(pts)}", pts


def gen_huge(rng, quick):
    clat, clon = rand_point(rng)
    big = float(rng.uniform(2000e3, 8000e3))
    n = size(rng, quick, 20, 150)
    pts = [(clat, clon, big)]
    reach = big / 1000.0 * float(rng.uniform(0.8, 1.5))
    for _ in range(n):
        d = km_deg(reach) * math.sqrt(rng.random())
        la, lo = destination(clat, clon, d, float(rng.uniform(0, 360)))
        pts.append((la, lo, rand_radius(rng, 50.0, 0.4)))
    far = int(rng.integers(3, 20))
    pts += [(*rand_point(rng), rand_radius(rng, 300.0)) for _ in range(far)]
    return f"huge circle r={big / 1e3:.0f} km at ({clat:.4g},{clon:.4g}) + {n} small + {far} far", pts


def gen_nested(rng, quick):
    k = int(rng.integers(1, 6))
    pts, desc = [], []
    for _ in range(k):
        clat, clon = rand_point(rng)
        m = int(rng.integers(2, 6))
        exact = rng.random() < 0.5
        for _ in range(m):
            r = float(rng.choice([0.0, float(rng.uniform(0, 3000e3)), float(rng.uniform(0, 300e3))]))
            if exact or not pts:
                pts.append((clat, clon, r))
            else:   # nearly the same centre: 1 m to 50 km away
                d = km_deg(10 ** float(rng.uniform(-3, math.log10(50))))
                la, lo = destination(clat, clon, d, float(rng.uniform(0, 360)))
                pts.append((la, lo, r))
        desc.append("same" if exact else "near")
    extra = int(rng.integers(0, 15 if quick else 40))
    pts += [(*rand_point(rng), rand_radius(rng)) for _ in range(extra)]
    rng.shuffle(pts)
    return f"nested k={k} ({','.join(desc)}) + {extra} random", pts


def gen_limits(rng, quick):
    n = size(rng, quick, 6, 80)
    choices = [0.0, 0.0, 1e-9, 0.05, 0.067, 0.068, 0.07, 1.0, 9000e3, 8999999.999, 8.5e6, 1e7,
               float(rng.uniform(0, 9000e3)), float(10 ** rng.uniform(-3, 6.95))]
    pts = [(*rand_point(rng), float(rng.choice(choices))) for _ in range(n)]
    return f"radii near limits n={n}", pts


def gen_grid(rng, quick):
    nl = int(rng.integers(2, 8 if quick else 14))
    nm = int(rng.integers(2, 10 if quick else 18))
    d = float(rng.choice([0.5, 2.0, 5.0, 10.0, 20.0]))
    nl = min(nl, int(170 / d) + 1)
    nm = min(nm, int(359 / d))
    la0 = float(rng.uniform(-85 + (nl - 1) * d, 85)) if (nl - 1) * d < 170 else 85.0
    lo0 = float(rng.uniform(-180, 180))
    r1, r2 = rand_radius(rng, 500.0, 0.3), rand_radius(rng, 500.0, 0.3)
    mode = rng.choice(["checker", "random", "rows"])
    pts = []
    for i in range(nl):
        for j in range(nm):
            r = r1 if (mode == "checker" and (i + j) % 2 == 0) or (mode == "rows" and i % 2 == 0) or \
                (mode == "random" and rng.random() < 0.5) else r2
            pts.append((la0 - i * d, wrap(lo0 + j * d), r))
    return f"grid {nl}x{nm} d={d} {mode} radii {r1:.0f}/{r2:.0f} m", pts


def gen_parallel(rng, quick):
    n = size(rng, quick, 3, 100)
    lat = float(rng.choice([0.0, 45.0, -60.0, 80.0, float(rng.uniform(-85, 85))]))
    even = rng.random() < 0.5
    lo0 = float(rng.uniform(-180, 180))
    two = rng.random() < 0.5
    r1, r2 = rand_radius(rng, 400.0), rand_radius(rng, 400.0)
    pts = []
    for i in range(n):
        lo = wrap(lo0 + 360.0 * i / n) if even else float(rng.uniform(-180, 180))
        pts.append((lat, lo, (r1 if i % 2 else r2) if two else rand_radius(rng, 400.0)))
    extra = int(rng.integers(0, 4))
    pts += [(*rand_point(rng), rand_radius(rng)) for _ in range(extra)]
    return f"parallel lat={lat} n={n} even={even} two_radii={two} +{extra}", pts


def gen_poles(rng, quick):
    pts = []
    for pole in (90.0, -90.0):
        if rng.random() < 0.8:
            for _ in range(int(rng.integers(1, 4))):   # the pole at any longitude: one position
                pts.append((pole, float(rng.uniform(-180, 180)), rand_radius(rng, 800.0)))
        for _ in range(int(rng.integers(0, 12))):
            la = pole - math.copysign(float(rng.choice([1e-7, 1e-4, 0.01, 0.5, float(rng.uniform(0, 10))])), pole)
            pts.append((la, float(rng.uniform(-180, 180)), rand_radius(rng, 500.0)))
    extra = int(rng.integers(2, 15 if quick else 50))
    pts += [(*rand_point(rng), rand_radius(rng)) for _ in range(extra)]
    rng.shuffle(pts)
    return f"poles n={len(pts)} (+{extra} random)", pts


def gen_antimeridian(rng, quick):
    n = size(rng, quick, 4, 60)
    pts = []
    for _ in range(n):
        lo = float(rng.choice([180.0, -180.0, 179.9999999, -179.9999999, 179.9, -179.5,
                               float(rng.uniform(170, 180)), float(rng.uniform(-180, -170))]))
        la = float(rng.uniform(-80, 80)) if rng.random() < 0.9 else float(rng.choice([89.9, -89.99]))
        pts.append((la, lo, rand_radius(rng, 600.0)))
    extra = int(rng.integers(0, 20))
    pts += [(*rand_point(rng), rand_radius(rng)) for _ in range(extra)]
    return f"antimeridian n={n} +{extra} random", pts


def gen_clusters(rng, quick):
    k = int(rng.integers(1, 6))
    pts = []
    for _ in range(k):
        clat, clon = rand_point(rng)
        m = int(rng.integers(3, 12 if quick else 30))
        spread = float(rng.choice([1.0, 10.0, 100.0]))
        for _ in range(m):
            la, lo = destination(clat, clon, km_deg(spread) * math.sqrt(rng.random()), float(rng.uniform(0, 360)))
            pts.append((la, lo, rand_radius(rng, spread * float(rng.choice([0.1, 0.5, 2.0])), 0.3)))
    extra = int(rng.integers(0, 20))
    pts += [(*rand_point(rng), rand_radius(rng)) for _ in range(extra)]
    return f"clusters k={k} n={len(pts)}", pts


RECIPES = [gen_random, gen_equal, gen_huge, gen_nested, gen_limits, gen_grid, gen_parallel,
           gen_poles, gen_antimeridian, gen_clusters]
BAD_RADII = ["", "abc", "-1", "1e8", "10007557.2", "nan", "-0.5", "1e400"]
WEIGHT_COLUMNS = ["r", "radius_m", "Buffer m", "R"]


def fmt(x):
    r = repr(float(x))
    return r[:-2] if r.endswith(".0") else r


# ---------------------------------------------------------------- a case
class Case:
    def __init__(self, seed, index, quick, tmp):
        self.seed, self.index, self.quick = seed, index, quick
        self.rng = np.random.default_rng([seed, index, 77])
        gen = RECIPES[index % len(RECIPES)]
        self.recipe, pts = gen(self.rng, quick)
        self.equal = gen is gen_equal
        self.col = str(self.rng.choice(WEIGHT_COLUMNS))
        self.dir = os.path.join(tmp, f"weighted_seed{seed}_case{index}")
        os.makedirs(self.dir, exist_ok=True)
        self.csv = os.path.join(self.dir, "sites.csv")
        self.rows = []          # (id, lat text, lon text, radius text, lat, lon, radius or None)
        for i, (la, lo, r) in enumerate(pts):
            self.rows.append((f"s{i}", fmt(la), fmt(lo), fmt(r), la, lo, r))
        self.bad = set()
        if not self.equal:
            for k in range(int(self.rng.integers(0, 5))):
                la, lo = rand_point(self.rng)
                rid = f"bad{k}"
                txt = str(self.rng.choice(BAD_RADII))
                pos = int(self.rng.integers(0, len(self.rows) + 1))
                self.rows.insert(pos, (rid, fmt(la), fmt(lo), txt, la, lo, None))
                self.bad.add(rid)
        with open(self.csv, "w") as f:
            col = f'"{self.col}"' if " " in self.col else self.col
            f.write(f"id,lat,lon,{col}\n")
            for rid, lat, lon, rt, *_ in self.rows:
                f.write(f"{rid},{lat},{lon},{rt}\n")
        self.failures, self.passed, self.notes, self.info = [], 0, [], []

    def label(self):
        return f"seed {self.seed} case {self.index} [{self.recipe}] ({len(self.rows)} rows, {self.csv})"

    def check(self, ok, cmd, what, detail=""):
        if ok:
            self.passed += 1
        else:
            self.failures.append((cmd, what, detail))
        return ok

    def run(self, geovor, args):
        cmd = [geovor] + args
        shown = " ".join(f"'{a}'" if " " in a else a for a in cmd)
        t0 = time.time()
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.check(False, shown, "geovor ran past the timeout", f"{TIMEOUT_S} s")
            return None, shown
        if not self.check(p.returncode == 0, shown, "geovor exit status",
                          f"exit {p.returncode} after {time.time() - t0:.2f} s; stderr: {p.stderr.strip()[-1500:]}"):
            return None, shown
        return p, shown


def read_geojson(path):
    with open(path) as f:
        fc = json.load(f)
    return [(ft.get("properties") or {}, ft.get("geometry")) for ft in fc["features"]]


def read_report(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


# ---------------------------------------------------------------- checks
def check_report(case, rep, cmd):
    """Row accounting. Returns (site rows by site_index: list of row indices, status by site index,
    holder by hidden site index) or None."""
    bad = []
    by_id = {r[0]: k for k, r in enumerate(case.rows)}
    if len(rep) != len(case.rows):
        bad.append(f"report has {len(rep)} rows for {len(case.rows)} input rows")
    counts = {}
    groups, status, holder = {}, {}, {}
    rejected_ids = set()
    for r in rep:
        st = r.get("status")
        counts[st] = counts.get(st, 0) + 1
        try:
            k = int(r["row"]) - 1
            rid = case.rows[k][0]
        except (KeyError, ValueError, IndexError):
            bad.append(f"report row {r}: bad row number")
            continue
        if st == "rejected":
            rejected_ids.add(rid)
            det = r.get("detail") or ""
            if not det.startswith(case.col + ":"):
                bad.append(f"row {k + 1} ({rid}, radius {case.rows[k][3]!r}) rejected, but the reason does not name the column {case.col!r}: {det!r}")
            continue
        try:
            si = int(r["site_index"])
        except (KeyError, TypeError, ValueError):
            bad.append(f"row {k + 1} ({rid}): site_index {r.get('site_index')!r}")
            continue
        groups.setdefault(si, []).append(k)
        if st in ("site", "hidden"):
            if si in status:
                bad.append(f"site {si} has two site/hidden rows")
            status[si] = (st, k)
            if st == "hidden":
                m = re.search(r"site (\d+) holds its position", r.get("detail") or "")
                holder[si] = int(m.group(1)) if m else None
                if not m:
                    bad.append(f"hidden row {k + 1} ({rid}): detail {r.get('detail')!r} names no holder")
        elif st != "merged":
            bad.append(f"row {k + 1} ({rid}): status {st!r}")
    if rejected_ids != case.bad:
        bad.append(f"rejected rows {sorted(rejected_ids)}, expected exactly the bad radii {sorted(case.bad)} "
                   f"({[(case.rows[by_id[i]][3]) for i in sorted(case.bad ^ rejected_ids)]})")
    if sum(counts.values()) != len(case.rows) or set(counts) - {"site", "merged", "hidden", "rejected"}:
        bad.append(f"status counts {counts} do not add up to {len(case.rows)} rows")
    n = len(status)
    if sorted(status) != list(range(n)) or sorted(groups) != list(range(n)):
        bad.append(f"site indices {sorted(status)[:10]}... not 0..{n - 1}")
    # merged rows: within the merge distance 2^-24 R of their site, per link of a chain (exact duplicates, the poles at
    # any longitude, points 1e-7 degree from a pole); the site row keeps the largest radius of its group
    for si, ks in groups.items():
        if si not in status:
            continue
        k0 = status[si][1]
        p0 = directions([case.rows[k0][4]], [case.rows[k0][5]], float)[0]
        same = []
        for k in ks:
            pk = directions([case.rows[k][4]], [case.rows[k][5]], float)[0]
            dk = float(np.linalg.norm(pk - p0))
            # a chain of merges (a site absorbed by a larger circle) may reach farther, each link
            # closer than the merge distance
            if dk > MERGE_CHORD * len(ks) * (1 + 1e-6) and k != k0:
                bad.append(f"row {k + 1} merged into site {si} (row {k0 + 1}) but {dk * R_EARTH:.3g} m away")
            if dk < 1e-12:
                same.append(k)
        # "Two rows at one position keep the one with the larger radius" (docs/user-guide.md):
        # rows at exactly the kept row's position (the same text, or a pole at any longitude)
        rmax = max(case.rows[k][6] for k in same)
        if case.rows[k0][6] != rmax:
            bad.append(f"site {si}: its row {k0 + 1} has radius {case.rows[k0][6]!r}, the largest at its exact position is {rmax!r}")
        rall = max(case.rows[k][6] for k in ks)
        if case.rows[k0][6] != rall:   # closer than the merge distance: the first inserted may be kept
            k1 = max(ks, key=lambda k: case.rows[k][6])
            case.notes.append(f"site {si}: row {k0 + 1} (r={case.rows[k0][6]!r}) kept, row {k1 + 1} (r={rall!r}) merged into it, "
                       f"{float(np.linalg.norm(directions([case.rows[k1][4]], [case.rows[k1][5]], float)[0] - p0)) * R_EARTH:.3g} m away")
    case.check(not bad, cmd, "report: row accounting (site + merged + hidden + rejected = rows, reasons, merges)",
               "; ".join(bad[:6]))
    if bad:
        return None
    # sites closer than the merge distance (docs/user-guide.md: "Sites closer than 2^-24 Earth radii
    # (0.38 m) are merged into one site"), hidden ones apart: its own check, the others go on
    close = []
    if status and len(status) <= 2000:
        U = directions([case.rows[status[i][1]][4] for i in range(n)], [case.rows[status[i][1]][5] for i in range(n)], float)
        G = np.linalg.norm(U[:, None, :] - U[None, :, :], axis=2)
        np.fill_diagonal(G, np.inf)
        i, j = np.unravel_index(np.argmin(G), G.shape)
        for i, j in zip(*np.nonzero(np.triu(G < MERGE_CHORD * (1 - 1e-6)))):
            # A hidden site (an empty cell) is merged only at one position (docs/weighted.md).
            if status[i][0] == "hidden" or status[j][0] == "hidden":
                continue
            ri, rj = case.rows[status[i][1]], case.rows[status[j][1]]
            close.append(f"sites {i} ({ri[0]},{ri[1]},{ri[2]},r={ri[3]}, {status[i][0]}) and {j} ({rj[0]},{rj[1]},{rj[2]},r={rj[3]}, "
                         f"{status[j][0]}) are {G[i, j] * R_EARTH:.4g} m apart (< merge distance {MERGE_CHORD * R_EARTH:.4g} m), not merged")
    case.check(not close, cmd, "sites closer than the merge distance are merged", "; ".join(close[:4]))
    return groups, status, holder, counts


def lp_cell(q, i):
    """Max t with x . (q_i - q_j) / |q_i - q_j| >= t for every j, x in [-1,1]^3 (HiGHS). Returns
    (t, x) and the certified margin: min_j of the sine of x's angular distance to the plane of i, j
    (long double), > 0 only when x is really inside C_i."""
    n = len(q)
    if n == 1:
        return 1.0, np.array(q[0], dtype=float), 1.0
    others = [j for j in range(n) if j != i]
    d = (q[i][None, :] - q[others]).astype(float)
    d /= np.linalg.norm(d, axis=1)[:, None]
    A = np.hstack([-d, np.ones((len(others), 1))])
    res = linprog(c=[0, 0, 0, -1], A_ub=A, b_ub=np.zeros(len(others)),
                  bounds=[(-1, 1), (-1, 1), (-1, 1), (-2, 2)], method="highs")
    if res.status != 0:
        return None, None, None
    x = np.array(res.x[:3])
    nx = np.linalg.norm(x)
    if nx == 0:
        return float(res.x[3]), x, -1.0
    xl = (x / nx).astype(np.longdouble)
    diff = q[i][None, :] - q[others]
    marg = (diff @ xl) / np.sqrt(np.sum(diff * diff, axis=1))
    return float(res.x[3]), x / nx, float(marg.min())


def check_cells(case, feats, cmd, prec, densify_m, sites, stderr, hidden_set, holder):
    """sites: dict with lat, lon, r arrays (by site index), q (lifted, long double)."""
    n = len(sites["lat"])
    tag = f"p={prec}"
    q = sites["q"]
    p = sites["p"]
    c = sites["c"]
    case.check(len(feats) == n, cmd, f"one feature per site, hidden ones included ({tag})", f"{len(feats)} features for {n} sites")
    cells, props, bad_geom, empty = {}, {}, [], set()
    for pr, gj in feats:
        try:
            si = int(pr.get("site_index"))
        except (TypeError, ValueError):
            bad_geom.append(f"site_index {pr.get('site_index')!r}")
            continue
        props[si] = pr
        if is_empty_geom(gj):
            empty.add(si)
            continue
        if gj.get("type") != "MultiPolygon":
            bad_geom.append(f"site {si}: geometry type {gj.get('type')}")
        g = shape(gj)
        if g.is_empty:
            empty.add(si)
            continue
        if not g.is_valid:
            bad_geom.append(f"site {si} ({pr.get('site_id')}): invalid: {explain_validity(g)}")
        minx, miny, maxx, maxy = g.bounds
        if minx < -180 or maxx > 180 or miny < -90 or maxy > 90:
            bad_geom.append(f"site {si}: bounds {g.bounds} outside [-180,180]x[-90,90]")
        cells[si] = (g, gj)
    case.check(not bad_geom, cmd, f"cells are GEOS-valid MultiPolygons in [-180,180]x[-90,90] ({tag})",
               f"{len(bad_geom)} bad: " + "; ".join(bad_geom[:5]))
    # empty geometries: exactly the hidden sites, plus cells reported collapsed at this precision
    collapsed = {si for si in empty - hidden_set
                 if re.search(r"collaps|unwritable", stderr, re.I) and str(props[si].get("site_id")) in stderr}
    unexplained = sorted(empty - hidden_set - collapsed)
    case.check(not unexplained, cmd, f"empty geometries only for hidden (or reported collapsed) sites ({tag})",
               "; ".join(f"site {si} ({props[si].get('site_id')}, weight_m {props[si].get('weight_m')}) empty, not hidden"
                         for si in unexplained[:5]))
    nonempty_hidden = sorted(hidden_set - empty)
    case.check(not nonempty_hidden, cmd, f"hidden sites have an empty geometry ({tag})",
               "; ".join(f"site {si} ({props[si].get('site_id')})" for si in nonempty_hidden[:5]))
    if collapsed:
        case.notes.append(f"{cmd}: {len(collapsed)} cells reported collapsed")
    # weight_m = the site's radius; hidden: area 0
    wbad = []
    for si, pr in props.items():
        try:
            w = float(pr.get("weight_m"))
        except (TypeError, ValueError):
            wbad.append(f"site {si}: weight_m {pr.get('weight_m')!r}")
            continue
        if abs(w - sites["r"][si]) > 1e-12 * sites["r"][si] + 1e-9:
            wbad.append(f"site {si} ({pr.get('site_id')}): weight_m {w!r}, radius {sites['r'][si]!r}")
        if si in hidden_set and (float(pr.get("area_m2") or 0) != 0 or float(pr.get("area_sr") or 0) != 0):
            wbad.append(f"hidden site {si}: area_m2 {pr.get('area_m2')}, area_sr {pr.get('area_sr')}")
    case.check(not wbad, cmd, f"weight_m is the site's radius; hidden sites have area 0 ({tag})", "; ".join(wbad[:5]))

    # ---- areas: area_m2 = GeographicLib of the written rings; sums
    afail, sum_m2, sum_written, sum_sr = [], 0.0, 0.0, 0.0
    for si, pr in props.items():
        try:
            got = float(pr.get("area_m2"))
            sum_sr += float(pr.get("area_sr"))
        except (TypeError, ValueError):
            afail.append(f"site {si}: area_m2 {pr.get('area_m2')!r} area_sr {pr.get('area_sr')!r}")
            continue
        sum_m2 += got
        if si not in cells:
            continue
        rings = rings_of(cells[si][1])
        a = sum(geod_ring_area(r) for r in rings)     # holes are clockwise: negative
        sum_written += a
        if abs(got - a) > max(1e-9 * abs(a), 0.25):
            afail.append(f"site {si} ({pr.get('site_id')}): area_m2 {got!r} vs GeographicLib {a!r} (rel {abs(got - a) / max(abs(a), 1e-300):.3g})")
    case.check(not afail, cmd, f"area_m2 = GeographicLib area of the written polygon ({tag})", "; ".join(afail[:5]))
    case.check(abs(sum_sr - 4 * math.pi) <= 1e-9 * 4 * math.pi, cmd, f"sum of area_sr = 4 pi ({tag})", f"sum {sum_sr!r}")
    if not collapsed:
        case.check(abs(sum_m2 - ELLIPSOID_AREA) <= 1e-9 * ELLIPSOID_AREA, cmd, f"sum of area_m2 = ellipsoid area ({tag})",
                   f"sum {sum_m2!r} vs {ELLIPSOID_AREA!r} (rel {abs(sum_m2 - ELLIPSOID_AREA) / ELLIPSOID_AREA:.3g})")
        case.check(abs(sum_written - ELLIPSOID_AREA) <= 1e-9 * ELLIPSOID_AREA, cmd,
                   f"GeographicLib areas of the written polygons sum to the ellipsoid area ({tag})",
                   f"sum {sum_written!r} (rel {abs(sum_written - ELLIPSOID_AREA) / ELLIPSOID_AREA:.3g})")

    # ---- brute force: random points in the cell of their largest power
    rng = np.random.default_rng([case.seed, case.index, prec])
    m_uniform = 1000 if case.quick else 3000
    V = rng.normal(size=(m_uniform, 3))
    # and points near sites, where the small cells are
    k_near = min(n, 150) * 4
    idx = rng.integers(0, n, size=k_near)
    scale = np.where(rng.random(k_near) < 0.5, 0.002, 0.03)
    Vn = p[idx].astype(float) + rng.normal(size=(k_near, 3)) * scale[:, None]
    V = np.vstack([V, Vn])
    V /= np.linalg.norm(V, axis=1)[:, None]
    Vl = V.astype(np.longdouble)
    P = Vl @ q.T                                              # powers x . q_j
    best = np.argmax(P, axis=1)
    pb = P[np.arange(len(V)), best]
    # distance (sine of the angle) from x to the plane x . (q_best - q_j) = 0, min over j: C_best is
    # the intersection of these hemispheres, so this bounds x's distance to its cell's boundary
    qq = q @ q.T
    nrm2 = np.diag(qq)[:, None] + np.diag(qq)[None, :] - 2 * qq
    D = np.sqrt(np.maximum(nrm2[best], 0))
    with np.errstate(divide="ignore", invalid="ignore"):
        dist = (pb[:, None] - P) / D
    dist[np.arange(len(V)), best] = np.inf
    dmin = np.min(dist, axis=1).astype(float) if n > 1 else np.full(len(V), np.inf)
    rerr_deg = 0.5 * 10.0 ** (-prec) if prec < 17 else 3e-14
    moved_deg = 0.5 * math.sqrt(2) * 10.0 ** (-min(prec, THIN_DECIMALS))
    tol_m = 2.0 * (densify_m + (rerr_deg * math.sqrt(2) + moved_deg) * DEG * R_EARTH) + 1e-3
    far = dmin * R_EARTH > tol_m
    lon, lat = lonlat_of(V)
    won = np.zeros(n, dtype=int)
    miss, overlap = [], []
    geoms = [(si, g) for si, (g, _) in cells.items()]
    tree = STRtree([g for _, g in geoms]) if geoms else None
    owner = {id(g): si for si, g in geoms}
    preps = {si: prep(g) for si, g in geoms}
    for s in np.nonzero(far)[0]:
        b = int(best[s])
        won[b] += 1
        pt = Point(float(lon[s]), float(lat[s]))
        if b not in preps:
            miss.append(f"point ({lon[s]!r},{lat[s]!r}) {dmin[s] * R_EARTH:.4g} m inside the power cell of site {b} "
                        f"({props.get(b, {}).get('site_id')}, r={sites['r'][b]!r}), which is written empty")
            continue
        if not preps[b].contains(pt):
            holders = [owner[id(g)] for g in tree.query(pt) if g.contains(pt)]
            miss.append(f"point ({lon[s]!r},{lat[s]!r}) {dmin[s] * R_EARTH:.4g} m inside the power cell of site {b} "
                        f"({props[b].get('site_id')}) is not in its polygon (in {holders})")
            continue
        others = [owner[id(g)] for g in tree.query(pt) if owner[id(g)] != b and g.contains(pt)]
        if others:
            overlap.append(f"point ({lon[s]!r},{lat[s]!r}) of site {b} also in cells {others}")
    case.info.append(f"{tag}: {n} sites, {len(hidden_set)} hidden, {len(empty)} empty, {int(far.sum())}/{len(V)} samples checked")
    case.check(not miss, cmd, f"brute force: points lie in the polygon of their largest-power site ({tag})",
               f"{len(miss)} of {int(far.sum())}: " + "; ".join(miss[:4]))
    case.check(not overlap, cmd, f"brute force: no point in two cells ({tag})", f"{len(overlap)}: " + "; ".join(overlap[:4]))

    # ---- hidden sites: their position is held by another site with a strictly larger power, and the
    # LP finds no interior point; sites with a cell but no sample: the LP finds one, inside their polygon
    hbad = []
    for si in sorted(hidden_set):
        own = 1.0 / c[si]
        pw = p[si] @ q.T
        pw[si] = -np.inf
        j = int(np.argmax(pw))
        if not pw[j] >= own * (1 - np.longdouble(1e-15)):
            hbad.append(f"hidden site {si} ({props[si].get('site_id')}, r={sites['r'][si]!r}): no site holds its position "
                        f"(largest other power there {float(pw[j])!r} < its own {float(own)!r})")
        h = holder.get(si)
        if h is not None and not (pw[h] >= pw[j] * (1 - np.longdouble(1e-15))):
            hbad.append(f"hidden site {si}: report says site {h} holds its position, but site {j} has the larger power there")
        if won[si]:
            hbad.append(f"hidden site {si} ({props[si].get('site_id')}) has the largest power at {won[si]} sample points away from any boundary")
    for si in range(n):
        if si not in hidden_set and won[si] and si not in empty:
            continue     # a sample well inside its polygon already shows the cell is there
        t, x, marg = lp_cell(q, si)
        if t is None:
            case.notes.append(f"{cmd}: LP failed for site {si}")
            continue
        if si in collapsed and marg * R_EARTH > 1.0:
            xl, xa = lonlat_of(x[None])
            hbad.append(f"site {si} ({props[si].get('site_id')}) reported collapsed at --precision {prec}, but a cap of "
                        f"{marg * R_EARTH:.4g} m about ({float(xl[0])!r},{float(xa[0])!r}) lies inside its power cell")
        if si in hidden_set:
            if marg > 1e-10:
                xl, xa = lonlat_of(x[None])
                hbad.append(f"hidden site {si} ({props[si].get('site_id')}, r={sites['r'][si]!r}) has a non-empty power cell: "
                            f"({float(xl[0])!r},{float(xa[0])!r}) is {marg * R_EARTH:.4g} m inside it")
        else:
            if t < -1e-7:
                hbad.append(f"site {si} ({props[si].get('site_id')}, r={sites['r'][si]!r}) is not hidden, written "
                            f"{'empty' if si in empty else 'non-empty'}, but its power cell is empty (LP margin {t:.3g})")
            elif marg * R_EARTH > tol_m and si in preps:
                xl, xa = lonlat_of(x[None])
                if not preps[si].contains(Point(float(xl[0]), float(xa[0]))):
                    hbad.append(f"site {si} ({props[si].get('site_id')}): ({float(xl[0])!r},{float(xa[0])!r}), "
                                f"{marg * R_EARTH:.4g} m inside its power cell, is not in its polygon")
    case.check(not hbad, cmd, f"hidden sites: position held by another site, power cell empty (LP); the others non-empty ({tag})",
               "; ".join(hbad[:5]))
    return won


def read_csv_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def check_nearest(case, geovor, sites, hidden, counts, cells_path):
    """`geovor index --weight-field` + `geovor nearest`: the site of largest power (brute force,
    long double, hidden sites excluded from the ranking), the polygon of `geovor cells` holding the
    query, --k by decreasing power, distance_m the great-circle distance, the same answers from the
    table as from the index, and the sphere metric refused on weighted sites."""
    d = case.dir
    n = len(sites["lat"])
    idx = os.path.join(d, "sites.gvi")
    p, cmd = case.run(geovor, ["index", case.csv, "--weight-field", case.col, "-o", idx, "--overwrite"])
    if p is None:
        return
    m = re.search(r"^hidden: (\d+)$", p.stdout, re.M)
    case.check(m is not None and int(m.group(1)) == counts.get("hidden", 0), cmd, "index --weight-field prints hidden: N (= the report's)",
               f"{m.group(0) if m else 'no hidden line'} vs {counts.get('hidden', 0)}")
    rng = np.random.default_rng([case.seed, case.index, 4242])
    m_uniform = 400 if case.quick else 1500
    V = rng.normal(size=(m_uniform, 3))
    k_near = min(n, 100) * 3
    near = rng.integers(0, n, size=k_near)
    scale = np.where(rng.random(k_near) < 0.5, 0.002, 0.03)
    V = np.vstack([V, sites["p"][near].astype(float) + rng.normal(size=(k_near, 3)) * scale[:, None]])
    V /= np.linalg.norm(V, axis=1)[:, None]
    qlon, qlat = lonlat_of(V)
    qcsv = os.path.join(d, "queries.csv")
    with open(qcsv, "w") as f:
        f.write("id,lat,lon\n")
        for i in range(len(V)):
            f.write(f"q{i},{fmt(qlat[i])},{fmt(qlon[i])}\n")
    X = directions(qlat, qlon)          # the queries as written, in long double
    P = X @ sites["q"].T
    visible = np.array([i not in hidden for i in range(n)])
    Pv = np.where(visible[None, :], P, -np.inf)
    order = np.argsort(-Pv, axis=1, kind="stable")[:, :4]
    top = np.take_along_axis(Pv, order, axis=1)
    out = os.path.join(d, "nearest.csv")
    p, cmd = case.run(geovor, ["nearest", "--sites", idx, "--queries", qcsv, "-o", out, "--overwrite"])
    if p is None:
        return
    rows = read_csv_rows(out)
    case.check(len(rows) == len(V), cmd, "nearest: one row per query", f"{len(rows)} rows for {len(V)} queries")
    bad, dist_bad, cell_bad, checked = [], [], [], 0
    cells = {}
    for pr, gj in read_geojson(cells_path):
        if not is_empty_geom(gj):
            cells[int(pr["site_index"])] = prep(shape(gj))
    gap_rel = 1e-9
    for i, r in enumerate(rows[:len(V)]):
        want = int(order[i, 0])
        sep = (top[i, 0] - top[i, 1]) / abs(top[i, 0]) if n > 1 else np.inf
        if not sep > gap_rel:
            continue   # a near tie: either answer is right up to the oracle's precision
        checked += 1
        got = int(r["site_index"]) if r["site_index"] else -1
        if got != want:
            bad.append(f"query {r['query_id']} ({qlat[i]!r},{qlon[i]!r}): site {got}, largest power site {want} (gap {float(sep):.3g})")
            continue
        dd = float(np.arctan2(np.linalg.norm(np.cross(X[i].astype(float), sites["p"][want].astype(float))),
                              float(X[i] @ sites["p"][want]))) * R_EARTH
        if abs(float(r["distance_m"]) - dd) > 1e-6 + 1e-9 * dd:
            dist_bad.append(f"query {r['query_id']}: distance_m {r['distance_m']} vs {dd!r}")
        if sep > 1e-6 and want in cells and not cells[want].contains(Point(float(qlon[i]), float(qlat[i]))):
            cell_bad.append(f"query {r['query_id']} ({qlat[i]!r},{qlon[i]!r}) answered site {want}, not in its cell polygon")
    case.check(not bad, cmd, "nearest on a weighted index = the site of largest power (brute force)",
               f"{len(bad)} of {checked}: " + "; ".join(bad[:4]))
    case.check(not dist_bad, cmd, "nearest: distance_m is the great-circle distance to the site", "; ".join(dist_bad[:4]))
    case.check(not cell_bad, cmd, "cells and nearest agree: the answer's polygon holds the query", "; ".join(cell_bad[:4]))
    # --k 3: the three largest powers, in order
    outk = os.path.join(d, "nearest_k3.csv")
    p, cmd = case.run(geovor, ["nearest", "--sites", idx, "--queries", qcsv, "-o", outk, "--overwrite", "--k", "3"])
    if p is not None:
        got = {}
        for r in read_csv_rows(outk):
            got.setdefault(r["query_id"], []).append(int(r["site_index"]))
        kbad = []
        for i in range(len(V)):
            kk = min(3, int(visible.sum()))
            if kk < 1 or any(not (top[i, j] - top[i, j + 1]) / abs(top[i, 0]) > gap_rel for j in range(min(kk, 3))
                             if j + 1 < top.shape[1] and np.isfinite(top[i, j + 1])):
                continue
            want = [int(x) for x in order[i, :kk]]
            if got.get(f"q{i}") != want:
                kbad.append(f"q{i}: {got.get(f'q{i}')} vs {want}")
        case.check(not kbad, cmd, "nearest --k 3 on a weighted index: the three largest powers, in order",
                   f"{len(kbad)}: " + "; ".join(kbad[:4]))
    # the table gives what the index gives; the sphere metric is refused
    outt = os.path.join(d, "nearest_table.csv")
    p, cmd = case.run(geovor, ["nearest", "--sites", case.csv, "--weight-field", case.col, "--queries", qcsv, "-o", outt,
                               "--overwrite", "-q"])
    if p is not None:
        with open(out, "rb") as f1, open(outt, "rb") as f2:
            case.check(f1.read() == f2.read(), cmd, "nearest --weight-field on the table = on its index (cmp)")
    if len(set(np.cos(sites["r"].astype(float) / R_EARTH).tolist())) < 2:
        return   # equal radii are no weights: the ordinary index, whose metrics all apply
    cmd = [geovor, "nearest", "--sites", idx, "--queries", qcsv, "--metric", "sphere", "-o", os.path.join(d, "sphere.csv")]
    pr = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT_S)
    case.check(pr.returncode == 2 and "power" in pr.stderr and not os.path.exists(os.path.join(d, "sphere.csv")),
               " ".join(cmd), "nearest --metric sphere on weighted sites: exit 2 naming the power metric, no output",
               f"exit {pr.returncode}: {pr.stderr.strip()[:200]}")


def run_case_body(case, geovor):
    d = case.dir
    densify = 100.0
    results = {}
    for prec in (17, 7):
        out = os.path.join(d, f"cells_p{prec}.geojson")
        rep = os.path.join(d, f"report_p{prec}.csv")
        p, cmd = case.run(geovor, ["cells", case.csv, "-o", out, "--weight-field", case.col, "--precision", str(prec),
                                   "--report", rep, "--overwrite", "--densify-m", repr(densify)])
        if p is None:
            return
        results[prec] = (out, rep, cmd, p.stderr)
    out17, rep17, cmd17, err17 = results[17]
    if case.index == 0:   # the documented bound, once per run: --help and the rejection message say pi R / 2
        p, cmd = case.run(geovor, ["cells", "--help"])
        if p is not None:
            m = re.search(r"--weight-field.*?0 <= r < ([0-9,.]+)", p.stdout, re.S)
            got = float(m.group(1).replace(",", "")) if m else None
            case.check(got is not None and abs(got - R_LIMIT) < 1.0, cmd, "--help gives the radius bound pi R / 2 = 10,007,557 m",
                       f"says {m.group(0)[-40:] if m else 'no bound'!r}")
    acc = check_report(case, read_report(rep17), cmd17)
    if acc is None:
        return
    groups, status, holder, counts = acc
    with open(rep17, "rb") as f1, open(results[7][1], "rb") as f2:
        r17, r7 = f1.read().decode(), f2.read().decode()
    # the reports differ only in cells collapsed at precision 7
    r7_lines = [ln for ln in r7.splitlines() if "collapsed" not in ln and "unwritable" not in ln]
    r17_lines = [ln for ln in r17.splitlines() if "collapsed" not in ln and "unwritable" not in ln]
    case.check(r7_lines == r17_lines, results[7][2], "--report the same at precision 7 and 17 (but collapsed cells)",
               f"{[x for x in r7_lines if x not in r17_lines][:3]} vs {[x for x in r17_lines if x not in r7_lines][:3]}")
    n = len(status)
    hidden = {si for si, (st, _) in status.items() if st == "hidden"}
    lat = np.array([case.rows[status[i][1]][4] for i in range(n)])
    lon = np.array([case.rows[status[i][1]][5] for i in range(n)])
    rad = np.array([case.rows[status[i][1]][6] for i in range(n)])
    q, pdir, c = lifted(lat, lon, rad)
    sites = dict(lat=lat, lon=lon, r=rad, q=q, p=pdir, c=c)
    # stderr lists every hidden row
    miss = [case.rows[status[si][1]][0] for si in hidden
            if not re.search(rf"id '{re.escape(case.rows[status[si][1]][0])}'.*is hidden", err17)]
    case.check(not miss, cmd17, "stderr lists every hidden site", f"not listed: {miss[:5]}")
    for prec in (17, 7):
        out, rep, cmd, err = results[prec]
        check_cells(case, read_geojson(out), cmd, prec, densify, sites, err, hidden, holder)
    check_nearest(case, geovor, sites, hidden, counts, out17)
    # geovor info
    p, cmd = case.run(geovor, ["info", case.csv, "--weight-field", case.col])
    if p is not None:
        kv = {}
        for ln in p.stdout.splitlines():
            if ":" in ln:
                k, v = ln.split(":", 1)
                kv[k.strip()] = v.strip()
        want = {"rows": str(len(case.rows)), "sites": str(counts.get("site", 0)), "merged": str(counts.get("merged", 0)),
                "hidden": str(counts.get("hidden", 0)), "rejected": str(counts.get("rejected", 0)), "valid": "yes"}
        diff = {k: (kv.get(k), v) for k, v in want.items() if kv.get(k) != v}
        case.check(not diff, cmd, "info --weight-field: rows, sites, merged, hidden (= the report's), rejected, valid: yes",
                   f"(got, expected): {diff}")
    # equal radii: the ordinary Voronoi cells, byte for byte (but the weight_m property)
    if case.equal:
        case.check(not hidden, cmd17, "equal radii: no hidden site", f"{sorted(hidden)[:5]}")
        for prec in (17, 7):
            out = os.path.join(d, f"unweighted_p{prec}.geojson")
            p, cmd = case.run(geovor, ["cells", case.csv, "-o", out, "--precision", str(prec), "--overwrite",
                                       "--densify-m", repr(densify), "-q"])
            if p is None:
                continue
            with open(results[prec][0], "rb") as f:
                w = f.read()
            with open(out, "rb") as f:
                u = f.read()
            stripped = re.sub(rb'"weight_m":[^,}]*,', b"", w)
            nw = len(re.findall(rb'"weight_m":', w))
            same = stripped == u
            where = ""
            if not same:
                k = next((i for i in range(min(len(stripped), len(u))) if stripped[i] != u[i]), min(len(stripped), len(u)))
                where = f"first difference at byte {k}: {stripped[max(0, k - 80):k + 80]!r} vs {u[max(0, k - 80):k + 80]!r}"
            case.check(same and nw == n, f"{results[prec][2]} ; {cmd}",
                       f"equal radii: cells byte-identical to the unweighted run but weight_m (cmp, p={prec})",
                       where or f"{nw} weight_m for {n} sites")


def run_case(args_tuple):
    seed, index, geovor, quick, tmp = args_tuple
    t0 = time.time()
    case = Case(seed, index, quick, tmp)
    try:
        run_case_body(case, geovor)
    except Exception:  # noqa: BLE001  a checker crash is a failure too
        case.failures.append(("(checker)", "oracle crashed", traceback.format_exc()[-2000:]))
    if not case.failures:
        shutil.rmtree(case.dir, ignore_errors=True)
    return dict(label=case.label(), failures=case.failures, passed=case.passed, notes=case.notes, info=case.info,
                seconds=time.time() - t0, index=index)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--geovor", required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cases", type=int, default=None, help="cases (default 20, --quick 10)")
    ap.add_argument("--first", type=int, default=0, help="index of the first case (to rerun one)")
    ap.add_argument("--quick", action="store_true", help="smaller site sets, fewer samples")
    ap.add_argument("--tmp", default=None, help="work folder (failing cases are kept there)")
    ap.add_argument("-v", "--verbose", action="store_true", help="one line per case")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args()
    geovor = os.path.abspath(args.geovor)
    if not os.access(geovor, os.X_OK):
        print(f"weighted-oracle: {geovor} is not an executable", file=sys.stderr)
        print("weighted-oracle: 0 passed, 1 failed")
        return 1
    cases = args.cases if args.cases is not None else (10 if args.quick else 20)
    tmp = args.tmp or tempfile.mkdtemp(prefix="geovor-weighted-")
    os.makedirs(tmp, exist_ok=True)
    work = [(args.seed, i, geovor, args.quick, tmp) for i in range(args.first, args.first + cases)]
    t0 = time.time()
    if args.jobs > 1 and len(work) > 1:
        import multiprocessing
        with multiprocessing.Pool(args.jobs) as pool:
            results = pool.map(run_case, work, chunksize=1)
    else:
        results = [run_case(w) for w in work]
    passed = sum(r["passed"] for r in results)
    failed = 0
    for r in sorted(results, key=lambda r: r["index"]):
        for cmd, what, detail in r["failures"]:
            failed += 1
            print(f"FAIL {r['label']}\n  command: {cmd}\n  check:   {what}\n  detail:  {detail}\n")
        if args.verbose:
            print(f"case {r['label']}: {r['seconds']:.1f} s, {r['passed']} passed; " + "; ".join(r["info"]))
        for note in r["notes"]:
            print(f"note {r['label']}: {note}")
    slow = max(results, key=lambda r: r["seconds"]) if results else None
    if slow:
        print(f"weighted-oracle: {len(results)} cases in {time.time() - t0:.1f} s (slowest {slow['seconds']:.1f} s: {slow['label']})")
    if failed == 0 and args.tmp is None:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"weighted-oracle: {passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
