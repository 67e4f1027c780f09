#!/usr/bin/python3
"""Independent randomized oracle for geovor's input rules (issue 16): delimited text read as
docs/user-guide.md ("Input") says, checked against the generator's own ground truth.

Each case is a site table with random but documented-legal variations: delimiter (, ; TAB |),
quoting, LF or CRLF, a UTF-8 byte order mark, a decimal comma where the delimiter is not a comma,
coordinate columns named by the documented conventions (random case where case cannot change the
words, random position), extra columns of text, integers (32 and 64 bits), reals, dates,
date-times, leading zeros, '+33', all-empty columns, empty values, an id column (or none) with
repeated ids, rows that must be rejected (not a number, empty, latitude beyond 90, longitude beyond
540, NaN/inf, DMS, a decimal comma in a comma file, wrong field count, bytes that are not UTF-8),
rows repeating an earlier position (merged), longitudes written +-360, a trailing delimiter, and
Latin-1 text read with --encoding ISO-8859-1. What the script expects is computed here, from the
rules, never by geovor:

- `geovor cells --report`: every data row is in the report exactly once, with its line number;
  a `site` at the expected site_index, `merged` into the site of the first row at its position
  (and listed in that cell's `ids`), or `rejected` with the documented reason; rows = sites +
  merged + rejected; each cell's id, `ids`, `n_rows` and every input column's value (text exact,
  numbers and dates by their type, empty values of typed columns null); feature ids unique
  (site_index when ids repeat, and then the warning with the count).
- `geovor nearest` at each expected site position (computed here from the text) answers that site
  at distance 0 (within 1 mm): the coordinates were parsed as written.
- Field types: geovor's GeoPackage read back by ogrinfo equals the documented typing of the
  accepted rows; GDAL's CSV driver (AUTODETECT_TYPE=YES, whole file) agrees except where the
  documentation says geovor differs (see README.md).

Usage: /usr/bin/python3 input_oracle.py --geovor build/tools/geovor --seed 1 [--cases N] [--tmp DIR]
Exit 0 when every check passes, 1 otherwise; last line `input oracle: N passed, M failed` (cases).
"""
import argparse
import csv
import io
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

TIMEOUT_S = 60

# Coordinate column name pairs from the documented conventions (user-guide, "Coordinate columns"):
# (latitude, longitude, may change case). camelCase names keep their case (it splits their words).
NAME_PAIRS = [
    ("lat", "lon", True), ("lat", "lng", True), ("lat", "long", True), ("latitude", "longitude", True),
    ("Latitude (deg)", "Longitude (deg)", True), ("Latitude [°]", "Longitude [°]", False),
    ("latitude_deg", "longitude_deg", True), ("lat_deg", "lon_deg", True), ("Lat_DD", "Lon_DD", True),
    ("LATITUDE (WGS84)", "LONGITUDE (WGS84)", True), ("decimalLatitude", "decimalLongitude", False),
    ("LAT-DD", "LON-DD", True),
    ("stop_lat", "stop_lon", True), ("pickup_latitude", "pickup_longitude", True),
    ("verbatimLatitude", "verbatimLongitude", False),
    ("y", "x", True), ("POINT_Y", "POINT_X", True), ("ycoord", "xcoord", True), ("y_coord", "x_coord", True),
]
RANK = {n: (1 if i < 12 else 2 if i < 15 else 3) for i, (n, _, _) in enumerate(NAME_PAIRS)}
# Columns of a lower rank than the chosen pair (numbers a careless reader might take) and names
# that only look like a coordinate ("long" not at the end of a name is no longitude).
DECOYS = {2: [("stop_lat", "stop_lon"), ("dropoff_latitude", "dropoff_longitude")],
          3: [("y", "x"), ("POINT_Y", "POINT_X")]}
ID_NAMES = ["id", "icao", "code", "name"]
# Extra column kinds: (kind, documented geovor type, GDAL's type when it differs by a documented rule).
KINDS = ["text", "int", "int64", "real", "mixed_num", "date", "datetime", "zeros", "plus", "empty",
         "decimal_comma"]
EXTRA_NAMES = ["population", "elev", "founded", "updated", "zip", "note", "score", "phone", "flag",
               "count_a", "remark", "altitude_ft_note", "a;b,c|d\te", "Café"]  # delimiters inside quotes are no delimiters
