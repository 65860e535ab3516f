"""Builds the matlas Python package with the project's CMake (the `_matlas` target only).

    python3 -m venv --system-site-packages .venv      # Debian's numpy and setuptools inside
    .venv/bin/pip install --no-build-isolation .       # no package index is contacted

MATLAS_CMAKE_ARGS adds arguments to the CMake configuration (e.g. -DMATLAS_NATIVE=ON).
"""
import os
import pathlib
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = pathlib.Path(self.build_temp).resolve() / "cmake"
        build_dir.mkdir(parents=True, exist_ok=True)
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
            "-DMATLAS_BUILD_TESTS=OFF", "-DMATLAS_BUILD_BENCH=OFF", "-DMATLAS_PYTHON=ON",
            f"-DPython_EXECUTABLE={sys.executable}",
        ] + shlex.split(os.environ.get("MATLAS_CMAKE_ARGS", ""))
        if shutil.which("ninja"):
            configure += ["-G", "Ninja"]
        subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "_matlas", "-j", str(os.cpu_count() or 2)],
                       check=True)
        package = build_dir / "python" / "matlas"
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).parent
        target.mkdir(parents=True, exist_ok=True)
        for f in package.iterdir():
            if f.is_file():
                shutil.copy2(f, target / f.name)


setup(
    packages=["matlas"],
    package_dir={"matlas": "python/matlas"},
    package_data={"matlas": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("matlas._matlas", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
