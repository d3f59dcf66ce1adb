"""Builds the package hsbd's C extension (hsbd._hsbd) with the project's CMake build, so
that pip installs the same extension `make build` puts in build/python/hsbd.

The version comes from CMakeLists.txt's project(hsbd VERSION ...), the one the C library
and the command line print. The CMake build tree is build/python-pkg/cmake under this
directory (kept, so a second install compiles only what changed), or HSBD_BUILD_DIR: an
existing CMake build tree of this source (e.g. `HSBD_BUILD_DIR=build` after `make build`),
where only the extension's target is brought up to date.
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))


def project_version():
    with open(os.path.join(HERE, "CMakeLists.txt")) as f:
        m = re.search(r"project\(hsbd\s+VERSION\s+([0-9.]+)", f.read())
    if not m:
        sys.exit("setup.py: no project(hsbd VERSION ...) in CMakeLists.txt")
    return m.group(1)


class CMakeBuild(build_ext):
    """The extension is the CMake target hsbd_python (CMakeLists.txt)."""

    def build_extension(self, ext):
        build = os.environ.get("HSBD_BUILD_DIR")
        if build:
            build = os.path.abspath(build)
            if not os.path.exists(os.path.join(build, "CMakeCache.txt")):
                sys.exit(f"setup.py: HSBD_BUILD_DIR={build} is not a CMake build tree")
        else:
            build = os.path.join(HERE, "build", "python-pkg", "cmake")
            subprocess.run(["cmake", "-S", HERE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                            f"-DPython3_EXECUTABLE={sys.executable}"], check=True)
        jobs = os.environ.get("HSBD_JOBS", "2")
        subprocess.run(["cmake", "--build", build, "--target", "hsbd_python", "-j", jobs],
                       check=True)
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = os.path.join(build, "python", "hsbd", "_hsbd" + suffix)
        if not os.path.exists(built):
            sys.exit(f"setup.py: {built} was not built: the CMake tree {build} builds for "
                     f"another Python than {sys.executable} (extension suffix {suffix})")
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built, target)


os.makedirs(os.path.join(HERE, "build", "python-pkg"), exist_ok=True)
setup(version=project_version(),
      ext_modules=[Extension("hsbd._hsbd", sources=[])],
      cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": os.path.join("build", "python-pkg")},
               "egg_info": {"egg_base": os.path.join("build", "python-pkg")}})