LATIN1_WORDS = ["Zürich", "São Paulo", "Besançon", "Málaga", "Göteborg", "Ærø", "Reykjavík"]
ASCII_WORDS = ["Paris", "Lima", "Oslo", "Perth", "Quito", "Accra", "Hanoi", "Denver", "New York, NY",
               'say "hi"', "a;b", "pipe|here", "tab\there", "two\nlines", " padded ", ""]

# Reject reasons (user-guide, "Values are WGS84 geodetic degrees. Rejected: ...") as regexes on the
# report's detail.
REASONS = {
    "not_number": r"is not a number",
    "empty": r"empty value",
    "lat_range": r"beyond \+-90",
    "lon_range": r"out of range",
    "nan": r"not a finite number",
    "dms": r"degrees, minutes and seconds",
    "comma_in_comma_file": r"is not a number",
    "few_fields": r"found \d+ fields, expected \d+",
    "many_fields": r"found \d+ fields, expected \d+",
    "not_utf8": r"not valid UTF-8",
}


class Case:
    pass


def fmt_coord(rng, v, decimal_comma_ok):
    """A coordinate's text: 6 decimals, an integer when it is one, a decimal comma where legal."""
    if v == int(v) and rng.random() < 0.5:
        text = str(int(v))
    else:
        text = f"{v:.6f}".rstrip("0").rstrip(".") if rng.random() < 0.5 else f"{v:.6f}"
    if decimal_comma_ok and "." in text and rng.random() < 0.5:
        text = text.replace(".", ",")
    return text


def coord_value(text):
    return float(text.replace(",", "."))


def case_variant(rng, name, may):
    if not may:
        return name
    return rng.choice([name, name.lower(), name.upper(), name.title()])


def value_for(rng, kind, row, decimal_comma_ok, crlf=False):
    """(text, python value as geovor's GeoJSON should hold it: str/int/float/None)."""
    if rng.random() < 0.15 and kind not in ("empty",):
        return "", None
    if kind == "text":
        w = rng.choice(ASCII_WORDS + (["two\r\nlines"] if crlf else []))
        return w, w
    if kind == "int":
        v = rng.randint(-2**31, 2**31 - 1) if rng.random() < 0.3 else rng.randint(-999, 9999)
        return str(v), v
    if kind == "int64":
        v = rng.choice([rng.randint(2**31, 2**62), rng.randint(-2**40, 2**40)])
        return str(v), v
    if kind == "real":
        t = rng.choice([f"{rng.uniform(-1000, 1000):.3f}", f"{rng.uniform(0, 10):.1e}", "-0.5", "1e3", "0.25"])
        return t, float(t)
    if kind == "mixed_num":
        t = rng.choice([str(rng.randint(-50, 50)), f"{rng.uniform(-5, 5):.2f}"])
        return t, float(t)
    if kind == "date":
        y, m = rng.randint(1900, 2030), rng.randint(1, 12)
        d = rng.randint(1, 28) if rng.random() < 0.9 else {2: 29 if y % 4 == 0 and (y % 100 or y % 400 == 0) else 28}.get(m, 30)
        t = f"{y:04d}-{m:02d}-{d:02d}"
        return t, t
    if kind == "datetime":
        t = f"20{rng.randint(0, 29):02d}-{rng.randint(1, 12):02d}-{rng.randint(1, 28):02d}" + rng.choice(["T", " "]) + \
            f"{rng.randint(0, 23):02d}:{rng.randint(0, 59):02d}:{rng.randint(0, 59):02d}" + rng.choice(["", "Z"])
        return t, t
    if kind == "zeros":
        t = "0" + str(rng.randint(0, 99999))
        return t, t
    if kind == "plus":
        t = "+" + str(rng.randint(1, 999))
        return t, t
    if kind == "empty":
        return "", ""
    if kind == "decimal_comma":
        t = f"{rng.uniform(-100, 100):.2f}".replace(".", ",") if decimal_comma_ok else f"{rng.randint(1, 9)},5"
        return t, t
    raise AssertionError(kind)


