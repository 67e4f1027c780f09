"""The geovor QGIS plugin: a Processing provider (algorithms geovor:cells, geovor:delaunay,
geovor:nearest and geovor:balance) over the geovor Python package (docs/qgis.md).

QGIS imports this directory as the top-level module `geovor`, the name of the geovor Python
package too: library.py imports that package under another name (geovor_library).
"""


def classFactory(iface):  # noqa: N802 (QGIS's name)
    from .plugin import GeovorPlugin

    return GeovorPlugin(iface)
