"""geovor:delaunay, the Delaunay triangles (and edges) of points on the Earth (geovor.delaunay)."""
from qgis.core import (
    QgsProcessing,
    QgsProcessingParameterBoolean,
    QgsProcessingParameterFeatureSink,
    QgsProcessingParameterFeatureSource,
    QgsWkbTypes,
)

from .common import (
    ID,
    LAT,
    LON,
    SITES_HELP,
    GeovorAlgorithm,
    Progress,
    densify_parameter,
    frame_columns,
    id_field_parameter,
    make_fields,
    merge_parameter,
    optional_text,
    read_points,
    report_merged,
    tr,
    weight_field_parameter,
    wgs84,
    write_frame,
)


class DelaunayAlgorithm(GeovorAlgorithm):
    INPUT = "INPUT"
    ID_FIELD = "ID_FIELD"
    WEIGHT_FIELD = "WEIGHT_FIELD"
    NO_GHOSTS = "NO_GHOSTS"
    OUTPUT = "OUTPUT"
    EDGES = "EDGES"

    def name(self):
        return "delaunay"

    def displayName(self):  # noqa: N802
        return tr("Delaunay triangulation on the Earth")

    def tags(self):
        return tr("delaunay,triangulation,tin,triangles,edges,sphere,geodesic").split(",")

    def shortHelpString(self):  # noqa: N802
        return tr(
            "<p>The Delaunay triangulation of the points on the sphere (the dual of the Voronoi cells): "
            "triangles whose edges are great-circle arcs, tiling the whole Earth, exact on any input.</p>"
            "<p>Triangles (MultiPolygons, cut at +-180 degrees) carry tri_index, kind (proper, ghost or "
            "great_circle), ghost (1 for a face outside the triangulation of the sites' convex hull, which "
            "exists only when all sites lie in one hemisphere), site_a/b/c (site indices, "
            "counter-clockwise), id_a/b/c, area_m2 (WGS84 ellipsoid, of the polygon as written), area_sr "
            "(sphere) and circumradius_m. 'Leave out ghost faces' keeps only the triangles that tile the "
            "sites' convex hull.</p>"
            "<p>Edges (optional output, MultiLineStrings) carry edge_index, site_a, site_b, id_a, id_b, "
            "length_m (great circle on the sphere of radius 6,371,008.8 m), geodesic_m (WGS84), hull and "
            "ghost.</p>"
            "<p>With a weight field (radii in metres) the triangulation is the regular (weighted) one; a "
            "hidden site is no vertex of it.</p>" + SITES_HELP +
            "<p>The same triangles as the command <code>geovor delaunay</code> (-o) and edges as its "
            "--edges.</p>")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.INPUT, tr("Sites (points)"), [QgsProcessing.TypeVectorPoint]))
        self.addParameter(id_field_parameter(self.ID_FIELD))
        self.addParameter(weight_field_parameter(self.WEIGHT_FIELD))
        self.addParameter(QgsProcessingParameterBoolean(
            self.NO_GHOSTS, tr("Leave out ghost faces and edges (sites in one hemisphere)"), False))
        self.addParameter(densify_parameter())
        self.addParameter(merge_parameter())
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, tr("Delaunay triangles"), QgsProcessing.TypeVectorPolygon))
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.EDGES, tr("Delaunay edges"), QgsProcessing.TypeVectorLine, None, True, False))

    def process(self, parameters, context, feedback):
        geovor = self.package()
        source = self.parameterAsSource(parameters, self.INPUT, context)
        if source is None:
            raise self.invalid_source(parameters, self.INPUT)
        points = read_points(source, context, feedback, Progress(feedback, 0, 20, source.featureCount()),
                             what=tr("sites"), id_field=optional_text(parameters, self.ID_FIELD, self, context),
                             numbers=[("weight", optional_text(parameters, self.WEIGHT_FIELD, self, context))])
        feedback.pushInfo(tr(f"{len(points.used)} points; site ids from {points.id_field or 'the feature numbers'}"))
        feedback.setProgress(20)
        triangles, edges = self.call(
            feedback, geovor.delaunay, points.frame(), lat=LAT, lon=LON, ids=ID, weights=points.array("weight"),
            densify_m=self.parameterAsDouble(parameters, "DENSIFY_M", context),
            no_ghosts=self.parameterAsBoolean(parameters, self.NO_GHOSTS, context),
            merge_m=self.parameterAsDouble(parameters, "MERGE_M", context), points=points)
        report_merged(feedback, points, triangles.attrs.get("merged", []), tr("sites"))
        feedback.setProgress(70)

        results = {}
        want_edges = parameters.get(self.EDGES) is not None
        outputs = [(self.OUTPUT, triangles, QgsWkbTypes.MultiPolygon, 70, 90 if want_edges else 100)]
        if want_edges:
            outputs.append((self.EDGES, edges, QgsWkbTypes.MultiLineString, 90, 100))
        for name, frame, geometry_type, start, end in outputs:
            own = frame_columns(frame)
            fields = make_fields(own)
            sink, dest_id = self.parameterAsSink(parameters, name, context, fields, geometry_type, wgs84())
            if sink is None:
                if name == self.EDGES:
                    continue  # not asked for
                raise self.invalid_sink(parameters, name)
            write_frame(sink, fields, frame, own, None, Progress(feedback, start, end, len(frame)))
            feedback.pushInfo(tr(f"{len(frame)} {'triangles' if name == self.OUTPUT else 'edges'} written"))
            results[name] = dest_id
        return results