# The documented type of an extra column of each kind (user-guide, "Field types"), given the
# values of its accepted rows.
def documented_type(kind, texts):
    nonempty = [t for t in texts if t != ""]
    if not nonempty:
        return "String"
    if kind in ("text", "zeros", "plus", "empty", "decimal_comma"):
        # text: a text column that happens to hold only number-like words is not generated
        return "String"
    if kind == "int":
        return "Integer"
    if kind == "int64":
        return "Integer64" if any(not (-2**31 <= int(t) < 2**31) for t in nonempty) else "Integer"
    if kind == "real":
        return "Real"
    if kind == "mixed_num":
        return "Real" if any(not re.fullmatch(r"-?(0|[1-9][0-9]*)", t) for t in nonempty) else "Integer"
    if kind == "date":
        return "Date"
    if kind == "datetime":
        return "DateTime"
    raise AssertionError(kind)


def coord_type(texts):
    """A coordinate column's documented type from its accepted values."""
    if any("," in t for t in texts):
        return "String"
    if all(re.fullmatch(r"-?(0|[1-9][0-9]*)", t) for t in texts):
        return "Integer"
    return "Real"


def make_case(seed, index):
    rng = random.Random(f"geovor-input-oracle-{seed}-{index}")
    c = Case()
    c.seed, c.index = seed, index
    c.delim = rng.choice([",", ";", "\t", "|"])
    c.eol = rng.choice(["\n", "\r\n"])
    c.bom = rng.random() < 0.3
    c.encoding = rng.choice(["utf-8", "utf-8", "latin-1", "latin-1-unsaid", "utf-16"])
    if c.encoding != "utf-8":
        c.bom = False
    dc_ok = c.delim != ","
    # a header that is not UTF-8 refuses the whole file: names stay ASCII where the text is unsaid Latin-1
    pairs = [p for p in NAME_PAIRS if c.encoding != "latin-1-unsaid" or (p[0] + p[1]).isascii()]
    lat_name, lon_name, may = rng.choice(pairs)
    lat_name, lon_name = case_variant(rng, lat_name, may), case_variant(rng, lon_name, may)
    if rng.random() < 0.1:  # names are compared trimmed
        lat_name, lon_name = " " + lat_name, lon_name + " "
    c.has_id = rng.random() < 0.8
    id_name = case_variant(rng, rng.choice(ID_NAMES), True)
    kinds = rng.sample(KINDS, rng.randint(0, 5))
    names = rng.sample([n for n in EXTRA_NAMES if c.encoding != "latin-1-unsaid" or n.isascii()], len(kinds))
    cols = [("lat", lat_name), ("lon", lon_name)] + [(k, n) for k, n in zip(kinds, names)]
    rank = RANK[[p for p in NAME_PAIRS if p[0].lower() == lat_name.strip().lower()][0][0]]
    c.ambiguous = None
    if rng.random() < 0.3:  # decoy columns of a lower rank: the better-ranked pair wins
        lower = [d for r, ds in DECOYS.items() if r > rank for d in ds]
        if lower:
            dl, dn = rng.choice(lower)
            cols += [("decoy", dl), ("decoy", dn)]
    if rng.random() < 0.2:
        cols.append(("text", "NAME_LONG"))
    if rng.random() < 0.05 and rank <= 2:  # a second latitude of the same rank: refused with both named
        other = {1: "Latitude" if lat_name.lower() != "latitude" else "lat", 2: "dropoff_latitude"}[rank]
        if other.lower() not in (n.lower() for _, n in cols):
            cols.append(("decoy", other))
            c.ambiguous = (lat_name, other)
    if c.has_id:
        cols.append(("id", id_name))
    rng.shuffle(cols)
    c.columns = cols
    c.trailing = rng.random() < 0.15  # a spreadsheet's trailing delimiter on every line
    c.stdin = rng.random() < 0.15       # read as `-` from a pipe (source "<stdin>")
    c.row_ids = rng.random() < 0.1      # --id-field '#row'
    # --lat-field/--lon-field naming the columns in another case (resolves an ambiguous header)
    c.named = rng.random() < 0.15
    ncol = len(cols)
    n = rng.randint(1, 30)
    rows = []   # per row: dict(fields=[texts], status, reason, pos, id, ...)
    positions = []  # accepted distinct positions (lat, lon reduced)
    id_pool = []
    latin_rows = c.encoding != "utf-8"
    for r in range(1, n + 1):
        row = {"row": r}
        roll = rng.random()
        kind = "good"
        if roll < 0.22:
            kind = rng.choice(list(REASONS))
            if kind == "not_utf8" and c.encoding != "latin-1-unsaid":
                kind = "not_number"
            if kind == "comma_in_comma_file" and c.delim != ",":
                kind = "dms"
        elif roll < 0.32 and positions:
            kind = "dup"
        # position
        if kind == "dup":
            lat, lon = rng.choice(positions)
        else:
            for _ in range(100):
                lat = round(rng.uniform(-89.5, 89.5), rng.choice([0, 2, 6]))
                lon = round(rng.uniform(-180, 179.999), rng.choice([0, 3, 6]))
                if rng.random() < 0.05:  # a pole: any longitude is the pole
                    lat = rng.choice([90, -90])
                if rng.random() < 0.05:  # the antimeridian, written 180, -180 or 540
                    lon = -180
                if all(abs(lat - a) > 0.01 or (abs(lat) != 90 and abs(((lon - b + 180) % 360) - 180) > 0.01)
                       for a, b in positions):
                    break
        written_lon = lon + rng.choice([0, 0, 0, 360, -360])
        if lon == -180:
            written_lon = rng.choice([-180, 180, 540, -540])
        lat_t, lon_t = fmt_coord(rng, lat, dc_ok), fmt_coord(rng, written_lon, dc_ok)
        reason = None
        if kind == "not_number":
            (lat_t, lon_t) = ("abc", lon_t) if rng.random() < 0.5 else (lat_t, "12x")
        elif kind == "empty":
            (lat_t, lon_t) = ("", lon_t) if rng.random() < 0.5 else (lat_t, "")
        elif kind == "lat_range":
            lat_t = rng.choice(["90.5", "-91", "1000", "90.0000001"])
        elif kind == "lon_range":
            lon_t = rng.choice(["540.5", "-600", "1e5"])
        elif kind == "nan":
            lat_t = rng.choice(["nan", "NaN", "inf", "-inf"])
        elif kind == "dms":
            lat_t = rng.choice(["40°26'46\"N", "12°30'S"] + (["40°26′46″N"] if c.encoding == "utf-8" else []))
            if c.encoding == "latin-1-unsaid":
                kind = "not_utf8"  # the degree sign's Latin-1 byte is not UTF-8: that comes first
        elif kind == "comma_in_comma_file":
            lat_t = "48,8566"
        fields = []
        texts_by_col = {}
        for k, name in cols:
            if k == "lat":
                t = lat_t
            elif k == "lon":
                t = lon_t
            elif k == "decoy":
                t = f"{rng.uniform(-80, 80):.4f}"
            elif k == "id":
                if id_pool and rng.random() < 0.15:
                    t = rng.choice(id_pool)
                else:
                    t = rng.choice([f"s{r}", f"{r:04d}", f"ST {r}", f"id,{r}"])
                id_pool.append(t)
            else:
                t, _ = value_for(rng, k, r, dc_ok, c.eol == "\r\n")
                if kind == "not_utf8" and k == "text":
                    pass
            fields.append(t)
        if kind == "not_utf8" and "°" not in lat_t:
            # a Latin-1 word in some text-like column (or a new one appended to a text field)
            tcols = [i for i, (k, _) in enumerate(cols) if k in ("text", "id", "empty")]
            if tcols:
                i = rng.choice(tcols)
                fields[i] = rng.choice(LATIN1_WORDS)

            else:
                kind = "nan"
                fields[[k for k, _ in cols].index("lat")] = "nan"
        elif latin_rows and kind in ("good", "dup") and c.encoding == "latin-1":
            tcols = [i for i, (k, _) in enumerate(cols) if k == "text"]
            if tcols and rng.random() < 0.5:
                fields[rng.choice(tcols)] = rng.choice(LATIN1_WORDS)
        if kind == "few_fields":
            fields = fields[:-1] if len(fields) > 2 else fields[:1]
        elif kind == "many_fields":
            fields = fields + ["extra"]
        row["fields"] = fields
        row["kind"] = kind
        row["accepted"] = kind in ("good", "dup")
        if row["accepted"]:
            key = (lat, ((lon + 180) % 360) - 180) if abs(lat) != 90 else (lat, 0.0)
            row["pos"] = key
            if kind != "dup":
                positions.append(key)
        rows.append(row)
    c.rows = rows
    return c


