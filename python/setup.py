"""Builds the _cw4d extension with the project's own CMake (the checkout one level up) and
packages it with cw4d/*.py. Driven by pip (PEP 517, setuptools backend):

    pip install --no-build-isolation ./python

CMake configures a Release build of the libraries and the module for the interpreter running
pip (CW4D_BUILD_PYTHON=ON, no tests, benchmarks or CLI) in build-pip/ of the checkout and
builds only the target cw4d_python; ccache (when installed) reuses what an earlier build of the
same checkout compiled. CW4D_JOBS sets the parallel jobs (default 2).

CW4D_PREBUILT=DIR skips CMake and packages the module an earlier build made in DIR (a CMake
build directory of this checkout with the Python module, e.g. build/ after ./setup.sh):

    CW4D_PREBUILT=$PWD/build pip install --no-build-isolation --no-index ./python

It must have been built for the interpreter running pip (its file name carries the ABI tag)."""

import os
import pathlib
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        prebuilt = os.environ.get("CW4D_PREBUILT")
        if prebuilt:
            return self.copy_prebuilt(ext, pathlib.Path(prebuilt))
        # A build directory beside build/ (same depth): ccache, keyed by paths relative to the
        # checkout, then reuses what ./setup.sh compiled.
        build_dir = ROOT / "build-pip"
        build_dir.mkdir(parents=True, exist_ok=True)
        env = dict(os.environ)
        env.setdefault("CCACHE_BASEDIR", str(ROOT))
        env.setdefault("CCACHE_NOHASHDIR", "1")
        generator = ["-G", "Ninja"] if shutil.which("ninja") else []
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build_dir), *generator,
                        "-DCMAKE_BUILD_TYPE=Release", "-DCW4D_BUILD_PYTHON=ON",
                        "-DCW4D_BUILD_TESTS=OFF", "-DCW4D_BUILD_BENCH=OFF",
                        "-DCW4D_BUILD_APPS=OFF", f"-DPython3_EXECUTABLE={sys.executable}"],
                       check=True, env=env)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "cw4d_python", "-j",
                        env.get("CW4D_JOBS", "2")], check=True, env=env)
        built = list((build_dir / "python" / "cw4d").glob("_cw4d*.so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one _cw4d module in {build_dir}/python/cw4d, "
                               f"found {built}")
        self.install_module(ext, built[0])

    def copy_prebuilt(self, ext, build_dir):
        module = build_dir / "python" / "cw4d" / ("_cw4d" + sysconfig.get_config_var("EXT_SUFFIX"))
        if not module.is_file():
            raise RuntimeError(f"CW4D_PREBUILT={build_dir}: no {module.name} in "
                               f"{module.parent} (build the target cw4d_python there with "
                               f"this interpreter, {sys.executable}, or unset CW4D_PREBUILT)")
        self.install_module(ext, module)

    def install_module(self, ext, module):
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(module, target)


setup(ext_modules=[CMakeExtension("cw4d._cw4d")], cmdclass={"build_ext": CMakeBuild})
