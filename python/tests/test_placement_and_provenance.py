"""Placements the CLI refuses are refused by every Python entry point too (InputError, never an
empty section), and a section drawn or written with a model it was not cut from is refused
before anything is read or written."""

import math

import numpy as np
import pytest

import cw4d

NAN, INF = math.nan, math.inf
N = [0.3, -0.2, 0.5, 1.0]  # a generic normal: the cuts below meet many cells
BAD_NORMALS = [[NAN, 0, 0, 1], [0, INF, 0, 1], [0, 0, -INF, 0], [0, 0, 0, 0], [0.0, -0.0, 0, 0]]
BAD_OFFSETS = [NAN, INF, -INF]
SCENE = """{"objects": [
  {"model": "24-cell", "scale": 0.6, "translate": [-2, 0, 0, 0]},
  {"model": "tesseract", "scale": 0.6, "translate": [2, 0, 0, 0]}
]}"""


@pytest.fixture(scope="module")
def tesseract():
    return cw4d.load_model("tesseract")


def cutters(model):
    """Every entry point that cuts one placed model, as f(normal, offset, transform)."""
    sm = cw4d.SliceModel(model)
    return {
        "section": lambda n, d, t=None: cw4d.section(model, n, d, t),
        "section_general": lambda n, d, t=None: cw4d.section_general(model, n, d, t),
        "Slicer.slice": lambda n, d, t=None: cw4d.Slicer().slice(sm, n, d, t),
        "Slicer.sweep": lambda n, d, t=None: cw4d.Slicer().sweep(sm, n, [0.0, d], t),
        "Slicer.sweep_volumes":
            lambda n, d, t=None: cw4d.Slicer().sweep_volumes(sm, n, [d, 0.0], t, threads=2),
    }


def scene_cutters(scene):
    """Every entry point that cuts a scene, as f(normal, offset)."""
    return {
        "SceneSlicer.slice": lambda n, d: cw4d.SceneSlicer(scene).slice(n, d),
        "section_scene": lambda n, d: cw4d.section_scene(scene, n, d),
        "section_objects": lambda n, d: cw4d.section_objects(scene, n, d),
    }


def test_bad_normals_and_offsets_are_refused_everywhere(tesseract):
    scene = cw4d.parse_scene(SCENE)
    calls = {**cutters(tesseract), **scene_cutters(scene),
             "_seconds_per_section": lambda n, d: cw4d._cw4d._seconds_per_section(tesseract, n, d, 1)}
    for name, cut in calls.items():
        for n in BAD_NORMALS:
            with pytest.raises(cw4d.InputError, match="normal is (zero|not finite)"):
                cut(n, 0.1)
        for d in BAD_OFFSETS:
            with pytest.raises(cw4d.InputError, match="offset is not finite"):
                cut(N, d)
        # Huge and tiny normals are directions like any other: the same cut as the unit one.
        for scale in () if name == "_seconds_per_section" else (1e300, 1e-300):
            got, want = cut([scale * x for x in N], 0.1), cut(N, 0.1)
            assert repr(got) == repr(want), name


def test_bad_transforms_are_refused_where_they_are_built():
    finite = "must be finite"
    with pytest.raises(cw4d.InputError, match=finite):
        cw4d.AffineTransform(np.full((4, 4), NAN))
    with pytest.raises(cw4d.InputError, match=finite):
        cw4d.AffineTransform(np.eye(4), [0, INF, 0, 0])
    with pytest.raises(cw4d.InputError, match=finite):
        cw4d.AffineTransform(translation=[0, 0, NAN, 0])
    h = np.eye(5)
    h[1, 4] = -INF
    with pytest.raises(cw4d.InputError, match=finite):
        cw4d.AffineTransform.from_matrix(h)
    for angle in BAD_OFFSETS:
        with pytest.raises(cw4d.InputError, match="angle must be finite"):
            cw4d.AffineTransform.rotation("xw", angle)
    with pytest.raises(cw4d.InputError, match=finite):
        cw4d.AffineTransform.translation([INF, 0, 0, 0])
    with pytest.raises(cw4d.InputError, match=finite):
        cw4d.AffineTransform.scale(NAN)
    with pytest.raises(cw4d.InputError, match=finite):
        cw4d.AffineTransform.scale([1, INF, 1, 1])
    big = cw4d.AffineTransform.scale(1e200)
    with pytest.raises(cw4d.InputError, match=finite):
        big @ big  # 1e400 overflows


