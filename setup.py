"""The CMake build step of `pip install .` (pyproject.toml).

setuptools' build_ext runs CMake on this source tree (Release, for the
interpreter that runs pip) in its build directory, builds the one target
nrsfm_python (the libraries it links and the pybind11 module, nothing else)
and copies the module where setuptools packs it. It needs what the README's
set-up command installs (CMake, a C++ compiler, Ceres, Eigen, glog, gflags,
matio, nlohmann-json, qhull, pybind11, python3-dev, numpy, libjs-three) and
downloads nothing. CMAKE_BUILD_PARALLEL_LEVEL sets the compile jobs (default:
one per CPU); NRSFM_CMAKE_ARGS adds CMake options (space-separated).
NRSFM_PIP_CMAKE_BUILD_DIR names an existing, configured CMake build tree of
this source (e.g. build/ of the README's commands, made for the same
interpreter) to build the target in instead of a new one, so that nothing is
compiled twice; .ci/run uses it (docs/python.md).
"""
import glob
import os
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = os.path.dirname(os.path.abspath(__file__))


def project_version():
    """The VERSION of project(nrsfm ...) in CMakeLists.txt."""
    with open(os.path.join(SOURCE, "CMakeLists.txt"), encoding="utf-8") as cmake:
        match = re.search(r"project\(nrsfm\s+VERSION\s+([0-9.]+)", cmake.read())
    if match is None:
        raise RuntimeError("CMakeLists.txt: no project(nrsfm VERSION x.y.z)")
    return match.group(1)


class CMakeBuild(build_ext):
    """Builds the module with CMake instead of compiling sources itself."""

    def build_extension(self, ext):
        reuse = os.environ.get("NRSFM_PIP_CMAKE_BUILD_DIR", "")
        build = (os.path.abspath(reuse) if reuse
                 else os.path.join(os.path.abspath(self.build_temp), "cmake"))
        if reuse and not os.path.isfile(os.path.join(build, "CMakeCache.txt")):
            raise RuntimeError("NRSFM_PIP_CMAKE_BUILD_DIR=%s is not a configured CMake build tree"
                               % reuse)
        configure = [
            "cmake", "-S", SOURCE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
            "-DPython3_EXECUTABLE=" + sys.executable, "-DNRSFM_BUILD_PYTHON=ON",
            "-DNRSFM_BUILD_TESTS=OFF", "-DNRSFM_BUILD_BENCH=OFF", "-DNRSFM_BUILD_MATLAB=OFF",
        ] + os.environ.get("NRSFM_CMAKE_ARGS", "").split()
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        if not reuse:
            subprocess.check_call(configure)
        subprocess.check_call(["cmake", "--build", build, "--target", "nrsfm_python",
                               "-j", jobs])
        built = glob.glob(os.path.join(build, "python", "nrsfm*.so"))
        if len(built) != 1:
            raise RuntimeError("the CMake build made %d modules nrsfm*.so in %s/python"
                               % (len(built), build))
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built[0], target)


setup(
    version=project_version(),
    ext_modules=[Extension("nrsfm", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    # The one extension module; the source folders are not Python packages.
    packages=[],
    py_modules=[],
    # setuptools' build directory, apart from a CMake build in build/.
    options={"build": {"build_base": "build-pip"}},
)
