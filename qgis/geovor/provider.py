"""The geovor Processing provider: id `geovor`, one algorithm per module."""
from qgis.core import QgsProcessingProvider

from . import library
from .balance_algorithm import BalanceAlgorithm
from .cells_algorithm import CellsAlgorithm
from .delaunay_algorithm import DelaunayAlgorithm
from .nearest_algorithm import NearestAlgorithm


class GeovorProvider(QgsProcessingProvider):
    def id(self):
        return "geovor"

    def name(self):
        return "geovor"

    def longName(self):  # noqa: N802
        return "geovor: Voronoi cells, Delaunay triangles and nearest sites on the Earth"

    def versionInfo(self):  # noqa: N802
        return "0.1.0"

    def loadAlgorithms(self):  # noqa: N802
        for algorithm in (CellsAlgorithm(), DelaunayAlgorithm(), NearestAlgorithm(), BalanceAlgorithm()):
            self.addAlgorithm(algorithm)

    def canBeActivated(self):  # noqa: N802
        return True

    def warningMessage(self):  # noqa: N802
        # Shown in the toolbox when the geovor package cannot be imported; the algorithms say
        # so too when run (library.load()).
        error = library.import_error()
        return "" if error is None else f"geovor: {error}"
