"""The plugin object QGIS holds: it adds the Processing provider (qgis_process calls
initProcessing only; the desktop calls it and then initGui)."""
from qgis.core import QgsApplication

from .provider import GeovorProvider


class GeovorPlugin:
    def __init__(self, iface):
        self.iface = iface  # None under qgis_process
        self.provider = None

    def initProcessing(self):  # noqa: N802 (QGIS's name)
        if self.provider is None:
            self.provider = GeovorProvider()
            QgsApplication.processingRegistry().addProvider(self.provider)

    def initGui(self):  # noqa: N802
        self.initProcessing()

    def unload(self):
        if self.provider is not None:
            QgsApplication.processingRegistry().removeProvider(self.provider)
            self.provider = None
