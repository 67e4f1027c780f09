"""The worked example of docs/python.md: the weather stations' cells as a GeoDataFrame, plotted
with GeoPandas (docs/img/python_station_cells.png), and the nearest station of a few places.

Usage: python examples/python/station_cells.py [OUTPUT.png]   (from the repository root)
"""
import sys

import geopandas as gpd
import matplotlib
import numpy as np
import pandas as pd

import geovor

matplotlib.use("Agg")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "docs/img/python_station_cells.png"
    stations = pd.read_csv("datasets/weather_stations.csv")
    cells = geovor.cells(stations)  # one row per station: polygon, area_m2, neighbors, the CSV's columns
    print(f"{len(cells)} cells, {cells.area_m2.sum() / 1e6:,.0f} km2 in all")
    print(cells.nlargest(3, "area_m2")[["site_id", "area_m2"]].to_string(index=False))

    index = geovor.Index.from_frame(stations)
    places = pd.DataFrame({"name": ["Paris", "Nairobi", "Honolulu"],
                           "lat": [48.8566, -1.2921, 21.3069], "lon": [2.3522, 36.8219, -157.8583]})
    site, dist_m = index.nearest(places.lat.to_numpy(), places.lon.to_numpy(), metric="geodesic")
    places["station"] = index.sites()["id"].to_numpy()[site]
    places["distance_km"] = (dist_m / 1000).round(1)
    print(places.to_string(index=False))

    cells["area_km2_log10"] = np.log10(cells.area_m2 / 1e6)
    ax = cells.plot(column="area_km2_log10", cmap="viridis", linewidth=0.1, edgecolor="white",
                    figsize=(12, 6.2), legend=True,
                    legend_kwds={"label": "log10 cell area (km²)", "shrink": 0.6})
    gpd.GeoSeries(gpd.points_from_xy(stations.lon_deg, stations.lat_deg), crs=4326).plot(
        ax=ax, markersize=0.3, color="black")
    ax.set_xlim(-180, 180)
    ax.set_ylim(-90, 90)
    ax.set_title(f"Voronoi cells of the {len(stations):,} bundled weather stations (geovor.cells)")
    ax.figure.savefig(out, dpi=110, bbox_inches="tight")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
