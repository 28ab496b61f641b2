"""Section.to_meshio() against the real meshio (Debian's python3-meshio), including a write and
read back through meshio's own VTU and OBJ code; to_trimesh() and to_pyvista(), whose packages
Debian does not ship, through their missing-package error and a minimal stand-in module that
records how it is called."""

import builtins
import sys
import types

import meshio
import numpy as np
import pytest

import cw4d


@pytest.fixture(scope="module")
def cut():
    # A generic plane through the 24-cell: polygons of several sizes, one per cell crossed.
    return cw4d.section(cw4d.load_model("24-cell"), [1, 2, 3, 4], 0.3)


def test_meshio_points_and_triangles_are_the_sections(cut):
    mesh = cut.to_meshio()
    assert isinstance(mesh, meshio.Mesh)
    np.testing.assert_array_equal(mesh.points, cut.vertices)
    tris, faces = cut.triangles(with_faces=True)
    assert [block.type for block in mesh.cells] == ["triangle"]
    np.testing.assert_array_equal(mesh.cells[0].data, np.asarray(tris).reshape(-1, 3))
    np.testing.assert_array_equal(mesh.cell_data["polygon"][0], faces)
    np.testing.assert_array_equal(mesh.cell_data["cell"][0], np.asarray(cut.source_cells)[faces])
    # The triangles cover the section: their areas add up to its boundary area.
    p = mesh.points[mesh.cells[0].data]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()
    assert area == pytest.approx(cut.area, rel=1e-12)


def test_meshio_polygons_grouped_by_size(cut):
    mesh = cut.to_meshio(triangulate=False)
    offsets, ids = cut.polygons
    sizes = np.diff(offsets)
    expected = {}
    for i, size in enumerate(sizes):
        expected.setdefault(int(size), []).append(ids[offsets[i]:offsets[i + 1]])
    assert sorted(len(b.data[0]) for b in mesh.cells) == sorted(expected)
    for block, cells in zip(mesh.cells, mesh.cell_data["cell"]):
        size = block.data.shape[1]
        np.testing.assert_array_equal(block.data, np.stack(expected[size]))
        np.testing.assert_array_equal(cells, np.asarray(cut.source_cells)[sizes == size])
        assert block.type == {3: "triangle", 4: "quad"}.get(size, "polygon")


@pytest.mark.parametrize("ext", [".vtu", ".obj"])
def test_meshio_write_read_round_trip(cut, tmp_path, ext):
    path = tmp_path / ("section" + ext)
    meshio.write(path, cut.to_meshio())
    back = meshio.read(path)
    np.testing.assert_allclose(back.points[:, :3], cut.vertices, rtol=0, atol=1e-12)
    assert [b.type for b in back.cells] == ["triangle"]
    np.testing.assert_array_equal(back.cells[0].data, cut.to_meshio().cells[0].data)
    if ext == ".vtu":
        np.testing.assert_array_equal(back.cell_data["cell"][0],
                                      cut.to_meshio().cell_data["cell"][0])


def test_only_3d_sections_convert():
    flat = cw4d.section(cw4d.load_model("cube:3"), [0, 0, 1], 0.1)
    assert flat.dim == 2
    with pytest.raises(cw4d.InputError, match="3D sections"):
        flat.to_meshio()


@pytest.fixture
def without(monkeypatch):
    """Makes `import NAME` fail for the given names, as when the package is not installed."""
    real_import = builtins.__import__

    def hide(*names):
        for name in names:
            monkeypatch.delitem(sys.modules, name, raising=False)

        def guarded(name, *args, **kwargs):
            if name.split(".")[0] in names:
                raise ModuleNotFoundError(f"No module named '{name}'", name=name)
            return real_import(name, *args, **kwargs)

        monkeypatch.setattr(builtins, "__import__", guarded)
        monkeypatch.setattr(
            "importlib.import_module",
            lambda name, package=None: guarded(name) if name in names else real_import(name))

    return hide


@pytest.mark.parametrize("method,package", [("to_trimesh", "trimesh"),
                                            ("to_pyvista", "pyvista"),
                                            ("to_meshio", "meshio")])
def test_missing_package_names_it(cut, without, method, package):
    without(package)
    with pytest.raises(ImportError, match=f"'{package}' package") as err:
        getattr(cut, method)()
    assert err.value.name == package
    assert f"Section.{method}()" in str(err.value)


def test_the_packages_are_not_imported_by_cw4d():
    # Importing cw4d imports none of them (checked in a fresh interpreter).
    import subprocess

    code = ("import sys, cw4d; cw4d.section(cw4d.load_model('tesseract'), [0,0,0,1], 0.1); "
            "print(sorted(m for m in ('trimesh', 'pyvista', 'meshio') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "[]"


class _Recorder:
    """Stand-in class of a mesh package: keeps the arguments it was built with."""

    def __init__(self, *args, **kwargs):
        self.args, self.kwargs = args, kwargs
        self.cell_data = {}


def test_trimesh_call_shape(cut, monkeypatch):
    fake = types.ModuleType("trimesh")
    fake.Trimesh = _Recorder
    monkeypatch.setitem(sys.modules, "trimesh", fake)
    mesh = cut.to_trimesh()
    assert mesh.args == ()
    kw = mesh.kwargs
    np.testing.assert_array_equal(kw["vertices"], cut.vertices)
    tris, faces = cut.triangles(with_faces=True)
    np.testing.assert_array_equal(kw["faces"], np.asarray(tris).reshape(-1, 3))
    assert kw["process"] is False
    np.testing.assert_array_equal(kw["face_attributes"]["polygon"], faces)
    np.testing.assert_array_equal(kw["face_attributes"]["cell"],
                                  np.asarray(cut.source_cells)[faces])


def test_pyvista_call_shape(cut, monkeypatch):
    fake = types.ModuleType("pyvista")
    fake.PolyData = _Recorder
    monkeypatch.setitem(sys.modules, "pyvista", fake)
    mesh = cut.to_pyvista()
    points, flat = mesh.args
    np.testing.assert_array_equal(points, cut.vertices)
    # Decode VTK's flat cell array independently: n, i_0 .. i_{n-1} per polygon.
    offsets, ids = cut.polygons
    decoded, i = [], 0
    while i < len(flat):
        n = int(flat[i])
        decoded.append(list(flat[i + 1:i + 1 + n]))
        i += 1 + n
    assert decoded == [list(ids[offsets[k]:offsets[k + 1]]) for k in range(len(offsets) - 1)]
    np.testing.assert_array_equal(mesh.cell_data["cell"], cut.source_cells)


def test_jupyter_display_is_kept(cut):
    # The converters sit beside the notebook display, which still draws the section.
    assert "<svg" in cut._repr_svg_()
    assert "Complex" in repr(cw4d.load_model("tesseract"))
