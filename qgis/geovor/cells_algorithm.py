"""geovor:cells, the Voronoi (Thiessen) cell of every point on the Earth (geovor.cells)."""
from qgis.core import (
    QgsProcessing,
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
    carried_fields,
    densify_parameter,
    frame_columns,
    id_field_parameter,
    make_fields,
    merge_parameter,
    optional_text,
    read_points,
    read_regions,
    report_merged,
    threads,
    tr,
    weight_field_parameter,
    wgs84,
)


class CellsAlgorithm(GeovorAlgorithm):
    INPUT = "INPUT"
    ID_FIELD = "ID_FIELD"
    WEIGHT_FIELD = "WEIGHT_FIELD"
    CLIP = "CLIP"  # optional regions (polygons): the cells cut by them, with Thiessen weights
    OUTPUT = "OUTPUT"

    def name(self):
        return "cells"

    def displayName(self):  # noqa: N802
        return tr("Voronoi cells on the Earth")

    def tags(self):
        return tr("voronoi,thiessen,cells,polygons,sphere,geodesic,ellipsoid,proximal,nearest").split(",")

    def shortHelpString(self):  # noqa: N802
        return tr(
            "<p>The Voronoi (Thiessen) cell of every point: the part of the Earth closer to it than to any "
            "other point, on the sphere, not on a plane; exact on any input (points around a pole, across "
            "the antimeridian, on a great circle).</p>"
            "<p>One polygon per site, cut at +-180 degrees (MultiPolygons), with site_index, site_id, ids "
            "(the ids of every feature merged into the site, JSON), n_rows, area_m2 (on the WGS84 ellipsoid, "
            "of the polygon as written), area_sr (of the exact cell on the unit sphere), n_vertices, "
            "neighbors (the ids of the neighbouring sites, JSON), weight_m (with a weight field), then the "
            "site's fields (a field named like one of these, or fid, geom, ..., is written src_NAME).</p>"
            "<p>With a weight field (each site's radius in metres, 0 <= r < 10,007,557 m) the cells are power "
            "cells (geovor's docs/weighted.md); a site that a larger circle hides has an empty cell, listed "
            "as a warning. Edges are great-circle arcs, written with vertices close enough that no point "
            "of an edge is farther than the densify distance from the arc.</p>" + SITES_HELP +
            "<p>With <b>Clip to regions</b> (basins, districts, countries: polygons in any CRS), one feature per "
            "non-empty piece of a cell inside a region instead, with site_index, site_id, region_index (the "
            "region's feature number from 0), region_id, area_m2 (of the piece) and region_share (the piece's "
            "share of its region: the site's Thiessen weight there; a region's shares sum to 1), the region's "
            "fields as region_NAME, then the site's fields. The clip is GEOS's overlay in longitude/latitude, "
            "as QGIS draws the layers; an invalid region is repaired (a warning names it) and the sites whose "
            "cell meets no region are listed.</p>"
            "<p>The same cells as the command <code>geovor cells</code>.</p>")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.INPUT, tr("Sites (points)"), [QgsProcessing.TypeVectorPoint]))
        self.addParameter(id_field_parameter(self.ID_FIELD))
        self.addParameter(weight_field_parameter(self.WEIGHT_FIELD))
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.CLIP, tr("Clip to regions (polygons; optional: Thiessen weights)"),
            [QgsProcessing.TypeVectorPolygon], optional=True))
        self.addParameter(densify_parameter())
        self.addParameter(merge_parameter())
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, tr("Voronoi cells"), QgsProcessing.TypeVectorPolygon))

    def process(self, parameters, context, feedback):
        geovor = self.package()
        source = self.parameterAsSource(parameters, self.INPUT, context)
        if source is None:
            raise self.invalid_source(parameters, self.INPUT)
        weight_field = optional_text(parameters, self.WEIGHT_FIELD, self, context)
        points = read_points(source, context, feedback, Progress(feedback, 0, 20, source.featureCount()),
                             what=tr("sites"), id_field=optional_text(parameters, self.ID_FIELD, self, context),
                             numbers=[("weight", weight_field)])
        feedback.pushInfo(tr(f"{len(points.used)} points; site ids from {points.id_field or 'the feature numbers'}"))
        regions = self.parameterAsSource(parameters, self.CLIP, context) if parameters.get(self.CLIP) else None
        clip = read_regions(regions, context, feedback) if regions is not None else None
        feedback.setProgress(20)
        cells = self.call(
            feedback, geovor.cells, points.frame(), lat=LAT, lon=LON, ids=ID, weights=points.array("weight"),
            densify_m=self.parameterAsDouble(parameters, "DENSIFY_M", context),
            merge_m=self.parameterAsDouble(parameters, "MERGE_M", context), threads=threads(), points=points,
            **({"clip": clip} if clip is not None else {}))
        report_merged(feedback, points, cells.attrs.get("merged", []), tr("sites"))
        if clip is not None:
            outside = cells.attrs.get("outside", [])
            if outside:
                feedback.pushWarning(tr(f"{len(outside)} sites' cells meet no region (site_index: "
                                        f"{', '.join(map(str, outside[:20]))}{' ...' if len(outside) > 20 else ''})"))
        feedback.setProgress(70)

        own = frame_columns(cells)
        fields = make_fields(own, carried_fields(points.fields, {name.lower() for name, _ in own}))
        sink, dest_id = self.parameterAsSink(parameters, self.OUTPUT, context, fields,
                                             QgsWkbTypes.MultiPolygon, wgs84())
        if sink is None:
            raise self.invalid_sink(parameters, self.OUTPUT)
        self.write(sink, fields, cells, own, points, Progress(feedback, 70, 100, len(cells)))
        feedback.pushInfo(tr(f"{len(cells)} {'pieces' if clip is not None else 'cells'} written"))
        return {self.OUTPUT: dest_id}
