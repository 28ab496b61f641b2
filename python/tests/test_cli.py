"""The Python API against the native CLI (build/apps/cw4d) on the same inputs."""

import json
import struct

import numpy as np
import pytest

import cw4d
from conftest import REPO

MODELS = ["5-cell", "tesseract", "24-cell", "120-cell", "duoprism:5,7", "wythoff:x4x3o3o",
          "snub 24-cell", "grand antiprism"]


@pytest.mark.parametrize("spec", MODELS)
def test_info_matches(cli, spec):
    info = json.loads(cli("info", spec, "--json").stdout)
    model = cw4d.load_model(spec)
    assert list(model.fvector) == info["fvector"]
    assert model.dim == info["dimension"]
    assert model.validate().ok == info["valid"]
    assert model.volume == info["volume"]  # the same double through JSON
    lo, hi = model.bounds()
    assert lo.tolist() == info["bounds"]["min"] and hi.tolist() == info["bounds"]["max"]


PLACED = [
    ("tesseract", "0,0,0,1", 0.25, ["xw:30", "yw:25", "zw:20"], None),
    ("24-cell", "1,2,-0.5,1", 0.3, ["xy:10"], "0.1,0,0,0.2"),
    ("120-cell", "0,0,0,1", 0.5, [], None),
    ("600-cell", "0.2,0.1,0.4,1", -0.35, ["zw:45"], None),
]


def placement(rotations, translate):
    xf = cw4d.AffineTransform.identity(4)
    for r in rotations:
        plane, degrees = r.split(":")
        xf = cw4d.AffineTransform.rotation(plane, float(degrees), degrees=True) @ xf
    if translate:
        xf = cw4d.AffineTransform.translation([float(x) for x in translate.split(",")]) @ xf
    return xf


def cli_args(spec, normal, offset, rotations, translate):
    args = [spec, "--normal", normal, "--offset", offset]
    for r in rotations:
        args += ["--rotate", r]
    if translate:
        args += ["--translate", translate]
    return args


@pytest.mark.parametrize("spec,normal,offset,rotations,translate", PLACED)
def test_slice_matches_cli_off(cli, tmp_path, spec, normal, offset, rotations, translate):
    out = tmp_path / "cut.4off"
    cli("slice", *cli_args(spec, normal, offset, rotations, translate), "-o", out)
    native = cw4d.read_off(str(out))
    cut = cw4d.section(cw4d.load_model(spec), [float(x) for x in normal.split(",")], offset,
                       transform=placement(rotations, translate))
    assert native.fvector == cut.fvector
    assert np.array_equal(native.positions, cut.vertices)  # nOFF keeps every bit
    assert native.volume == pytest.approx(cut.volume, rel=1e-12)
    # and the Python writer gives the same file
    mine = tmp_path / "mine.4off"
    cw4d.write_off(str(mine), cut)
    assert mine.read_text() == out.read_text()


def strip_comments(text):
    return [line for line in text.splitlines() if not line.startswith("#")]


@pytest.mark.parametrize("triangulate", [False, True])
def test_obj_matches_cli(cli, tmp_path, triangulate):
    spec, normal, offset, rotations, translate = PLACED[1]
    out = tmp_path / "cut.obj"
    extra = ["--triangulate"] if triangulate else []
    cli("slice", *cli_args(spec, normal, offset, rotations, translate), *extra, "-o", out)
    model = cw4d.load_model(spec)
    cut = cw4d.section(model, [float(x) for x in normal.split(",")], offset,
                       transform=placement(rotations, translate))
    mine = cw4d.obj_text(cut, triangulate=triangulate, model=model)
    assert strip_comments(mine) == strip_comments(out.read_text())
    written = tmp_path / "mine.obj"
    cw4d.write_obj(str(written), cut, triangulate=triangulate, model=model)
    assert strip_comments(written.read_text()) == strip_comments(out.read_text())


def glb_json(data):
    magic, version, _ = struct.unpack_from("<III", data, 0)
    assert magic == 0x46546C67 and version == 2  # "glTF"
    length, kind = struct.unpack_from("<II", data, 12)
    assert kind == 0x4E4F534A  # "JSON"
    return json.loads(data[20:20 + length])


