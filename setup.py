"""Builds the extension `rtt._rtt` with the project's CMake build, for `pip install .`
(pyproject.toml). The module is configured for the interpreter pip runs (sys.executable), with
the library's options for a module: no command line, tests or benchmarks."""
import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(rtt VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        out = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        build = pathlib.Path(self.build_temp).resolve() / "cmake"
        build.mkdir(parents=True, exist_ok=True)
        config = [
            "cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
            "-DRTT_BUILD_APPS=OFF", "-DBUILD_TESTING=OFF", "-DRTT_WITH_PYTHON=ON",
            f"-DPython_EXECUTABLE={sys.executable}",
        ]
        config += os.environ.get("RTT_CMAKE_ARGS", "").split()
        subprocess.run(config, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 2))
        subprocess.run(["cmake", "--build", str(build), "--target", "_rtt", "-j", jobs], check=True)
        built = sorted((build / "python").glob("_rtt*.so"))
        if not built:
            raise RuntimeError("the CMake build made no _rtt module in " + str(build / "python"))
        out.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], out)


setup(
    version=project_version(),
    # Not build/: that is where the README's CMake build goes.
    options={"build": {"build_base": "build-python"}},
    ext_modules=[Extension("rtt._rtt", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
)
