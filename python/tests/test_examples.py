"""Every examples/*.py runs to the end and writes what it says."""

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import cw4d

EXAMPLES = sorted((pathlib.Path(__file__).resolve().parents[1] / "examples").glob("*.py"))


def run(script, *args, cwd):
    env = dict(os.environ, MPLBACKEND="Agg")
    # the package this test imported, wherever it came from
    env["PYTHONPATH"] = os.pathsep.join(
        [str(pathlib.Path(cw4d.__file__).resolve().parents[1]), env.get("PYTHONPATH", "")])
    done = subprocess.run([sys.executable, str(script), *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_there_are_examples():
    assert {p.name for p in EXAMPLES} >= {"quickstart.py", "volume_profile.py",
                                          "export_scene.py"}


@pytest.mark.parametrize("script", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_runs(script, tmp_path):
    out = run(script, tmp_path / "out", cwd=tmp_path) if script.name == "export_scene.py" \
        else run(script, tmp_path / "out.png", cwd=tmp_path)
    assert out.strip()
    if script.name == "quickstart.py":
        image = cw4d.read_png(str(tmp_path / "quickstart.png"))
        assert image.shape == (360, 480, 4)
        assert out.split(" ", 1)[1].strip() == "(80, 3) (80, 120, 42)"
        volume = float(out.split()[0])
        ref = cw4d.section(cw4d.load_model("120-cell"), [0, 0, 0, 1], 0.5).volume
        assert volume == pytest.approx(ref, abs=1e-6)
    elif script.name == "volume_profile.py":
        assert (tmp_path / "out.png").stat().st_size > 1000
        for line in out.splitlines():
            integral, volume = float(line.split()[-3]), float(line.split()[-1])
            assert integral == pytest.approx(volume, rel=1e-3)
    elif script.name == "export_scene.py":
        for name in ("scene.obj", "scene.mtl", "scene.glb", "scene.stl", "sweep.glb"):
            assert (tmp_path / "out" / name).stat().st_size > 0
