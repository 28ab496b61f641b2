"""The type stubs describe the module as it is: every public function, class and member of the
extension is in _cw4d.pyi, and the stubs name nothing the module lacks."""

import ast
import inspect
import pathlib

import cw4d
from cw4d import _cw4d

STUB = pathlib.Path(cw4d.__file__).with_name("_cw4d.pyi")


def stub_names():
    tree = ast.parse(STUB.read_text())
    top, members = set(), {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            top.add(node.name)
        if isinstance(node, ast.ClassDef):
            members[node.name] = {
                n.name if isinstance(n, ast.FunctionDef) else n.target.id
                for n in node.body
                if isinstance(n, ast.FunctionDef)
                or (isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name))}
    return top, members


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def test_every_module_name_is_stubbed():
    top, _ = stub_names()
    assert public(_cw4d) == top
    assert set(cw4d.__all__) == top
    assert all(hasattr(cw4d, name) for name in cw4d.__all__)


def test_every_class_member_is_stubbed():
    _, members = stub_names()
    for name, stubbed in members.items():
        cls = getattr(_cw4d, name)
        if issubclass(cls, BaseException):
            continue  # attributes set per instance (file, line, ...), checked in test_errors
        own = {n for n in public(cls) if n not in public(object)}
        assert own == {n for n in stubbed if not n.startswith("_")}, name


def test_docstrings():
    for name in public(_cw4d):
        obj = getattr(_cw4d, name)
        assert inspect.getdoc(obj), name


def test_mypy_stubtest(tmp_path):
    """mypy's stubtest (Debian python3-mypy) compares the stubs with the imported module."""
    import os
    import subprocess
    import sys

    config = tmp_path / "mypy.ini"
    config.write_text("[mypy]\nignore_missing_imports = True\n")
    allowlist = pathlib.Path(__file__).with_name("stubtest_allowlist.txt")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(pathlib.Path(cw4d.__file__).resolve().parents[1]), os.environ.get("PYTHONPATH", "")]))
    done = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "--mypy-config-file", str(config),
         "--allowlist", str(allowlist), "cw4d"],
        capture_output=True, text=True, env=env, cwd=tmp_path, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Success" in done.stdout