def quote_field(rng, text, delim):
    need = any(ch in text for ch in (delim, '"', "\n", "\r")) or text != text.strip(" ")
    if need or rng.random() < 0.1:
        return '"' + text.replace('"', '""') + '"'
    return text


def serialize(c, delim=None, for_gdal=False):
    """The file's bytes and each row's first line number."""
    rng = random.Random(f"serialize-{c.seed}-{c.index}-{delim}")
    d = delim or c.delim
    lines = [d.join(quote_field(rng, n, d) for _, n in c.columns) + (d if c.trailing and not for_gdal else "")]
    line_no = 2
    for row in c.rows:
        row_text = d.join(quote_field(rng, t, d) for t in row["fields"])
        if c.trailing and not for_gdal and row["kind"] not in ("few_fields", "many_fields"):
            row_text += d
        if not for_gdal:
            row["line"] = line_no
        line_no += 1 + row_text.count("\n")
        lines.append(row_text)
    text = c.eol.join(lines) + c.eol
    enc = "utf-8" if (c.encoding == "utf-8" or for_gdal) else c.encoding.replace("-unsaid", "")
    data = text.encode(enc)  # UTF-16 with its byte order mark
    if c.bom and not for_gdal:
        data = b"\xef\xbb\xbf" + data
    return data


