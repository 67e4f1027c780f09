"""Pictures of the QGIS plugin for docs/qgis.md, drawn headless (QT_QPA_PLATFORM=offscreen):
the Processing toolbox's geovor algorithms and the dialog of geovor:cells with the bundled
stations loaded.

Usage, from the repository root, with the geovor package built (docs/qgis.md):
  GEOVOR_PYTHONPATH=build/python-venv/lib/python3.11/site-packages QT_QPA_PLATFORM=offscreen \\
    /usr/bin/python3 scripts/render_qgis_toolbox.py [OUT_DIR]    (default docs/img)
writes OUT_DIR/qgis_toolbox.png and OUT_DIR/qgis_cells_dialog.png. QGIS's settings go to a
temporary HOME.
"""
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else ROOT / "docs" / "img")
    os.environ["HOME"] = tempfile.mkdtemp(prefix="geovor-qgis-")
    from qgis.core import QgsApplication, QgsProject, QgsVectorLayer
    from qgis.PyQt.QtCore import QSize

    app = QgsApplication([], True)
    app.initQgis()
    sys.path.insert(0, "/usr/share/qgis/python/plugins")
    from processing.core.Processing import Processing

    Processing.initialize()
    sys.path.insert(0, str(ROOT / "qgis"))
    import geovor  # the plugin (qgis/geovor)

    plugin = geovor.classFactory(None)
    plugin.initProcessing()

    from qgis.gui import QgsProcessingToolboxTreeView

    view = QgsProcessingToolboxTreeView(None, QgsApplication.processingRegistry())
    view.setHeaderHidden(True)
    view.setFilterString("on the Earth")
    view.expandAll()
    view.resize(QSize(400, 120))
    view.show()
    app.processEvents()
    view.grab().save(str(out / "qgis_toolbox.png"))

    uri = (f"file://{ROOT / 'datasets' / 'weather_stations.csv'}?type=csv&xField=lon_deg&yField=lat_deg"
           "&crs=EPSG:4326")
    stations = QgsVectorLayer(uri, "weather_stations", "delimitedtext")
    assert stations.isValid(), uri
    QgsProject.instance().addMapLayer(stations)
    from processing.gui.AlgorithmDialog import AlgorithmDialog

    dialog = AlgorithmDialog(QgsApplication.processingRegistry().createAlgorithmById("geovor:cells"))
    dialog.resize(QSize(860, 560))
    dialog.show()
    app.processEvents()
    dialog.grab().save(str(out / "qgis_cells_dialog.png"))
    print(f"wrote {out / 'qgis_toolbox.png'} and {out / 'qgis_cells_dialog.png'}")
    plugin.unload()
    app.exitQgis()


if __name__ == "__main__":
    main()
