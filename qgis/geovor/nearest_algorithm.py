"""geovor:nearest, a join of every point of a layer to its nearest site (or k nearest) of another
(geovor.Index), as the command `geovor nearest` writes it."""
import math

from qgis.core import (
    QgsFeature,
    QgsFeatureSink,
    QgsProcessing,
    QgsProcessingException,
    QgsProcessingParameterEnum,
    QgsProcessingParameterFeatureSink,
    QgsProcessingParameterFeatureSource,
    QgsProcessingParameterField,
    QgsProcessingParameterNumber,
    QgsWkbTypes,
)
from qgis.PyQt.QtCore import QVariant

from .common import (
    QUERY_ID_NAMES,
    GeovorAlgorithm,
    Progress,
    carried_fields,
    id_field_parameter,
    make_fields,
    optional_text,
    point_geometry,
    read_points,
    report_merged,
    threads,
    tr,
    weight_field_parameter,
    wgs84,
)

METRICS = [
    (None, "automatic: great circle, or power for weighted sites"),
    ("sphere", "great circle on the sphere of mean radius 6,371,008.8 m"),
    ("geodesic", "WGS84 geodesic"),
    ("power", "power (weighted sites: the power cell holding the point)"),
]


class NearestAlgorithm(GeovorAlgorithm):
    INPUT = "INPUT"
    QUERY_ID_FIELD = "QUERY_ID_FIELD"
    SITES = "SITES"
    SITES_ID_FIELD = "SITES_ID_FIELD"
    SITES_WEIGHT_FIELD = "SITES_WEIGHT_FIELD"
    SITE_FIELDS = "SITE_FIELDS"
    K = "K"
    MAX_DISTANCE_M = "MAX_DISTANCE_M"
    METRIC = "METRIC"
    OUTPUT = "OUTPUT"

    def name(self):
        return "nearest"

    def displayName(self):  # noqa: N802
        return tr("Join to the nearest site on the Earth")

    def tags(self):
        return tr("nearest,neighbour,neighbor,knn,join,distance,hub,closest,sphere,geodesic").split(",")

    def shortHelpString(self):  # noqa: N802
        return tr(
            "<p>For every point of the input layer, the exact nearest site of the sites layer (or the k "
            "nearest, nearest first, ties to the lower site index), by the great-circle distance on the "
            "sphere or the WGS84 geodesic distance: not a planar distance in the layer's CRS.</p>"
            "<p>One point per (input point, site) pair at the input point, with query_id (the input's id "
            "field, else the first field named query_id, id, icao, code or name, else the feature number), "
            "rank (1 = nearest), site_index, site_id, distance_m, then the input point's fields (src_NAME on "
            "a clash), then the chosen site fields (site_NAME on a clash). A point with no site within the "
            "maximum distance, or without a usable point (no geometry), gets one feature with an empty match "
            "(and a null geometry for the latter).</p>"
            "<p>Sites are read as for Voronoi cells on the Earth (in any CRS; sites closer than 0.38 m are one "
            "site). With a weight field (radii in metres) the answer is the site whose power cell holds the "
            "point, the cell 'Voronoi cells on the Earth' draws with that weight field (metric power); "
            "distance_m stays the great-circle distance to the site.</p>"
            "<p>The same rows as the command <code>geovor nearest --k K</code>.</p>")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.INPUT, tr("Input points"), [QgsProcessing.TypeVectorPoint]))
        self.addParameter(id_field_parameter(
            self.QUERY_ID_FIELD, self.INPUT,
            tr("Input id field (default: query_id, id, icao, code or name)")))
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.SITES, tr("Sites (points)"), [QgsProcessing.TypeVectorPoint]))
        self.addParameter(id_field_parameter(self.SITES_ID_FIELD, self.SITES))
        self.addParameter(QgsProcessingParameterField(
            self.SITE_FIELDS, tr("Site fields to add"), None, self.SITES, QgsProcessingParameterField.Any, True, True))
        self.addParameter(QgsProcessingParameterNumber(
            self.K, tr("Number of nearest sites (k)"), QgsProcessingParameterNumber.Integer, 1, False, 1))
        self.addParameter(QgsProcessingParameterNumber(
            self.MAX_DISTANCE_M, tr("Maximum distance (m)"), QgsProcessingParameterNumber.Double,
            None, True, 0.0))
        self.addParameter(QgsProcessingParameterEnum(
            self.METRIC, tr("Distance"), [tr(text) for _, text in METRICS], False, 0))
        self.addParameter(weight_field_parameter(self.SITES_WEIGHT_FIELD, self.SITES))
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, tr("Joined points"), QgsProcessing.TypeVectorPoint))

    def process(self, parameters, context, feedback):
        geovor = self.package()
        import numpy as np

        sites_source = self.parameterAsSource(parameters, self.SITES, context)
        if sites_source is None:
            raise self.invalid_source(parameters, self.SITES)
        queries_source = self.parameterAsSource(parameters, self.INPUT, context)
        if queries_source is None:
            raise self.invalid_source(parameters, self.INPUT)
        k = self.parameterAsInt(parameters, self.K, context)
        max_distance = None
        if parameters.get(self.MAX_DISTANCE_M) not in (None, ""):
            max_distance = self.parameterAsDouble(parameters, self.MAX_DISTANCE_M, context)
        metric = METRICS[self.parameterAsEnum(parameters, self.METRIC, context)][0]

        sites = read_points(sites_source, context, feedback, Progress(feedback, 0, 15, sites_source.featureCount()),
                            what=tr("sites"), id_field=optional_text(parameters, self.SITES_ID_FIELD, self, context),
                            numbers=[("weight", optional_text(parameters, self.SITES_WEIGHT_FIELD, self, context))])
        feedback.pushInfo(tr(f"{len(sites.used)} site points; site ids from {sites.id_field or 'the feature numbers'}"))
        index = self.call(feedback, geovor.Index, np.asarray(sites.lat), np.asarray(sites.lon), sites.ids,
                          weights=sites.array("weight"), points=sites)
        table = index.sites()
        first_rows = table["first_row"].tolist()
        merged = [(row, first_rows[site]) for site, rows in enumerate(table["rows"].tolist())
                  for row in rows if row != first_rows[site]]
        report_merged(feedback, sites, merged, tr("sites"))
        site_ids = table["id"].tolist()
        site_layer_rows = [sites.used[row] for row in first_rows]
        feedback.setProgress(25)

        queries = read_points(queries_source, context, feedback,
                              Progress(feedback, 25, 45, queries_source.featureCount()), what=tr("input"),
                              id_field=optional_text(parameters, self.QUERY_ID_FIELD, self, context),
                              id_names=QUERY_ID_NAMES, allow_none=True)
        feedback.setProgress(45)
        if queries.used:
            found, distance = self.call(feedback, index.nearest, np.asarray(queries.lat), np.asarray(queries.lon), k=k,
                                        metric=metric, max_distance_m=max_distance, threads=threads(),
                                        points=queries)
            found = np.asarray(found).reshape(len(queries.used), -1).tolist()
            distance = np.asarray(distance).reshape(len(queries.used), -1).tolist()
        else:
            found = distance = []
        feedback.setProgress(60)

        # Fields: ours, the query's (src_NAME on a clash), the chosen sites' (site_NAME on a clash).
        own = [("query_id", QVariant.String), ("rank", QVariant.Int), ("site_index", QVariant.LongLong),
               ("site_id", QVariant.String), ("distance_m", QVariant.Double)]
        taken = {name for name, _ in own}
        query_fields = carried_fields(queries.fields, taken)
        chosen = self.parameterAsFields(parameters, self.SITE_FIELDS, context)
        site_field_index = []
        for name in chosen:
            i = sites.fields.lookupField(name)
            if i < 0:
                raise QgsProcessingException(tr(f"sites: no field {name!r}"))
            site_field_index.append(i)
        site_fields = carried_fields([sites.fields[i] for i in site_field_index], taken, "site_")
        fields = make_fields(own, query_fields + site_fields)
        sink, dest_id = self.parameterAsSink(parameters, self.OUTPUT, context, fields, QgsWkbTypes.Point, wgs84())
        if sink is None:
            raise self.invalid_sink(parameters, self.OUTPUT)

        progress = Progress(feedback, 60, 100, len(queries.attributes))
        answer = {row: j for j, row in enumerate(queries.used)}
        no_site = [None] * len(site_fields)
        written = unmatched = 0
        for row, attributes in enumerate(queries.attributes):
            progress.step(row)
            j = answer.get(row)
            matches = []
            if j is not None:
                matches = [(rank, s, d) for rank, (s, d) in enumerate(zip(found[j], distance[j]), 1)
                           if s >= 0 and math.isfinite(d)]
            query_id = queries.id_of(row)
            geometry = point_geometry(queries.point.get(row))
            if not matches:
                unmatched += 1
                matches = [(None, None, None)]
            for rank, s, d in matches:
                feature = QgsFeature(fields)
                if s is None:
                    values = [query_id, None, None, None, None] + attributes + no_site
                else:
                    site_attributes = sites.attributes[site_layer_rows[s]]
                    values = ([query_id, rank, s, site_ids[s], d] + attributes +
                              [site_attributes[i] for i in site_field_index])
                feature.setAttributes(values)
                feature.setGeometry(geometry)
                if not sink.addFeature(feature, QgsFeatureSink.FastInsert):
                    raise QgsProcessingException(tr(f"could not write feature {written + 1}: {sink.lastError()}"))
                written += 1
        progress.finish()
        feedback.pushInfo(tr(f"{len(queries.attributes)} input points, {written} features written"
                             + (f", {unmatched} without a site" if unmatched else "")))
        return {self.OUTPUT: dest_id}

