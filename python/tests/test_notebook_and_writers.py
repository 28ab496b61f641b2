"""Notebook niceties (SVG repr, matplotlib plot) and the writers' files, read back."""

import json
import struct
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import cw4d


@pytest.fixture(scope="module")
def cut():
    return cw4d.section(cw4d.load_model("24-cell"), [0.2, 0.1, 0.3, 1.0], 0.25)


def test_repr_svg(cut):
    svg = cut._repr_svg_()
    root = ET.fromstring(svg)
    assert root.tag.endswith("svg")
    assert len(root.findall(".//{http://www.w3.org/2000/svg}polygon")) > 0
    empty = cw4d.section(cw4d.load_model("24-cell"), [0, 0, 0, 1], 5.0)
    assert empty._repr_svg_() is None


def test_plot_draws_every_polygon(cut):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ax = cut.plot()
    ax.figure.canvas.draw()  # 3D collections project their polygons when drawn
    paths = ax.collections[0].get_paths()
    assert len(paths) == cut.fvector[2]
    plt.close("all")
    flat = cw4d.section(cw4d.load_model("cube:3"), [0, 0, 1], 0.0)
    ax = flat.plot()
    assert len(ax.lines) == flat.fvector[1]
    plt.close("all")


def test_stl_and_ply(tmp_path, cut):
    triangles = cut.triangles()
    cw4d.write_stl(str(tmp_path / "c.stl"), cut)
    data = (tmp_path / "c.stl").read_bytes()
    (count,) = struct.unpack_from("<I", data, 80)
    assert count == len(triangles) and len(data) == 84 + 50 * count
    cw4d.write_ply(str(tmp_path / "c.ply"), cut)
    header = (tmp_path / "c.ply").read_bytes().split(b"end_header")[0].decode()
    assert f"element face {len(triangles)}" in header


def test_gltf_pair_and_animation(tmp_path, cut):
    model = cw4d.load_model("24-cell")
    sm = cw4d.SliceModel(model)
    layers = cw4d.Slicer().sweep(sm, [0, 0, 0, 1], np.linspace(-0.9, 0.9, 5))
    path = tmp_path / "sweep.gltf"
    cw4d.write_gltf(str(path), layers, seconds_per_node=0.5, description="a sweep")
    doc = json.loads(path.read_text())
    assert len(doc["nodes"]) == 5 and len(doc["animations"]) == 1
    assert (tmp_path / "sweep.bin").stat().st_size == doc["buffers"][0]["byteLength"]
    positions = [doc["accessors"][m["primitives"][0]["attributes"]["POSITION"]]["count"]
                 for m in doc["meshes"]]
    # one mesh vertex per polygon corner (each carries its polygon's normal)
    assert positions == [len(s.polygons[1]) for s in layers]


def test_off_svg_png_round_trips(tmp_path, cut):
    cw4d.write_off(str(tmp_path / "c.4off"), cut)
    back = cw4d.read_off(str(tmp_path / "c.4off"))
    assert back.fvector == cut.fvector and np.array_equal(back.positions, cut.vertices)
    cw4d.write_svg(str(tmp_path / "c.svg"), cut, width=200, height=100)
    root = ET.parse(tmp_path / "c.svg").getroot()
    assert root.get("width") == "200" and root.get("height") == "100"
    image = cw4d.render(cut, 64, 48, samples=1)
    cw4d.write_png(str(tmp_path / "c.png"), image)
    assert np.array_equal(cw4d.read_png(str(tmp_path / "c.png")), image)


def test_scene_section(tmp_path):
    text = """{"objects": [
        {"model": "tesseract", "translate": [-1.5, 0, 0, 0], "color": "#ff8000"},
        {"model": "tesseract", "translate": [1.5, 0, 0, 0], "scale": 0.5}]}"""
    scene = cw4d.parse_scene(text)
    assert len(scene) == 2 and scene.dim == 4
    assert scene.objects[0].color[:3] == pytest.approx((1.0, 128 / 255, 0.0))
    merged = cw4d.section_scene(scene, [0, 0, 0, 1], 0.25)
    pieces = cw4d.section_objects(scene, [0, 0, 0, 1], 0.25)
    assert merged.volume == pytest.approx(8.0 + 1.0)
    assert [p.volume for p in pieces] == pytest.approx([8.0, 1.0])


def test_scene_slicer_matches_section_objects():
    objects = ",".join(
        f'{{"model": "24-cell", "translate": [{3 * i}, 0, 0, 0], "rotate": [["xw", {10 * i}]]}}'
        for i in range(6))
    scene = cw4d.parse_scene(f'{{"objects": [{objects}]}}')
    slicer = cw4d.SceneSlicer(scene)
    assert len(slicer) == 6
    normal = [0.3, 0.0, 0.2, 1.0]
    for offset in (0.1, 2.5):
        fast = slicer.slice(normal, offset, threads=2)
        ref = cw4d.section_objects(scene, normal, offset)
        assert [s.fvector for s in fast] == [s.fvector for s in ref]
        assert [s.volume for s in fast] == pytest.approx([s.volume for s in ref], rel=1e-12)
        # culled objects are among those the plane misses
        assert sum(not s.empty for s in ref) <= slicer.touched <= 6
