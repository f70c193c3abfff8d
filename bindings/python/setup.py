"""Puts the built library into the package, so that `pip install bindings/python` after the CMake
build gives a package that needs nothing else. The library is taken from SSCAPE_LIBRARY, or from
the build folder of this checkout: libsscape_offline (the runtime with the offline tools that
sscape.pipeline needs) where the build made it, else libsscape (the runtime alone)."""
import os
import shutil
from pathlib import Path

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent


def built_library():
    env = os.environ.get("SSCAPE_LIBRARY")
    build = HERE.parents[1] / "build" / "sdk"
    candidates = [Path(env)] if env else [build / "libsscape_offline.so.0", build / "libsscape.so.0"]
    for path in candidates:
        if path.is_file():
            return path
    raise SystemExit("sscape: libsscape not found (looked at " + ", ".join(map(str, candidates)) +
                     "): build it first (./setup.sh) or set SSCAPE_LIBRARY to its path")


class BuildWithLibrary(build_py):
    def run(self):
        super().run()
        library = built_library()
        name = "libsscape_offline.so" if "sscape_offline" in library.name else "libsscape.so"
        shutil.copyfile(library, Path(self.build_lib) / "sscape" / name)


class BinaryDistribution(Distribution):
    """The wheel holds a native library: tag it for this platform."""

    def has_ext_modules(self):
        return True


setup(cmdclass={"build_py": BuildWithLibrary}, distclass=BinaryDistribution)
