"""Shared fixtures: the native CLI next to the module (build/apps/cw4d, or $CW4D_CLI) and the
regular polychora."""

import os
import pathlib
import subprocess

import pytest

import cw4d

REPO = pathlib.Path(__file__).resolve().parents[2]
REGULAR = ["5-cell", "tesseract", "16-cell", "24-cell", "120-cell", "600-cell"]


def _cli_path():
    if os.environ.get("CW4D_CLI"):
        return pathlib.Path(os.environ["CW4D_CLI"])
    # build/python/cw4d/__init__.py -> build/apps/cw4d
    return pathlib.Path(cw4d.__file__).resolve().parents[2] / "apps" / "cw4d"


@pytest.fixture(scope="session")
def cli():
    path = _cli_path()
    if not path.is_file():
        pytest.fail(f"the cw4d CLI is not at {path} (build it, or set CW4D_CLI)")

    def run(*args, check=True):
        done = subprocess.run([str(path), *map(str, args)], capture_output=True, text=True)
        if check and done.returncode != 0:
            raise AssertionError(f"cw4d {' '.join(map(str, args))} exited {done.returncode}: "
                                 f"{done.stderr.strip()}")
        return done

    return run


@pytest.fixture(scope="session")
def regular_models():
    return {name: cw4d.load_model(name) for name in REGULAR}
