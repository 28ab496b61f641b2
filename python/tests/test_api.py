"""The API against analytic values and against itself by a second route."""

import math

import numpy as np
import pytest

import cw4d
from conftest import REGULAR

# f-vectors of the regular polychora (Coxeter, Regular Polytopes, 1973, table I).
FVECTORS = {
    "5-cell": (5, 10, 10, 5),
    "tesseract": (16, 32, 24, 8),
    "16-cell": (8, 24, 32, 16),
    "24-cell": (24, 96, 96, 24),
    "120-cell": (600, 1200, 720, 120),
    "600-cell": (120, 720, 1200, 600),
}


@pytest.mark.parametrize("name", REGULAR)
def test_regular_fvectors_and_validity(name, regular_models):
    c = regular_models[name]
    assert c.dim == 4
    assert c.fvector[:4] == FVECTORS[name]
    assert c.positions.shape == (FVECTORS[name][0], 4)
    report = c.validate()
    assert report.ok and bool(report), report.summary()
    assert c.volume > 0


def test_wythoff_and_spec_agree():
    a = cw4d.wythoff("x3o4o3o")
    assert a.fvector[:4] == FVECTORS["24-cell"]
    b = cw4d.load_model("wythoff:x3o4o3o")
    assert np.array_equal(a.positions, b.positions)
    # every edge of a Wythoff polytope has length 2
    offsets, ids, signs = a.boundary(1)
    ends = np.asarray(ids).reshape(-1, 2)
    lengths = np.linalg.norm(a.positions[ends[:, 1]] - a.positions[ends[:, 0]], axis=1)
    assert np.allclose(lengths, 2.0)
    assert cw4d.uniform_polychoron_diagram("truncated tesseract") == "x4x3o3o"
    assert cw4d.uniform_polychoron_diagram("no such thing") is None


def test_tesseract_analytic_sections():
    t = cw4d.load_model("tesseract")  # [-1, 1]^4
    s = cw4d.section(t, [0, 0, 0, 1], 0.5)
    assert s.dim == 3
    assert s.volume == pytest.approx(8.0)
    assert s.area == pytest.approx(24.0)
    assert s.fvector[:3] == (8, 12, 6)
    # the plane x+y+z+w = 0 cuts [-1, 1]^4 in the regular octahedron whose vertices are the
    # permutations of (1, 1, -1, -1): circumradius 2, volume 4/3 * 2^3
    d = cw4d.section(t, [1, 1, 1, 1], 0.0)
    assert d.fvector[:3] == (6, 12, 8)
    assert d.volume == pytest.approx(32.0 / 3.0)
    miss = cw4d.section(t, [0, 0, 0, 1], 1.5)
    assert miss.empty and miss.volume == 0.0 and miss.vertices.shape == (0, 3)


def test_boundary_tables_are_consistent(regular_models):
    c = regular_models["24-cell"]
    for rank in range(1, c.top_rank + 1):
        offsets, ids, signs = c.boundary(rank)
        assert offsets.dtype == np.uint32 and ids.dtype == np.uint32 and signs.dtype == np.int8
        assert len(offsets) == c.count(rank) + 1 and offsets[-1] == len(ids) == len(signs)
        assert set(np.unique(signs)) <= {-1, 1}
        assert ids.max() < c.count(rank - 1)
    # d(d) = 0 between ranks 3 and 1: the signed edge sum of every cell's faces cancels
    o3, i3, s3 = c.boundary(3)
    o2, i2, s2 = c.boundary(2)
    for cell in range(c.count(3)):
        total = np.zeros(c.count(1))
        for k in range(o3[cell], o3[cell + 1]):
            f = i3[k]
            np.add.at(total, i2[o2[f]:o2[f + 1]], s3[k] * s2[o2[f]:o2[f + 1]].astype(float))
        assert not total.any()
    with pytest.raises(IndexError):
        c.boundary(0)
    with pytest.raises(IndexError):
        c.boundary(c.top_rank + 1)


def test_transform_places_the_model():
    t = cw4d.load_model("tesseract")
    xf = (cw4d.AffineTransform.translation([0, 0, 0, 0.25])
          @ cw4d.AffineTransform.rotation("xw", 30, degrees=True))
    assert np.allclose(xf.apply([1, 0, 0, 0]), [math.cos(math.pi / 6), 0, 0,
                                                0.25 + math.sin(math.pi / 6)])
    assert np.allclose(xf.matrix[:4, 4], [0, 0, 0, 0.25])
    again = cw4d.AffineTransform.from_matrix(xf.matrix)
    assert np.allclose(again.linear, xf.linear)
    assert np.allclose((xf @ xf.inverse()).matrix, np.eye(5))
    a = cw4d.section(t, [0, 0, 0, 1], 0.3, transform=xf)
    b = cw4d.section(t.transformed(xf), [0, 0, 0, 1], 0.3)
    assert a.volume == pytest.approx(b.volume, rel=1e-12)
    assert np.allclose(a.world_vertices()[:, 3], 0.3)
    # from numpy: an (n, n) matrix and a translation
    m = cw4d.AffineTransform(np.diag([2.0, 1, 1, 1]), [0, 0, 0, 0])
    assert cw4d.section(t, [0, 0, 0, 1], 0.0, m).volume == pytest.approx(16.0)