def expected(c):
    """The ground truth: sites (first row of each position) and merges, ids, feature ids, types."""
    site_of_pos = {}
    sites = []
    for row in c.rows:
        if not row["accepted"]:
            continue
        idcol = [k for k, _ in c.columns].index("id") if c.has_id and not c.row_ids else None
        row["id"] = row["fields"][idcol] if idcol is not None else str(row["row"])
        if row["pos"] in site_of_pos:
            row["site"] = site_of_pos[row["pos"]]
            row["status"] = "merged"
        else:
            row["site"] = len(sites)
            site_of_pos[row["pos"]] = row["site"]
            sites.append(row)
            row["status"] = "site"
    accepted = [r for r in c.rows if r["accepted"]]
    seen, repeats = set(), 0
    for r in accepted:
        repeats += r["id"] in seen
        seen.add(r["id"])
    c.sites, c.accepted, c.repeats = sites, accepted, repeats
    c.types = {}
    for i, (k, name) in enumerate(c.columns):
        texts = [r["fields"][i] for r in accepted]
        if k == "id" and not c.row_ids:
            c.types[name] = "String"
        elif k == "id":
            c.types[name] = documented_type("text", texts) if not all(
                re.fullmatch(r"-?(0|[1-9][0-9]*)", t) for t in texts if t) else "Integer"
        elif k in ("lat", "lon"):
            c.types[name] = coord_type(texts)
        elif k == "decoy":
            c.types[name] = "Real" if texts else "String"
        else:
            c.types[name] = documented_type(k, texts)


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, timeout=TIMEOUT_S, **kw)


def typed_value(t, typ):
    if t == "":
        return None if typ != "String" else ""
    if typ in ("Integer", "Integer64"):
        return int(t)
    if typ == "Real":
        return float(t)
    return t


def ogr_types(args_list):
    p = run(["ogrinfo", "-ro", "-so", "-al"] + args_list)
    out = p.stdout.decode("utf-8", "replace")
    types = {}
    for m in re.finditer(r"^(.+): (Integer64|Integer|Real|String|Date|DateTime|Time)\b", out, re.M):
        types[m.group(1)] = m.group(2)
    return types, out + p.stderr.decode("utf-8", "replace")


# GDAL's CSV driver types these differently, each a documented rule of geovor's (user-guide,
# "Field types"; README.md here): an identifier column stays text, a leading zero or '+' keeps a
# column text, a decimal comma keeps it text, a column is typed by its accepted rows only.
DOCUMENTED_DIFFERENCES = {
    "id": "the id column is always String",
    "zeros": "a leading zero keeps a column text",
    "plus": "a leading '+' keeps a column text",
    "decimal_comma": "a decimal comma keeps a column text",
}


STATS = {}  # GDAL's CSV typing against geovor's: agreements, and each documented difference met


