"""Builds the cdkit extension with the project's CMake for `pip install --no-build-isolation .` (pyproject.toml).

The CMake tree is build-pip/ in the source directory (CDKIT_PIP_BUILD_DIR names another, e.g. an existing build tree
to reuse its objects; ignored by git like every build-*/), and setuptools' own files go under it, so that they never
mix with the project's build/. Only the library and the module are built (the tree is configured without tests,
benchmarks and examples); CDKIT_PIP_JOBS sets the parallel jobs (default: all cores).
"""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent
WORK = pathlib.Path(os.environ.get("CDKIT_PIP_BUILD_DIR", ROOT / "build-pip")).resolve()


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        tree = WORK
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(tree), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                        "-DCDKIT_BUILD_TESTS=OFF", "-DCDKIT_BUILD_BENCHMARKS=OFF", "-DCDKIT_BUILD_EXAMPLES=OFF",
                        "-DCDKIT_BUILD_PYTHON=ON", f"-DPython_EXECUTABLE={sys.executable}"], check=True)
        jobs = os.environ.get("CDKIT_PIP_JOBS", str(os.cpu_count() or 2))
        subprocess.run(["cmake", "--build", str(tree), "--target", "_cdkit", "-j", jobs], check=True)
        built = tree / "python" / "cdkit"
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).parent
        target.mkdir(parents=True, exist_ok=True)
        for f in built.iterdir():
            if f.is_file():
                shutil.copy2(f, target / f.name)


(WORK / "pip-egg").mkdir(parents=True, exist_ok=True)
setup(
    packages=["cdkit"],
    package_dir={"cdkit": "python/cdkit"},
    package_data={"cdkit": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("cdkit._cdkit", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(WORK / "pip-setuptools")}, "egg_info": {"egg_base": str(WORK / "pip-egg")}},
    zip_safe=False,
)