def test_fast_path_equals_general_cut(regular_models):
    rng = np.random.default_rng(7)
    for name in ("24-cell", "120-cell"):
        model = regular_models[name]
        for _ in range(5):
            n = rng.normal(size=4)
            d = rng.uniform(-0.5, 0.5) * model.bounds()[1].max()
            fast, general = cw4d.section(model, n, d), cw4d.section_general(model, n, d)
            assert fast.fvector == general.fvector
            assert np.allclose(fast.vertices, general.vertices, atol=1e-12)


def test_slicer_and_sweep_equal_section(regular_models):
    model = regular_models["120-cell"]
    sm = cw4d.SliceModel(model)
    assert sm.fast and sm.dim == 4
    slicer = cw4d.Slicer()
    n = [0.3, -0.2, 0.5, 1.0]
    offsets = np.linspace(-3.0, 3.0, 13)
    sweep = slicer.sweep(sm, n, offsets)
    volumes = slicer.sweep_volumes(sm, n, offsets, threads=2)
    assert len(sweep) == len(offsets) == len(volumes)
    for d, s, v in zip(offsets, sweep, volumes):
        ref = cw4d.section(model, n, d)
        one = slicer.slice(sm, n, d)
        assert s.fvector == ref.fvector == one.fvector
        assert np.array_equal(s.vertices, one.vertices)
        assert np.allclose(s.vertices, ref.vertices, atol=1e-12)
        assert v == pytest.approx(ref.volume, abs=1e-12)


def test_topology_cache_in_animation():
    model = cw4d.load_model("24-cell")
    sm, slicer = cw4d.SliceModel(model), cw4d.Slicer()
    first = slicer.slice(sm, [0, 0, 0, 1], 0.10, reuse_topology=True)
    second = slicer.slice(sm, [0, 0, 0, 1], 0.11, reuse_topology=True)
    assert slicer.reused_topology and slicer.cached_slices >= 1
    assert second.fvector == first.fvector
    assert second.volume == pytest.approx(cw4d.section(model, [0, 0, 0, 1], 0.11).volume)


def test_polygons_triangles_normals_sources():
    model = cw4d.load_model("tesseract")
    s = cw4d.section(model, [0, 0, 0, 1], 0.5)
    offsets, ids = s.polygons
    assert len(offsets) == 7 and np.all(np.diff(offsets) == 4)
    tris, faces = s.triangles(with_faces=True)
    assert tris.shape == (12, 3) and len(faces) == 12
    v = s.vertices
    # triangles keep the outward orientation: the signed volume of their cones is the volume
    cone = np.einsum("ij,ij->i", v[tris[:, 0]], np.cross(v[tris[:, 1]], v[tris[:, 2]])) / 6
    assert cone.sum() == pytest.approx(8.0)
    # normals point away from the centre of the cube; each polygon came from a distinct cell
    centres = np.array([v[ids[offsets[i]:offsets[i + 1]]].mean(axis=0) for i in range(6)])
    assert np.all(np.einsum("ij,ij->i", s.normals, centres) > 0)
    assert np.allclose(np.linalg.norm(s.normals, axis=1), 1)
    assert len(set(s.source_cells.tolist())) == 6
    element, rank, t = s.vertex_source
    assert np.all(rank == 1) and np.all((t > 0) & (t < 1))
    # a crossing vertex lies on its model edge at parameter t
    o1, i1, _ = model.boundary(1)
    ends = np.asarray(i1).reshape(-1, 2)[element]
    p = model.positions
    on_edge = (1 - t)[:, None] * p[ends[:, 0]] + t[:, None] * p[ends[:, 1]]
    assert np.allclose(on_edge, s.world_vertices())


def test_build_complex_from_numpy():
    # the unit cube [0, 1]^3 from a soup
    pts = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    cube = cw4d.build_complex(pts, faces)
    assert cube.fvector == (8, 12, 6) and cube.validate().ok
    assert cube.volume == pytest.approx(1.0)
    cut = cw4d.section(cube, [0, 0, 1], 0.5)
    assert cut.volume == pytest.approx(1.0)  # the square's area
    assert cut.area == pytest.approx(4.0)    # its perimeter
    prism = cw4d.prism(cube, 2.0)
    assert prism.dim == 4 and prism.volume == pytest.approx(2.0)


def test_operators_and_builtins():
    assert cw4d.simplex(4).fvector[:4] == FVECTORS["5-cell"]
    assert cw4d.cube(4).volume == pytest.approx(16.0)
    assert cw4d.orthoplex(4).volume == pytest.approx(2.0 / 3.0)  # 2^4 / 4!
    dual = cw4d.dual(cw4d.load_model("tesseract"))
    assert dual.fvector[:4] == FVECTORS["16-cell"]
    assert cw4d.duoprism(5, 7).fvector[:4] == (35, 70, 47, 12)
    assert any(spec.startswith("duoprism") for spec, _ in cw4d.builtin_list())
    text = cw4d.off_text(cw4d.load_model("5-cell"))
    again = cw4d.parse_off(text)
    assert np.array_equal(again.positions, cw4d.load_model("5-cell").positions)


def test_hull_based_families_are_registered():
    # the non-Wythoffian convex uniform polychora (Conway and Guy, 1965; f-vectors as in
    # Johnson's list): the snub 24-cell and the grand antiprism
    assert cw4d.load_model("snub 24-cell").fvector[:4] == (96, 432, 480, 144)
    assert cw4d.load_model("grand antiprism").fvector[:4] == (100, 500, 720, 320)
    assert any(spec.startswith("glome") for spec, _ in cw4d.builtin_list())
