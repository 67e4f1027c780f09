"""Finds and imports the geovor Python package for the algorithms.

QGIS imports this plugin as the top-level module `geovor`, which is also the Python package's
name, so `import geovor` would give the plugin back. The package is therefore looked up as a
directory `geovor` holding `__init__.py` and the extension module `_geovor` (so never this
plugin), in each directory of $GEOVOR_PYTHONPATH (separated by os.pathsep, searched first) and
then of sys.path (where `pip install` puts it), and imported under the name `geovor_library`.
"""
import importlib.machinery
import importlib.util
import os
import sys
from pathlib import Path

MODULE_NAME = "geovor_library"
_PLUGIN_DIR = Path(__file__).resolve().parent


def search_path():
    """The directories searched for the package, in order."""
    extra = [p for p in os.environ.get("GEOVOR_PYTHONPATH", "").split(os.pathsep) if p]
    return extra + [p for p in sys.path if isinstance(p, str)]


def find():
    """The directory of the geovor package (a Path), or None."""
    for entry in search_path():
        package = Path(entry or ".") / "geovor"
        try:
            if not (package / "__init__.py").is_file() or package.resolve() == _PLUGIN_DIR:
                continue
        except OSError:
            continue
        if any((package / f"_geovor{suffix}").is_file() for suffix in importlib.machinery.EXTENSION_SUFFIXES):
            return package
    return None


def load():
    """The geovor package, imported once. ImportError says where it was looked for, or why it
    could not be imported."""
    module = sys.modules.get(MODULE_NAME)
    if module is not None:
        return module
    package = find()
    if package is None:
        raise ImportError(
            "the geovor Python package (a directory geovor/ with its extension module _geovor) is in no "
            "directory of GEOVOR_PYTHONPATH nor of QGIS's Python path: install it into the Python that QGIS "
            "runs (pip install <geovor sources>) or set GEOVOR_PYTHONPATH to the directory holding it "
            "(docs/qgis.md)")
    spec = importlib.util.spec_from_file_location(MODULE_NAME, package / "__init__.py",
                                                  submodule_search_locations=[str(package)])
    module = importlib.util.module_from_spec(spec)
    sys.modules[MODULE_NAME] = module
    try:
        spec.loader.exec_module(module)
    except BaseException as error:
        for name in [n for n in sys.modules if n == MODULE_NAME or n.startswith(MODULE_NAME + ".")]:
            del sys.modules[name]
        if isinstance(error, ImportError):
            raise ImportError(f"the geovor Python package in {package} cannot be imported: {error}") from error
        raise
    return module


def import_error():
    """None when the package imports, else the reason (text)."""
    try:
        load()
    except ImportError as error:
        return str(error)
    return None
