"""What the algorithms share: the base class, reading a point layer into WGS84 arrays, the
package's GeoDataFrames written to a feature sink, progress, cancellation and the package's
warnings as feedback."""
import math
import re
import warnings

from qgis.core import (
    QgsApplication,
    QgsCoordinateReferenceSystem,
    QgsFeature,
    QgsFeatureRequest,
    QgsFeatureSink,
    QgsField,
    QgsFields,
    QgsGeometry,
    QgsPointXY,
    QgsProcessingAlgorithm,
    QgsProcessingException,
    QgsWkbTypes,
)
from qgis.PyQt.QtCore import QCoreApplication, QDate, QDateTime, Qt, QTime, QVariant

from . import library

# The command's and the package's id columns (compared trimmed and case-insensitively; the
# earlier name wins); a query's id is looked for as query_id first (geovor nearest).
ID_NAMES = ("id", "icao", "code", "name")
QUERY_ID_NAMES = ("query_id",) + ID_NAMES

# Names an output format keeps for itself (lib/include/geovor/layers/input_columns.hpp): an input
# field of one of these names, or of one of the algorithm's own fields, is written src_NAME.
RESERVED_NAMES = ("fid", "ogc_fid", "geom", "geometry", "the_geom", "wkb_geometry", "wkt", "gml_id", "shape")

# The columns of the DataFrame handed to the package: coordinates, id, and the feature's index in
# the layer, which the package carries to each output feature (the site's first feature), so that
# the layer's attributes are copied with their QGIS types.
LAT, LON, ID, ROW = "__geovor_lat", "__geovor_lon", "__geovor_id", "__geovor_row"
HELPER_COLUMNS = (LAT, LON, ID, ROW)


def tr(text):
    return QCoreApplication.translate("geovor", text)


def wgs84():
    return QgsCoordinateReferenceSystem("EPSG:4326")


def is_null(value):
    return value is None or (isinstance(value, QVariant) and value.isNull())


def as_text(value):
    """An attribute as an id text: NULL is empty; dates in ISO 8601."""
    if is_null(value):
        return ""
    if isinstance(value, (QDate, QDateTime, QTime)):
        return value.toString(Qt.ISODate)
    return str(value)


def as_number(value):
    """An attribute as a float, or None for NULL or a value that is no number."""
    if is_null(value) or isinstance(value, bool):
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


def threads():
    """QGIS's thread setting (Settings > Options > Rendering, max threads): None for all cores."""
    n = QgsApplication.maxThreads()
    return n if n and n > 0 else None


class Canceled(Exception):
    """The user canceled: the algorithm returns {} (QGIS then discards the outputs)."""


class Progress:
    """feedback's progress over [start, end) of the whole run, and its cancel button."""

    def __init__(self, feedback, start, end, total):
        self.feedback, self.start, self.span = feedback, start, end - start
        self.total = max(int(total), 1)

    def step(self, i):
        if i % 256 == 0:
            if self.feedback.isCanceled():
                raise Canceled()
            self.feedback.setProgress(self.start + self.span * min(i, self.total) / self.total)

    def finish(self):
        self.feedback.setProgress(self.start + self.span)


class GeovorAlgorithm(QgsProcessingAlgorithm):
    """The algorithms' base: group, instance creation, the package, and the run wrapped so that
    the package's errors are Processing errors and its warnings feedback warnings."""

    def group(self):
        return ""

    def groupId(self):  # noqa: N802
        return ""

    def createInstance(self):  # noqa: N802
        return type(self)()

    def canExecute(self):  # noqa: N802
        error = library.import_error()
        return (True, "") if error is None else (False, error)

    def package(self):
        try:
            return library.load()
        except ImportError as error:
            raise QgsProcessingException(str(error)) from error

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        try:
            return self.process(parameters, context, feedback)
        except Canceled:
            return {}

    def invalid_source(self, parameters, name):
        return QgsProcessingException(self.invalidSourceError(parameters, name))

    def invalid_sink(self, parameters, name):
        return QgsProcessingException(self.invalidSinkError(parameters, name))

    def write(self, sink, fields, frame, own, points, progress):
        """The rows of a frame of sites' features (cells) with each site's layer attributes."""
        write_frame(sink, fields, frame, own, lambda row: points.attributes[row], progress)

    def call(self, feedback, function, *args, points=None, **kwargs):
        """function(*args, **kwargs) from the package: a ValueError (bad data, no convergence) is a
        QgsProcessingException, naming the feature when it names an index of `points`; its
        warnings (cells written empty, hidden sites) go to feedback."""
        if feedback.isCanceled():
            raise Canceled()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                result = function(*args, **kwargs)
            except ValueError as error:
                raise QgsProcessingException(f"geovor: {name_feature(str(error), points)}") from error
        package = self.package()
        ours = (package.GeometryWarning, package.HiddenSiteWarning)
        for w in caught:
            if issubclass(w.category, ours):
                feedback.pushWarning(str(w.message))
        return result


