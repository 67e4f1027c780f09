// d3-geo-voronoi's polygons() on the points of a CSV (columns lat_deg, lon_deg), written as one
// GeoJSON FeatureCollection: the reference side of bench/cells_vs_d3.sh.
// Usage: node polygons.mjs INPUT.csv OUTPUT.geojson
import { readFileSync, writeFileSync } from "node:fs";
import { geoVoronoi } from "d3-geo-voronoi";

const [input, output] = process.argv.slice(2);
const lines = readFileSync(input, "utf8").split(/\r?\n/);  // the cities file has CRLF line ends
const header = lines[0].split(",");
const lat = header.indexOf("lat_deg"), lon = header.indexOf("lon_deg");
const points = [];
const seen = new Set();
let duplicates = 0;
for (let i = 1; i < lines.length; i++) {
  if (!lines[i]) continue;
  // The coordinates are the last two fields; names may hold quoted commas.
  const f = lines[i].split(",");
  const n = f.length - header.length;
  const p = [Number(f[lon + n]), Number(f[lat + n])];
  // d3-geo-voronoi returns no polygon at all when two points coincide: drop exact duplicates.
  const key = p[0] + "," + p[1];
  if (seen.has(key)) {
    duplicates++;
    continue;
  }
  seen.add(key);
  points.push(p);
}
const t0 = process.hrtime.bigint();
const polygons = geoVoronoi(points).polygons();
const t1 = process.hrtime.bigint();
writeFileSync(output, JSON.stringify(polygons));
const t2 = process.hrtime.bigint();
console.error(`d3-geo-voronoi: ${points.length} points (${duplicates} exact duplicates dropped), ` +
              `${polygons.features.length} polygons, polygons() ${Number(t1 - t0) / 1e9} s, write ${Number(t2 - t1) / 1e9} s`);