def test_placements_beyond_doubles_are_refused_by_every_cut(tesseract):
    placements = {
        "coordinates up to 1e\\+300 once placed": cw4d.AffineTransform.scale(1e300),
        "coordinates up to 1e\\+101 once placed":
            cw4d.AffineTransform.translation([0, 0, 1e101, 0]),
        "spans only 0 once placed": cw4d.AffineTransform.scale(0.0),
        "spans only 0 once placed ": cw4d.AffineTransform(np.zeros((4, 4))),
        "spans only 1e-101 once placed": cw4d.AffineTransform.scale(0.5e-101),
    }
    for name, cut in cutters(tesseract).items():
        for message, t in placements.items():
            with pytest.raises(cw4d.InputError, match="the model (has )?" + message.strip()):
                cut(N, 0.0, t)
        # Within the bounds, scaled models cut like the model (volumes scale by s^3).
        for s in (1e90, 1e-90):
            v = cw4d.section(tesseract, N, 0.1 * s, cw4d.AffineTransform.scale(s)).volume
            assert v == pytest.approx(cw4d.section(tesseract, N, 0.1).volume * s**3, rel=1e-12)
    # A scene scaled beyond the bounds: every scene entry point names the object.
    big = cw4d.parse_scene(SCENE.replace('"scale": 0.6, "translate": [2', '"scale": 1e200, '
                                                                            '"translate": [2'))
    for name, cut in scene_cutters(big).items():
        with pytest.raises(cw4d.InputError, match=r"object 1 \(tesseract\) of the scene has "
                                                  r"coordinates up to 1e\+200 once placed"):
            cut(N, 0.1)
    with pytest.raises(cw4d.InputError, match="object 1"):
        cw4d.SceneSlicer(big)


def test_view_and_light_directions(tesseract):
    cut = cw4d.section(tesseract, N, 0.1)
    for bad in ([0, 0, 0], [NAN, 1, 1], [1, INF, 1]):
        with pytest.raises(cw4d.InputError, match="view_from must"):
            cw4d.render(cut, 16, 12, view_from=bad)
        with pytest.raises(cw4d.InputError, match="view_from must"):
            cw4d.svg_text(cut, view_from=bad)
        with pytest.raises(cw4d.InputError, match="light_from must"):
            cw4d.svg_text(cut, light_from=bad)
    # Huge and tiny directions are directions: the same picture as the unit one.
    for scale in (1e300, 1e-300):
        assert np.array_equal(cw4d.render(cut, 32, 24, view_from=[scale, scale, scale]),
                              cw4d.render(cut, 32, 24, view_from=[1, 1, 1]))
        assert cw4d.svg_text(cut, view_from=[scale, 0, scale], light_from=[0, scale, 0]) == \
            cw4d.svg_text(cut, view_from=[1, 0, 1], light_from=[0, 1, 0])


# --- provenance -------------------------------------------------------------------------------

def test_a_model_the_section_was_not_cut_from_is_refused(tmp_path):
    big = cw4d.load_model("120-cell")
    small = cw4d.load_model("tesseract")
    same_counts = cw4d.load_model("24-cell")  # every id of a tesseract cut is in range here
    for model, source in ((small, big), (same_counts, small)):
        cut = cw4d.section(source, N, 0.1)
        assert not cut.empty
        calls = {
            "render": lambda: cw4d.render(cut, 16, 12, model=model),
            "obj_text": lambda: cw4d.obj_text(cut, model=model),
            "write_obj": lambda: cw4d.write_obj(str(tmp_path / "a.obj"), cut, model=model),
            "write_gltf": lambda: cw4d.write_gltf(str(tmp_path / "a.glb"), [cut, cut],
                                                  model=model),
        }
        for name, call in calls.items():
            with pytest.raises(cw4d.InputError, match="the section was not cut from this model"):
                call()
        assert list(tmp_path.iterdir()) == []  # nothing written
        # The source itself, and a moved copy of it, are accepted.
        moved = source.transformed(cw4d.AffineTransform.rotation("xw", 0.3))
        for m in (source, moved):
            assert cw4d.render(cut, 16, 12, model=m).shape == (12, 16, 4)
            assert "vt " in cw4d.obj_text(cut, model=m)
    # The id check names the first cell out of range (the tesseract has 8 cells).
    cut = cw4d.section(big, N, 0.1)
    with pytest.raises(cw4d.InputError, match=r"f-vector \(16, 32, 24, 8\)"):
        cw4d.render(cut, 16, 12, model=small)


def test_a_scene_section_needs_its_scene(tmp_path):
    scene = cw4d.parse_scene(SCENE)
    other = cw4d.parse_scene(SCENE.replace("24-cell", "16-cell"))
    cut = cw4d.section_scene(scene, N, 0.1)
    assert "vt " in cw4d.obj_text(cut, model=scene)
    for model in (other, scene.objects[0].complex):
        with pytest.raises(cw4d.InputError, match="the section was not cut from th"):
            cw4d.obj_text(cut, model=model)
        with pytest.raises(cw4d.InputError, match="the section was not cut from th"):
            cw4d.write_gltf(str(tmp_path / "s.gltf"), cut, model=model)
    assert list(tmp_path.iterdir()) == []
    # A per-object section belongs to its object's model, not to the scene.
    pieces = cw4d.section_objects(scene, N, 0.1)
    assert "vt " in cw4d.obj_text(pieces[1], model=scene.objects[1].complex)
    with pytest.raises(cw4d.InputError, match="the section was not cut from th"):
        cw4d.obj_text(pieces[1], model=scene)