def name_feature(message, points):
    """The package's message with the feature it names: its indices (weights[i], share i, row i)
    count the points handed to it, not the layer's features."""
    match = re.search(r"\[(\d+)\]|\b(?:share|row) (\d+)", message)
    if points is None or match is None:
        return message
    i = int(match.group(1) or match.group(2))
    if not 0 <= i < len(points.used):
        return message
    return f"{message} (feature {points.used[i] + 1}, id {points.ids[i]})"


def find_field(fields, given, names):
    """The index of the field named `given` (a parameter; None or '' for automatic), else of the
    first of `names` present (trimmed, case-insensitive); -1 for none."""
    if given:
        index = fields.lookupField(given)
        if index < 0:
            raise QgsProcessingException(tr(f"no field {given!r}"))
        return index
    lower = {}
    for i, field in enumerate(fields):
        lower.setdefault(field.name().strip().lower(), i)
    for name in names:
        if name in lower:
            return lower[name]
    return -1


class Points:
    """A point layer read in WGS84: for every feature (in the layer's order) its attributes, and
    for those with a usable point (`used`: their indices in the layer) lat/lon in degrees, the id
    text and the numbers of the `numbers` fields."""

    def __init__(self):
        self.fields = QgsFields()
        self.attributes = []  # per feature of the layer
        self.used = []  # layer indices of the features with a usable point
        self.lat, self.lon, self.ids = [], [], []
        self.numbers = {}  # name -> values per used feature
        self.point = {}  # layer index -> (lon, lat) of a used feature
        self.id_index = -1  # the id field's index, or -1 (feature numbers)

    @property
    def id_field(self):
        return None if self.id_index < 0 else self.fields[self.id_index].name()

    def id_of(self, row):
        """The id text of the feature at index `row` of the layer."""
        return as_text(self.attributes[row][self.id_index]) if self.id_index >= 0 else str(row + 1)

    def frame(self):
        """The used points as the DataFrame handed to the package (columns LAT, LON, ID, ROW)."""
        import pandas as pd

        return pd.DataFrame({LAT: self.lat, LON: self.lon, ID: self.ids, ROW: self.used})

    def array(self, name):
        import numpy as np

        return None if name not in self.numbers else np.asarray(self.numbers[name], dtype=np.float64)