def check_case(c, geovor, tmp, use_gdal):
    fails = []
    expected(c)
    ext = random.Random(f"ext-{c.seed}-{c.index}").choice([".csv", ".txt", ".tsv", ""])
    name = f"case{c.seed}_{c.index}{ext}"
    path = os.path.join(tmp, name)
    data = serialize(c)
    with open(path, "wb") as f:
        f.write(data)
    enc = {"latin-1": ["--encoding", "ISO-8859-1"], "utf-16": ["--encoding", "UTF-16"]}.get(c.encoding, [])
    recipe = (f"delim={c.delim!r} eol={c.eol!r} bom={c.bom} encoding={c.encoding} trailing={c.trailing} "
              f"columns={[n for _, n in c.columns]} kinds={[k for k, _ in c.columns]} rows={len(c.rows)}")
    n_acc = len(c.accepted)
    gj = os.path.join(tmp, name + ".geojson")
    rep = os.path.join(tmp, name + ".report.csv")
    if c.row_ids:
        enc = enc + ["--id-field", "#row"]
    if c.named:
        lat_name = [n for k, n in c.columns if k == "lat"][0]
        lon_name = [n for k, n in c.columns if k == "lon"][0]
        flip = random.Random(f"named-{c.seed}-{c.index}")
        enc = enc + ["--lat-field", flip.choice([lat_name, lat_name.strip().upper(), lat_name.strip().lower()]),
                     "--lon-field", flip.choice([lon_name, lon_name.strip().upper(), lon_name.strip().lower()])]
    source = "<stdin>" if c.stdin else path

    def geovor_run(args):
        if c.stdin:  # the table from a pipe, as `-`
            return run([geovor] + [("-" if a == path else a) for a in args], input=data)
        return run([geovor] + args)

    p = geovor_run(["cells", path, "-o", gj, "--report", rep, "--overwrite"] + enc)
    err = p.stderr.decode("utf-8", "replace")
    # A value under a trailing unnamed column refuses the file, naming the first such row.
    spill = [r for r in c.rows if c.trailing and r["kind"] == "many_fields"]
    if c.ambiguous and not c.named:
        a, b = sorted(c.ambiguous, key=[n for _, n in c.columns].index)  # named in column order
        want = f"ambiguous latitude column: '{a}', '{b}' are equally likely; choose one with --lat-field"
        if p.returncode != 3 or want not in err:
            fails.append(f"ambiguous header: expected exit 3 and '{want}', got {p.returncode}: {err[-500:]}")
        return fails, recipe, path
    if spill:
        r = spill[0]
        want = (f"{source}: header: column {len(c.columns) + 1} has no name, but row {r['row']} (line {r['line']}) "
                f"has a value there: 'extra'; name the column")
        if p.returncode != 3 or want not in err:
            fails.append(f"a value under the trailing unnamed column: expected exit 3 and '{want}', got "
                         f"{p.returncode}: {err[-500:]}")
        return fails, recipe, path
    if n_acc == 0:
        if p.returncode != 3 or "no usable site" not in err:
            fails.append(f"no accepted row: expected exit 3 'no usable site', got {p.returncode}: {err[-500:]}")
        return fails, recipe, path
    if p.returncode != 0:
        fails.append(f"cells exited {p.returncode}: {err[-800:]}")
        return fails, recipe, path
    # The report: one line per row, each row once.
    with open(rep, newline="", encoding="utf-8") as f:
        report = list(csv.DictReader(f))
    by_row = {}
    for r in report:
        k = int(r["row"])
        if k in by_row:
            fails.append(f"report: row {k} twice")
        by_row[k] = r
    if sorted(by_row) != list(range(1, len(c.rows) + 1)):
        fails.append(f"report rows {sorted(by_row)} != 1..{len(c.rows)}")
    for row in c.rows:
        r = by_row.get(row["row"])
        if r is None:
            continue
        if int(r["line"]) != row["line"]:
            fails.append(f"row {row['row']}: line {r['line']}, expected {row['line']}")
        if not row["accepted"]:
            if r["status"] != "rejected" or not re.search(REASONS[row["kind"]], r["detail"]):
                fails.append(f"row {row['row']} ({row['kind']}, fields {row['fields']}): {r['status']} "
                             f"'{r['detail']}', expected rejected /{REASONS[row['kind']]}/")
            continue
        if r["status"] != row["status"] or int(r["site_index"] or -1) != row["site"] or r["id"] != row["id"]:
            fails.append(f"row {row['row']} ({row['kind']}): {r['status']} site {r['site_index']} id {r['id']!r}, "
                         f"expected {row['status']} site {row['site']} id {row['id']!r} (fields {row['fields']})")
    n_site = sum(r["status"] == "site" for r in report)
    n_merged = sum(r["status"] == "merged" for r in report)
    n_rej = sum(r["status"] == "rejected" for r in report)
    if (n_site, n_merged, n_rej) != (len(c.sites), n_acc - len(c.sites), len(c.rows) - n_acc):
        fails.append(f"report counts site/merged/rejected {n_site}/{n_merged}/{n_rej}, expected "
                     f"{len(c.sites)}/{n_acc - len(c.sites)}/{len(c.rows) - n_acc}")
    p = geovor_run(["info", path] + enc)
    info = dict(re.findall(r"^(\w+): (\S+)$", p.stdout.decode("utf-8", "replace"), re.M))
    want = {"rows": str(len(c.rows)), "sites": str(len(c.sites)), "merged": str(n_acc - len(c.sites)),
            "rejected": str(len(c.rows) - n_acc)}
    if p.returncode != 0 or {k: info.get(k) for k in want} != want:
        fails.append(f"info (exit {p.returncode}): {[info.get(k) for k in want]}, expected {want}")
    # Repeated ids: the warning and unique feature ids.
    m = re.search(r"warning: (\d+) rows have the id of an earlier row", err)
    if (int(m.group(1)) if m else 0) != c.repeats:
        fails.append(f"duplicate-id warning says {m.group(1) if m else 'nothing'}, expected {c.repeats} repeated ids")
    # The cells: ids, n_rows, every column's value.
    with open(gj, encoding="utf-8") as f:
        feats = json.load(f)["features"]
    if len(feats) != len(c.sites):
        fails.append(f"{len(feats)} cells, expected {len(c.sites)}")
    for feat in feats:
        pr = feat["properties"]
        s = pr["site_index"]
        if s >= len(c.sites):
            continue
        site = c.sites[s]
        members = [r["id"] for r in c.accepted if r["site"] == s]
        want_fid = s if c.repeats else site["id"]
        if feat.get("id") != want_fid:
            fails.append(f"cell {s}: feature id {feat.get('id')!r}, expected {want_fid!r}")
        if pr["site_id"] != site["id"] or pr["ids"] != members or pr["n_rows"] != len(members):
            fails.append(f"cell {s}: site_id {pr['site_id']!r} ids {pr['ids']} n_rows {pr['n_rows']}, expected "
                         f"{site['id']!r} {members}")
        for i, (k, colname) in enumerate(c.columns):
            want = typed_value(site["fields"][i], c.types[colname])
            got = pr.get(colname, "<missing>")
            if got != want or type(got) is not type(want) and not (isinstance(want, float) and isinstance(got, int)):
                fails.append(f"cell {s}: {colname} = {got!r}, expected {want!r} ({c.types[colname]})")
    # Positions: nearest at each expected site's position answers it at distance 0.
    q = os.path.join(tmp, name + ".queries.csv")
    with open(q, "w", encoding="utf-8") as f:
        f.write("query_id,lat,lon\n")
        for s, site in enumerate(c.sites):
            f.write(f"q{s},{site['pos'][0]!r},{site['pos'][1]!r}\n")
    p = geovor_run(["nearest", "--sites", path, "--queries", q, "-o", "-", "-q"] + enc)
    if p.returncode != 0:
        fails.append(f"nearest exited {p.returncode}: {p.stderr.decode('utf-8', 'replace')[-500:]}")
    else:
        for r in csv.DictReader(io.StringIO(p.stdout.decode("utf-8"))):
            s = int(r["query_id"][1:])
            if int(r["site_index"]) != s or float(r["distance_m"]) > 1e-3:
                fails.append(f"nearest at site {s}'s position {c.sites[s]['pos']} (row {c.sites[s]['row']}, "
                             f"fields {c.sites[s]['fields']}): site {r['site_index']} at {r['distance_m']} m")
    # Field types: geovor's GeoPackage read back by GDAL, and GDAL's own CSV typing.
    if use_gdal:
        gpkg = os.path.join(tmp, name + ".gpkg")
        p = geovor_run(["cells", path, "-o", gpkg, "--overwrite", "-q"] + enc)
        if p.returncode != 0:
            fails.append(f"cells -o gpkg exited {p.returncode}: {p.stderr.decode('utf-8', 'replace')[-500:]}")
            return fails, recipe, path
        got, _ = ogr_types([gpkg, "cells"])
        # GDAL reads this table: the same values, UTF-8, ';' for '|' (GDAL 3.6 reads no '|'), no
        # rejected row whose field count is wrong (GDAL pads or drops them).
        kept = [r for r in c.rows]
        twin = os.path.join(tmp, name + ".gdal.csv")
        with open(twin, "wb") as f:
            f.write(serialize(c, delim=";" if c.delim == "|" else c.delim, for_gdal=True))
        gdal, gout = ogr_types(["-oo", "AUTODETECT_TYPE=YES", "-oo", "AUTODETECT_SIZE_LIMIT=0", "CSV:" + twin])
        for i, (k, colname) in enumerate(c.columns):
            want = c.types[colname]
            if got.get(colname) != want:
                fails.append(f"type of {colname} ({k}) in geovor's GeoPackage: {got.get(colname)}, documented {want}")
            g = gdal.get(colname.strip())  # GDAL trims names; geovor writes them as read
            if g is None:
                fails.append(f"GDAL's CSV driver has no column {colname}: {gout[-400:]}")
                continue
            if g == want:
                STATS["GDAL agrees"] = STATS.get("GDAL agrees", 0) + 1
                continue
            why = DOCUMENTED_DIFFERENCES.get(k)
            if why is None and k in ("lat", "lon") and want == "String":
                why = "a decimal comma keeps a column text"
            if why is None and any(not r["accepted"] and i < len(r["fields"]) and r["fields"][i] != ""
                                   for r in c.rows):
                why = "geovor types a column by its accepted rows, GDAL by every row"
            if why is not None:
                key = f"{why} (geovor {want}, GDAL {g})"
                STATS[key] = STATS.get(key, 0) + 1
                continue
            fails.append(f"type of {colname} ({k}): geovor {want}, GDAL's CSV driver {g}, and no documented rule "
                         f"tells them apart")
    return fails, recipe, path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--geovor", required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cases", type=int, default=20)
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--tmp", help="folder for the cases' files (kept); default a temporary one, removed")
    ap.add_argument("--no-gdal", action="store_true", help="skip the field-type checks (ogrinfo)")
    ap.add_argument("-v", "--verbose", action="store_true")
    a = ap.parse_args()
    use_gdal = not a.no_gdal and shutil.which("ogrinfo") is not None
    if not a.no_gdal and not use_gdal:
        print("input oracle: ogrinfo not found (install gdal-bin) or pass --no-gdal")
        print("input oracle: 0 passed, 1 failed")
        return 1
    tmp = a.tmp or tempfile.mkdtemp(prefix="geovor_input_oracle_")
    os.makedirs(tmp, exist_ok=True)
    passed = failed = 0
    try:
        for i in range(a.first, a.first + a.cases):
            c = make_case(a.seed, i)
            try:
                fails, recipe, path = check_case(c, a.geovor, tmp, use_gdal)
            except Exception as exc:  # noqa: BLE001
                fails, recipe, path = [f"oracle error: {exc!r}"], "", ""
            if fails:
                failed += 1
                print(f"FAIL seed {a.seed} case {i}: {recipe}\n  file {path}")
                for f in fails[:20]:
                    print("  " + f)
            else:
                passed += 1
                if a.verbose:
                    print(f"ok seed {a.seed} case {i}: {recipe}")
    finally:
        if not a.tmp:
            shutil.rmtree(tmp, ignore_errors=True)
    if use_gdal:
        print("field types, columns compared with GDAL's CSV driver (AUTODETECT_TYPE=YES):")
        for k in sorted(STATS, key=lambda k: (k != "GDAL agrees", k)):
            print(f"  {STATS[k]:4d}  {k}")
    print(f"input oracle: {passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
