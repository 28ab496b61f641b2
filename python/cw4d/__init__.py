"""cw4d: 4D polytopes as CW complexes and their hyperplane sections, from Python.

    import cw4d
    model = cw4d.load_model("120-cell")
    cut = cw4d.section(model, [0, 0, 0, 1], 0.5)
    print(cut.volume, cut.vertices.shape)

Arrays come back as numpy arrays. Views of the C++ storage (no copy, read-only, kept alive by
their owner): Complex.positions, Complex.facet_normals, Complex.boundary(rank),
Section.vertices, Section.normals, Section.source_cells, Section.source(rank),
Section.vertex_source. Everything else that returns an array computes it into a new one
(Section.polygons, Section.triangles(), Section.world_vertices(), render(), ...).

numpy is needed only by the calls that return arrays, matplotlib only by Section.plot(), and
trimesh, pyvista and meshio only by Section.to_trimesh(), .to_pyvista() and .to_meshio().
"""

from . import _cw4d
from ._cw4d import (
    AffineTransform,
    Complex,
    Error,
    InputError,
    IoError,
    ParseError,
    Scene,
    SceneObject,
    SceneSlicer,
    Section,
    SliceModel,
    Slicer,
    TopologyError,
    ValidationIssue,
    ValidationReport,
    antiprism,
    atlas,
    build_complex,
    builtin_list,
    cube,
    dual,
    duoprism,
    load_model,
    obj_text,
    off_text,
    orthoplex,
    parse_off,
    parse_scene,
    polygon,
    prism,
    product,
    pyramid,
    read_g4mf,
    read_off,
    read_png,
    read_scene,
    render,
    section,
    section_general,
    section_objects,
    section_scene,
    simplex,
    spin,
    svg_text,
    torus,
    transformed,
    uniform_polychoron_diagram,
    uv_sphere,
    validate,
    write_g4mf,
    write_gltf,
    write_obj,
    write_off,
    write_ply,
    write_png,
    write_stl,
    write_svg,
    wythoff,
)
from . import _interop, _notebook

__version__ = "0.1.0"

_notebook.install(Section)
_interop.install(Section)

__all__ = [name for name in dir(_cw4d) if not name.startswith("_")]