def read_points(source, context, feedback, progress, *, what, id_field=None, id_names=ID_NAMES, numbers=(),
                allow_none=False):
    """The features of `source` (a QgsProcessingFeatureSource of points, in any CRS) as Points.

    A feature without a point (null or empty geometry), or whose `numbers` fields (name, field
    name) are NULL or not a number, is left out with a warning naming it, as the command rejects
    rows; a multipoint of more than one point is an error. Ids: the `id_field`, else the first of
    `id_names` present, else the feature number (1, 2, ...: the command's row numbers). No usable
    point at all is an error unless allow_none."""
    points = Points()
    points.fields = source.fields()
    points.id_index = find_field(points.fields, id_field, id_names)
    number_fields = []
    for name, field_name in numbers:
        if field_name:
            index = points.fields.lookupField(field_name)
            if index < 0:
                raise QgsProcessingException(tr(f"{what}: no field {field_name!r}"))
            number_fields.append((name, field_name, index))
            points.numbers[name] = []
    request = QgsFeatureRequest().setDestinationCrs(wgs84(), context.transformContext())
    if source.sourceCrs().isValid() and source.sourceCrs() != wgs84():
        crs = source.sourceCrs().authid() or source.sourceCrs().description()
        feedback.pushInfo(tr(f"{what}: reprojected from {crs} to EPSG:4326"))
    skipped = 0
    for i, feature in enumerate(source.getFeatures(request)):
        progress.step(i)
        attributes = feature.attributes()
        points.attributes.append(attributes)
        number = i + 1
        geometry = feature.geometry()
        xy = None
        if geometry is not None and not geometry.isNull() and not geometry.isEmpty():
            if QgsWkbTypes.isMultiType(geometry.wkbType()):
                parts = geometry.constGet()
                if parts.numGeometries() != 1:
                    raise QgsProcessingException(tr(
                        f"{what}: feature {number} is a multipoint of {parts.numGeometries()} points; geovor "
                        "takes one point per feature (Processing's 'Multipart to singleparts' splits them)"))
                part = parts.geometryN(0)
            else:
                part = geometry.constGet()
            xy = (part.x(), part.y())
            if not (math.isfinite(xy[0]) and math.isfinite(xy[1])):
                xy = None
        if xy is None:
            feedback.pushWarning(tr(f"{what}: feature {number} (FID {feature.id()}) has no point: left out"))
            skipped += 1
            continue
        values = []
        for name, field_name, index in number_fields:
            value = as_number(attributes[index])
            if value is None:
                break
            values.append(value)
        if len(values) < len(number_fields):
            field_name = number_fields[len(values)][1]
            feedback.pushWarning(tr(
                f"{what}: feature {number} (FID {feature.id()}): {field_name} is empty or not a number: left out"))
            skipped += 1
            continue
        for (name, _, _), value in zip(number_fields, values):
            points.numbers[name].append(value)
        points.used.append(i)
        points.lon.append(xy[0])
        points.lat.append(xy[1])
        points.point[i] = xy
        points.ids.append(points.id_of(i))
    progress.finish()
    if skipped:
        feedback.pushWarning(tr(f"{what}: {skipped} of {len(points.attributes)} features left out"))
    if not points.used and not allow_none:
        raise QgsProcessingException(tr(f"{what}: no feature has a usable point"))
    return points


def read_regions(source, context, feedback):
    """The polygons of `source` (any CRS) as a GeoDataFrame in EPSG:4326 with their attributes,
    for geovor.cells(clip=...); a feature without a polygon is left out with a warning naming it."""
    import geopandas as gpd
    from shapely import wkb

    request = QgsFeatureRequest().setDestinationCrs(wgs84(), context.transformContext())
    names = [field.name() for field in source.fields()]
    rows, shapes = [], []
    for i, feature in enumerate(source.getFeatures(request)):
        geometry = feature.geometry()
        if geometry is None or geometry.isNull() or geometry.isEmpty() or \
                QgsWkbTypes.geometryType(geometry.wkbType()) != QgsWkbTypes.PolygonGeometry:
            feedback.pushWarning(tr(f"regions: feature {i + 1} (FID {feature.id()}) has no polygon: left out"))
            continue
        rows.append([None if is_null(v) else v for v in feature.attributes()])
        shapes.append(wkb.loads(bytes(geometry.asWkb())))
    if not shapes:
        raise QgsProcessingException(tr("regions: no feature has a polygon"))
    return gpd.GeoDataFrame(rows, columns=names, geometry=shapes, crs="EPSG:4326")


def output_name(name, taken, prefix):
    """`name`, or prefix + name (repeated) while it equals, case-insensitively, a name in `taken`
    (lower case) or a reserved one; the result is added to `taken`."""
    while name.lower() in taken or name.lower() in RESERVED_NAMES:
        name = prefix + name
    taken.add(name.lower())
    return name


def _qgis_type(dtype):
    if dtype.kind in "iu":
        return QVariant.LongLong
    if dtype.kind == "f":
        return QVariant.Double
    if dtype.kind == "b":
        return QVariant.Bool
    return QVariant.String


def frame_columns(frame):
    """The package's own columns of `frame` (not the geometry nor ours) with their QGIS types."""
    geometry = frame.geometry.name
    return [(str(c), _qgis_type(frame[c].dtype)) for c in frame.columns if c != geometry and c not in HELPER_COLUMNS]


def carried_fields(source_fields, taken, prefix="src_"):
    """Copies of the layer's fields after the algorithm's own (renamed prefix + NAME where they clash)."""
    out = []
    for field in source_fields:
        copy = QgsField(field)
        copy.setName(output_name(field.name(), taken, prefix))
        out.append(copy)
    return out


