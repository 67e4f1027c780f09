"""geovor:balance, power cells of given shares of the Earth's area (geovor.balance)."""
from qgis.core import (
    QgsProcessing,
    QgsProcessingParameterDefinition,
    QgsProcessingParameterFeatureSink,
    QgsProcessingParameterFeatureSource,
    QgsProcessingParameterField,
    QgsProcessingParameterNumber,
    QgsWkbTypes,
)

from .common import (
    ID,
    LAT,
    LON,
    SITES_HELP,
    GeovorAlgorithm,
    Progress,
    carried_fields,
    densify_parameter,
    frame_columns,
    id_field_parameter,
    make_fields,
    merge_parameter,
    optional_text,
    read_points,
    report_merged,
    threads,
    tr,
    wgs84,
)


class BalanceAlgorithm(GeovorAlgorithm):
    INPUT = "INPUT"
    ID_FIELD = "ID_FIELD"
    CAPACITY = "CAPACITY"
    TOLERANCE = "TOLERANCE"
    MAX_ITERATIONS = "MAX_ITERATIONS"
    OUTPUT = "OUTPUT"

    def name(self):
        return "balance"

    def displayName(self):  # noqa: N802
        return tr("Balanced territories on the Earth")

    def tags(self):
        return tr("balance,territories,capacity,power,weighted,voronoi,optimal transport,equal area").split(",")

    def shortHelpString(self):  # noqa: N802
        return tr(
            "<p>Territories of given sizes: the radius of every site for which its power cell (a weighted "
            "Voronoi cell) covers its share of the Earth's area on the WGS84 ellipsoid, equal shares "
            "without a capacity field, else capacity / sum of capacities. Solved by damped Newton on the "
            "exact cells (semi-discrete optimal transport; geovor's docs/weighted.md); each iteration's "
            "largest relative area error is logged. Features merged into one site pool their capacities; "
            "a capacity must be positive.</p>"
            "<p>The cells carry the fields of Voronoi cells on the Earth with a weight field (weight_m: the "
            "radius found, the smallest is 0), then target_m2 (the cell's target area; area_m2 is that of "
            "the polygon as written, within the densification of it), then the site's fields.</p>"
            "<p>Fails when the tolerance is not reached in the given iterations (sites all in one "
            "hemisphere: some region is then more than 90 degrees from every site).</p>" + SITES_HELP +
            "<p>The same cells as the command <code>geovor balance</code>.</p>")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.INPUT, tr("Sites (points)"), [QgsProcessing.TypeVectorPoint]))
        self.addParameter(id_field_parameter(self.ID_FIELD))
        self.addParameter(QgsProcessingParameterField(
            self.CAPACITY, tr("Capacity field (positive; default: equal shares)"), None, self.INPUT,
            QgsProcessingParameterField.Numeric, False, True))
        tolerance = QgsProcessingParameterNumber(
            self.TOLERANCE, tr("Largest relative area error |area - target| / target"),
            QgsProcessingParameterNumber.Double, 1e-6, False, 1e-15)
        tolerance.setFlags(tolerance.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
        self.addParameter(tolerance)
        iterations = QgsProcessingParameterNumber(
            self.MAX_ITERATIONS, tr("Newton iterations at most"), QgsProcessingParameterNumber.Integer, 50, False, 0)
        iterations.setFlags(iterations.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
        self.addParameter(iterations)
        self.addParameter(densify_parameter())
        self.addParameter(merge_parameter())
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, tr("Balanced cells"), QgsProcessing.TypeVectorPolygon))

    def process(self, parameters, context, feedback):
        geovor = self.package()
        source = self.parameterAsSource(parameters, self.INPUT, context)
        if source is None:
            raise self.invalid_source(parameters, self.INPUT)
        points = read_points(source, context, feedback, Progress(feedback, 0, 20, source.featureCount()),
                             what=tr("sites"), id_field=optional_text(parameters, self.ID_FIELD, self, context),
                             numbers=[("capacity", optional_text(parameters, self.CAPACITY, self, context))])
        feedback.pushInfo(tr(f"{len(points.used)} points; site ids from {points.id_field or 'the feature numbers'}"))
        feedback.setProgress(20)
        cells = self.call(
            feedback, geovor.balance, points.frame(), lat=LAT, lon=LON, ids=ID, capacity=points.array("capacity"),
            tolerance=self.parameterAsDouble(parameters, self.TOLERANCE, context),
            max_iterations=self.parameterAsInt(parameters, self.MAX_ITERATIONS, context),
            densify_m=self.parameterAsDouble(parameters, "DENSIFY_M", context),
            merge_m=self.parameterAsDouble(parameters, "MERGE_M", context), threads=threads(),
            points=points)
        report_merged(feedback, points, cells.attrs.get("merged", []), tr("sites"))
        for i, (error, step) in enumerate(cells.attrs.get("iterations", []), 1):
            feedback.pushInfo(tr(f"iteration {i}: largest relative area error {error:.3g}, step {step:g}"))
        feedback.setProgress(70)

        own = frame_columns(cells)
        fields = make_fields(own, carried_fields(points.fields, {name.lower() for name, _ in own}))
        sink, dest_id = self.parameterAsSink(parameters, self.OUTPUT, context, fields,
                                             QgsWkbTypes.MultiPolygon, wgs84())
        if sink is None:
            raise self.invalid_sink(parameters, self.OUTPUT)
        self.write(sink, fields, cells, own, points, Progress(feedback, 70, 100, len(cells)))
        feedback.pushInfo(tr(f"{len(cells)} cells written"))
        return {self.OUTPUT: dest_id}
