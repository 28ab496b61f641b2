"""Section.to_trimesh(), .to_pyvista() and .to_meshio(): a 3D section as the mesh object of
another package. Each package is imported only when its method is called; when it is missing
the call raises an ImportError that names it (cw4d itself needs none of them)."""

import importlib

from . import _cw4d


def _require(package, method):
    try:
        return importlib.import_module(package)
    except ImportError as e:
        raise ImportError(
            f"Section.{method}() needs the '{package}' package, which is not installed "
            f"(pip install {package}); cw4d itself works without it",
            name=package) from e


def _check_3d(section, method):
    if section.dim != 3:
        raise _cw4d.InputError(
            f"Section.{method}() converts 3D sections (of 4D models); this one lives in "
            f"R^{section.dim}")


def _triangles(section):
    import numpy as np

    tris, faces = section.triangles(with_faces=True)
    cells = np.asarray(section.source_cells)
    return (np.asarray(tris, dtype=np.int64).reshape(-1, 3), np.asarray(faces, dtype=np.int64),
            cells[faces] if len(cells) else np.zeros(len(faces), dtype=np.uint32))


def to_trimesh(self):
    """The section as a trimesh.Trimesh: its vertices and the ear-clipped triangles of its
    polygons (outward orientation, no merging or repair: process=False), with face_attributes
    'polygon' (the section polygon of each triangle) and 'cell' (the model cell it was cut
    from). Needs the trimesh package."""
    trimesh = _require("trimesh", "to_trimesh")
    _check_3d(self, "to_trimesh")
    tris, faces, cells = _triangles(self)
    return trimesh.Trimesh(vertices=self.vertices.copy(), faces=tris, process=False,
                           face_attributes={"polygon": faces, "cell": cells})


def to_pyvista(self):
    """The section as a pyvista.PolyData of its polygons (not triangulated; vertex cycles in
    outward orientation), with cell_data 'cell' (the model cell of each polygon). Needs the
    pyvista package."""
    pyvista = _require("pyvista", "to_pyvista")
    _check_3d(self, "to_pyvista")
    import numpy as np

    offsets, ids = self.polygons
    offsets = np.asarray(offsets, dtype=np.int64)
    sizes = np.diff(offsets)
    # VTK's flat cell array: n, i_0 .. i_{n-1} for each polygon.
    flat = np.insert(np.asarray(ids, dtype=np.int64), offsets[:-1], sizes)
    mesh = pyvista.PolyData(self.vertices.copy(), flat)
    mesh.cell_data["cell"] = np.asarray(self.source_cells)
    return mesh


def to_meshio(self, triangulate=True):
    """The section as a meshio.Mesh: by default one 'triangle' block (the ear-clipped
    triangles) with cell_data 'cell' (the model cell of each triangle) and 'polygon'; with
    triangulate=False one block per polygon size ('triangle', 'quad', then 'polygon' blocks of
    five or more corners) with cell_data 'cell'. Needs the meshio package."""
    meshio = _require("meshio", "to_meshio")
    _check_3d(self, "to_meshio")
    import numpy as np

    if triangulate:
        tris, faces, cells = _triangles(self)
        return meshio.Mesh(self.vertices.copy(), [("triangle", tris)],
                           cell_data={"cell": [cells], "polygon": [faces]})
    offsets, ids = self.polygons
    offsets = np.asarray(offsets, dtype=np.int64)
    ids = np.asarray(ids, dtype=np.int64)
    source = np.asarray(self.source_cells)
    sizes = np.diff(offsets)
    blocks, data = [], []
    for size in sorted(set(sizes.tolist())):
        which = np.nonzero(sizes == size)[0]
        corners = np.stack([ids[offsets[i]:offsets[i] + size] for i in which])
        name = {3: "triangle", 4: "quad"}.get(size, "polygon")
        blocks.append((name, corners))
        data.append(source[which])
    return meshio.Mesh(self.vertices.copy(), blocks, cell_data={"cell": data})


def install(section_class):
    section_class.to_trimesh = to_trimesh
    section_class.to_pyvista = to_pyvista
    section_class.to_meshio = to_meshio
