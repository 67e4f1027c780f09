#!/usr/bin/python3
"""Thiessen pieces (issue 35): the stations' cells clipped to Natural Earth's countries, geovor
against the same job in GeoPandas, in one run on the same data.

geovor: geovor.cells(stations, clip=countries), end to end (triangulation, cells, clip, areas).
GeoPandas: the cells from geovor.cells(stations), untimed, then the timed part:
geopandas.overlay(cells, countries, how="intersection") (Debian's GeoPandas 0.12 with rtree) and
the areas with pyproj.Geod.geometry_area_perimeter. Prints both times (best of REPEAT, the two
jobs' runs alternating), the ratio, the pieces, and the invalid pieces of each (GEOS is_valid), how
far the shares of each country are from summing to 1, and the load average before and after.
Usage: python3 bench/python/clip_vs_geopandas.py [REPEAT=3]"""
import os
import sys
import time
import warnings
from pathlib import Path

import geopandas as gpd
import numpy as np
import pandas as pd
from pyproj import Geod

import geovor

ROOT = Path(__file__).resolve().parents[2]
repeat = int(sys.argv[1]) if len(sys.argv) > 1 else 3
warnings.filterwarnings("ignore")
stations = pd.read_csv(ROOT / "datasets" / "weather_stations.csv")
countries = gpd.read_file(gpd.datasets.get_path("naturalearth_lowres"))


cells = geovor.cells(stations)[["site_index", "site_id", "geometry"]]
geod = Geod(ellps="WGS84")


def geovor_job():
    return geovor.cells(stations, clip=countries)


def geopandas_job():
    out = gpd.overlay(cells, countries, how="intersection", keep_geom_type=True)
    out["area_m2"] = [abs(geod.geometry_area_perimeter(g)[0]) for g in out.geometry]
    return out


def best_of_both(jobs):
    """Each job's best time and last result; the jobs' runs alternate, so that a burst of load
    from other processes (a build) falls on both, not on all the runs of one."""
    times, results = [[] for _ in jobs], [None] * len(jobs)
    for _ in range(repeat):
        for i, job in enumerate(jobs):
            t = time.perf_counter()
            results[i] = job()
            times[i].append(time.perf_counter() - t)
    return [min(t) for t in times], results


load_before = os.getloadavg()
(g_s, p_s), (pieces, theirs) = best_of_both([geovor_job, geopandas_job])
g_sums = pieces.groupby("region_index").region_share.sum()
their_area = theirs.groupby("name").area_m2.sum()
their_share_sum = theirs.assign(share=theirs.area_m2 / theirs.name.map(their_area)).groupby("name").share.sum()
print(f"stations {len(stations)}, countries {len(countries)}, {repeat} runs each, best time")
print(f"| job | seconds | pieces | invalid pieces | max abs(sum of shares - 1) |")
print(f"|---|---:|---:|---:|---:|")
print(f"| geovor.cells(clip=countries), end to end | {g_s:.3f} | {len(pieces)} | {int((~pieces.is_valid).sum())} | {abs(g_sums - 1).max():.1e} |")
print(f"| GeoPandas overlay + pyproj areas (cells given) | {p_s:.3f} | {len(theirs)} | {int((~theirs.is_valid).sum())} | {abs(their_share_sum - 1).max():.1e} |")
print(f"geovor is {p_s / g_s:.2f}x GeoPandas (target: at least 5x, 0 invalid pieces)")
print("load average (1, 5, 15 min): before %.2f %.2f %.2f, after %.2f %.2f %.2f" % (*load_before, *os.getloadavg()))
