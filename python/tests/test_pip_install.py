"""`pip install ./python` into a fresh virtual environment, offline (--no-index, no build
isolation: setuptools and numpy come from the system), reusing the module of this build tree
(CW4D_PREBUILT), then cw4d imported and used from the environment, not from the build tree."""

import os
import pathlib
import shutil
import subprocess
import sys

import cw4d
from conftest import REPO


def test_pip_install_into_a_fresh_venv(tmp_path):
    # The module under test: build/python/cw4d/_cw4d*.so -> the build directory is build/.
    build_dir = pathlib.Path(cw4d._cw4d.__file__).resolve().parents[2]
    # A copy of python/, so that pip's in-tree build leaves the checkout untouched.
    source = tmp_path / "python"
    shutil.copytree(REPO / "python", source,
                    ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__", "tests"))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)],
                   check=True)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PIP_INDEX_URL")}
    env["CW4D_PREBUILT"] = str(build_dir)
    env["PIP_NO_INDEX"] = "1"
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    done = subprocess.run([str(venv / "bin" / "pip"), "install", "--no-build-isolation",
                           "--no-index", str(source)], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    code = ("import cw4d, sys; m = cw4d.load_model('tesseract'); "
            "s = cw4d.section(m, [0, 0, 0, 1], 0.25); "
            "print(cw4d.__file__); print(s.volume); print(s._repr_svg_() is not None)")
    out = subprocess.run([str(venv / "bin" / "python"), "-c", code], env=env, cwd=tmp_path,
                         capture_output=True, text=True, check=True).stdout.split("\n")
    assert pathlib.Path(out[0]).resolve().is_relative_to(venv.resolve())
    assert float(out[1]) == 8.0  # the cube [-1, 1]^3 cut from the tesseract [-1, 1]^4
    assert out[2] == "True"
    # The stubs and the typing marker are installed with it.
    package = pathlib.Path(out[0]).parent
    assert (package / "_cw4d.pyi").is_file() and (package / "py.typed").is_file()
