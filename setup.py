"""Builds geovor._geovor with the project's CMake (python/CMakeLists.txt) for
`pip install --no-build-isolation .`.

The build directory is $GEOVOR_CMAKE_BUILD_DIR when set (scripts/test.sh points it at the release
build, which already has the library), else build-python/ in the checkout; either way later installs
rebuild only what changed.
"""
import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = Path(os.environ.get("GEOVOR_CMAKE_BUILD_DIR", ROOT / "build-python")).resolve()
        configure = ["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DGEOVOR_BUILD_PYTHON=ON",
                     f"-DPython_EXECUTABLE={sys.executable}"]
        if not (build_dir / "CMakeCache.txt").exists():
            configure += ["-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release", "-DGEOVOR_BUILD_TESTS=OFF",
                          "-DGEOVOR_BUILD_BENCH=OFF"]
        print(f"geovor: building the extension module with CMake in {build_dir}", flush=True)
        subprocess.run(configure, check=True, stdout=subprocess.DEVNULL)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "_geovor"], check=True)
        built = next((build_dir / "python" / "geovor").glob("_geovor*.so"))
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built, target)


setup(ext_modules=[CMakeExtension("geovor._geovor")], cmdclass={"build_ext": CMakeBuild})