def test_glb_matches_cli(cli, tmp_path):
    spec, normal, offset, rotations, translate = PLACED[0]
    out = tmp_path / "cut.glb"
    cli("slice", *cli_args(spec, normal, offset, rotations, translate), "-o", out)
    model = cw4d.load_model(spec)
    cut = cw4d.section(model, [float(x) for x in normal.split(",")], offset,
                       transform=placement(rotations, translate))
    mine = tmp_path / "mine.glb"
    cw4d.write_gltf(str(mine), cut, model=model, names=[spec])
    a, b = glb_json(out.read_bytes()), glb_json(mine.read_bytes())
    assert a["accessors"] == b["accessors"]
    assert a["meshes"] == b["meshes"] and [n["name"] for n in b["nodes"]] == [spec]
    # the binary chunk (positions, normals, uvw, ...) is the same
    assert out.read_bytes()[-a["buffers"][0]["byteLength"]:] == \
        mine.read_bytes()[-b["buffers"][0]["byteLength"]:]


def test_render_matches_cli(cli, tmp_path):
    out = tmp_path / "cut.png"
    cli("render", "24-cell", "--normal", "0,0,0,1", "--offset", 0.3, "--size", "160x120",
        "--edges", "-o", out)
    model = cw4d.load_model("24-cell")
    image = cw4d.render(cw4d.section(model, [0, 0, 0, 1], 0.3), 160, 120, edges=True,
                        model=model)
    assert image.shape == (120, 160, 4) and image.dtype == np.uint8
    assert np.all(image[..., 3] == 255)
    native = cw4d.read_png(str(out))
    assert native.shape == (120, 160, 3)
    assert np.array_equal(native, image[..., :3])
    # the picture is not blank: the section covers a good part of it
    assert (image[..., :3] != 255).any(axis=2).mean() > 0.1


def test_parse_error_matches_cli(cli, tmp_path):
    bad = tmp_path / "bad.4off"
    bad.write_text("4OFF\n3 1 3 0\n0 0 0 0\n1 0 0 0\n0 1 zero 0\n3 0 1 2\n")
    done = cli("info", bad, check=False)
    assert done.returncode == 2
    with pytest.raises(cw4d.ParseError) as caught:
        cw4d.read_off(str(bad))
    assert str(caught.value) in done.stderr
    assert caught.value.file == str(bad) and caught.value.line == 5


def test_scene_matches_cli(cli, tmp_path):
    scene_file = REPO / "data" / "example-scene.json"
    out = tmp_path / "scene.obj"
    printed = cli("slice", "--scene", scene_file, "--normal", "0.1,0,0.2,1", "--offset", 0.1,
                  "-o", out).stdout
    scene = cw4d.read_scene(str(scene_file))
    assert [o.name for o in scene.objects] == ["centre", "left", "right"]
    cut = cw4d.section_scene(scene, [0.1, 0, 0.2, 1], 0.1)
    mine = tmp_path / "mine.obj"
    cw4d.write_obj(str(mine), cut, model=scene)
    mine_lines = strip_comments(mine.read_text())
    assert mine_lines == [l.replace("scene.mtl", "mine.mtl") for l in strip_comments(out.read_text())]
    assert "mtllib mine.mtl" in mine_lines
    assert mine.with_suffix(".mtl").read_text() == out.with_suffix(".mtl").read_text()
    pieces = cw4d.SceneSlicer(scene).slice([0.1, 0, 0.2, 1], 0.1)
    # the CLI prints one line per object with its f-vector and volume
    for i, piece in enumerate(pieces):
        line = next(l for l in printed.splitlines() if l.strip().startswith(f"object {i} "))
        assert f"{piece.fvector[0]} vertices" in line


def test_scene_glb_matches_cli(cli, tmp_path):
    scene_file = REPO / "data" / "example-scene.json"
    out = tmp_path / "scene.glb"
    cli("slice", "--scene", scene_file, "--normal", "0,0.3,0,1", "--offset", -0.2, "-o", out)
    scene = cw4d.read_scene(str(scene_file))
    mine = tmp_path / "mine.glb"
    cw4d.write_gltf(str(mine), cw4d.section_scene(scene, [0, 0.3, 0, 1], -0.2), model=scene)
    a, b = glb_json(out.read_bytes()), glb_json(mine.read_bytes())
    assert [n["name"] for n in a["nodes"]] == [n["name"] for n in b["nodes"]] == \
        ["centre", "left", "right"]
    assert a["accessors"] == b["accessors"] and a["meshes"] == b["meshes"]
    assert a["materials"] == b["materials"]