def make_fields(own, carried=()):
    fields = QgsFields()
    for name, qtype in own:
        fields.append(QgsField(name, qtype))
    for field in carried:
        fields.append(field)
    return fields


def _python(values):
    """A column's values as QGIS attribute values (NaN and infinities are NULL)."""
    return [None if isinstance(v, float) and not math.isfinite(v) else v for v in values.tolist()]


def geometries(frame):
    """The frame's geometries as QgsGeometry (null for an empty one)."""
    out = []
    for wkb, empty in zip(frame.geometry.to_wkb().tolist(), frame.geometry.is_empty.tolist()):
        geometry = QgsGeometry()
        if wkb is not None and not empty:
            geometry.fromWkb(wkb)
        out.append(geometry)
    return out


def write_frame(sink, fields, frame, own, carried_attributes, progress):
    """The rows of `frame` as features: the `own` columns, then carried_attributes(row) (a list,
    for the carried fields) when given."""
    columns = [_python(frame[name]) for name, _ in own]
    shapes = geometries(frame)
    rows = frame[ROW].tolist() if carried_attributes is not None else None
    for i in range(len(frame)):
        progress.step(i)
        feature = QgsFeature(fields)
        attributes = [column[i] for column in columns]
        if rows is not None:
            attributes += carried_attributes(rows[i])
        feature.setAttributes(attributes)
        feature.setGeometry(shapes[i])
        if not sink.addFeature(feature, QgsFeatureSink.FastInsert):
            raise QgsProcessingException(tr(f"could not write feature {i + 1}: {sink.lastError()}"))
    progress.finish()


def report_merged(feedback, points, merged, what):
    """The package's merged pairs (input row, row merged into), as feature numbers."""
    for row, into in merged:
        a, b = points.used[row], points.used[into]
        feedback.pushInfo(tr(f"{what}: feature {a + 1} (id {points.ids[row]}) merged into the site of feature "
                             f"{b + 1} (id {points.ids[into]}): same position"))


def point_geometry(xy):
    return QgsGeometry() if xy is None else QgsGeometry.fromPointXY(QgsPointXY(xy[0], xy[1]))


# Parameters several algorithms share.
def densify_parameter():
    from qgis.core import QgsProcessingParameterDefinition, QgsProcessingParameterNumber

    p = QgsProcessingParameterNumber(
        "DENSIFY_M", tr("Largest distance between a written edge and the true great-circle arc (m)"),
        QgsProcessingParameterNumber.Double, 100.0, False, 1e-6)
    p.setFlags(p.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
    return p


def merge_parameter():
    from qgis.core import QgsProcessingParameterDefinition, QgsProcessingParameterNumber

    p = QgsProcessingParameterNumber(
        "MERGE_M", tr("Merge sites closer than (m; 0: only those closer than 0.38 m)"),
        QgsProcessingParameterNumber.Double, 0.0, False, 0.0)
    p.setFlags(p.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
    return p


def id_field_parameter(name="ID_FIELD", parent="INPUT", description=None):
    from qgis.core import QgsProcessingParameterField

    return QgsProcessingParameterField(
        name, description or tr("Site id field (default: id, icao, code or name)"),
        None, parent, QgsProcessingParameterField.Any, False, True)


def weight_field_parameter(name="WEIGHT_FIELD", parent="INPUT"):
    from qgis.core import QgsProcessingParameterField

    return QgsProcessingParameterField(
        name, tr("Weight field: radius in metres (power cells)"),
        None, parent, QgsProcessingParameterField.Numeric, False, True)


def optional_text(parameters, name, algorithm, context):
    """A field parameter's value, or None when it is not set."""
    value = algorithm.parameterAsString(parameters, name, context)
    return value or None


SITES_HELP = tr(
    "<p>Sites are the points of the input layer, in any CRS (reprojected to WGS84); the output is "
    "in EPSG:4326. A feature without a point, or whose weight (or capacity) is empty, is left out "
    "with a warning. Sites closer than 0.38 m (or Merge distance) are one site: the first feature's, "
    "listed in the log with the features merged into it.</p>"
    "<p>Site ids: the Site id field, else the first field named id, icao, code or name, else the "
    "feature number (1, 2, ...), as the geovor command does.</p>")
