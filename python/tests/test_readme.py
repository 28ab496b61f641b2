"""The README's Python example runs as written (tests/readme_test.py runs its shell commands and
its C++ example; this runs its one ```python block)."""

import contextlib
import io
import os
import pathlib
import re

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[2]


def readme_python_blocks():
    text = (REPO / "README.md").read_text(encoding="utf-8")
    return re.findall(r"^```python\n(.*?)^```\s*$", text, re.S | re.M)


def test_readme_python_example_runs_as_written(tmp_path):
    found = readme_python_blocks()
    assert len(found) == 1, f"README.md should have one ```python block, has {len(found)}"
    namespace = {"__name__": "__main__"}
    printed = io.StringIO()
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        with contextlib.redirect_stdout(printed):
            exec(compile(found[0], "README.md (python block)", "exec"), namespace)
    finally:
        os.chdir(cwd)
    assert printed.getvalue().strip(), "the example prints nothing"
    cut = namespace["cut"]
    # The example computes the volume with numpy from the triangles (divergence theorem): it
    # must agree with the section's own volume, which must be a real solid.
    assert cut.volume > 0
    assert np.isclose(namespace["volume"], cut.volume, rtol=1e-9)
