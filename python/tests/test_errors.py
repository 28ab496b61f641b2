"""C++ errors arrive as the documented Python exceptions, with file and line."""

import numpy as np
import pytest

import cw4d


def test_hierarchy():
    assert issubclass(cw4d.Error, RuntimeError)
    for cls in (cw4d.InputError, cw4d.ParseError, cw4d.TopologyError):
        assert issubclass(cls, cw4d.Error) and issubclass(cls, ValueError)
    assert issubclass(cw4d.IoError, cw4d.Error) and issubclass(cw4d.IoError, OSError)
    assert cw4d.ParseError.__module__ == "cw4d"


def test_parse_error_of_an_off_file(tmp_path):
    path = tmp_path / "broken.4off"
    path.write_text("4OFF\n# a comment line\n3 1 3 0\n0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 7\n")
    with pytest.raises(cw4d.ParseError) as caught:
        cw4d.read_off(str(path))
    e = caught.value
    assert e.file == str(path) and e.line == 7
    assert str(e) == f"{path}:7: {e.message}" and "7" in e.message


def test_parse_error_of_text_and_missing_file(tmp_path):
    with pytest.raises(cw4d.ParseError) as caught:
        cw4d.parse_off("4OFF\n1 0 0 0\n0 0 nan? 0\n", name="inline.4off")
    assert caught.value.file == "inline.4off" and caught.value.line == 3
    missing = tmp_path / "nothing.4off"
    with pytest.raises(cw4d.ParseError) as caught:
        cw4d.read_off(str(missing))
    assert caught.value.line == 0 and caught.value.file == str(missing)


def test_scene_errors_name_the_line(tmp_path):
    text = '{\n  "objects": [\n    {"model": "tesseract",\n     "colour": "#ff0000"}\n  ]\n}\n'
    with pytest.raises(cw4d.ParseError) as caught:
        cw4d.parse_scene(text, name="scene.json")
    assert caught.value.file == "scene.json" and caught.value.line == 4
    assert "colour" in caught.value.message
    path = tmp_path / "s.json"
    path.write_text('{"objects": [{"model": "no-such-model"}]}')
    with pytest.raises(cw4d.ParseError) as caught:
        cw4d.read_scene(str(path))
    assert caught.value.file == str(path) and caught.value.line == 1


def test_input_errors():
    t = cw4d.load_model("tesseract")
    with pytest.raises(cw4d.InputError):
        cw4d.load_model("no-such-polytope")
    with pytest.raises(cw4d.InputError, match="zero"):
        cw4d.section(t, [0, 0, 0, 0], 0.0)
    with pytest.raises(cw4d.InputError):
        cw4d.section(t, [0, 0, 1], 0.0)  # a 3-vector for a 4D model
    with pytest.raises(cw4d.InputError):
        cw4d.section(t, [[0, 0, 0, 1]], 0.0)  # not 1-D
    with pytest.raises(cw4d.InputError):
        cw4d.wythoff("x6o3o")  # an infinite group
    with pytest.raises(ValueError):  # InputError is a ValueError
        cw4d.AffineTransform.rotation("xq", 1.0)


def test_topology_error_names_the_elements():
    pts = np.eye(3)
    with pytest.raises(cw4d.TopologyError) as caught:
        cw4d.build_complex(pts, [[0, 1, 5]])
    assert caught.value.rank >= 0 and isinstance(caught.value.ids, list)


def test_io_error(tmp_path):
    s = cw4d.section(cw4d.load_model("tesseract"), [0, 0, 0, 1], 0.0)
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(cw4d.IoError):
        cw4d.write_obj(str(blocker / "cut.obj"), s)  # a path under a regular file
    with pytest.raises(OSError):
        cw4d.write_off(str(blocker / "cut.4off"), s)


def test_bad_arguments_of_the_other_calls():
    t = cw4d.load_model("tesseract")
    sm = cw4d.SliceModel(t)
    with pytest.raises(cw4d.InputError, match="R\\^3"):
        cw4d.section(t, [0, 0, 0, 1], 0.0, cw4d.AffineTransform.identity(3))
    with pytest.raises(cw4d.InputError, match="finite"):
        cw4d.Slicer().sweep(sm, [0, 0, 0, 1], [0.0, float("nan")])
    with pytest.raises(cw4d.InputError):
        cw4d.Slicer().slice(sm, [0, 0, 1], 0.0)
    with pytest.raises(cw4d.InputError, match="R\\^2"):
        cw4d.render(cw4d.section(cw4d.load_model("cube:3"), [0, 0, 1], 0.0))
    with pytest.raises(cw4d.InputError):
        cw4d.render(cw4d.section(t, [0, 0, 0, 1], 0.0), width=0)
    with pytest.raises(cw4d.InputError):
        cw4d.write_png("unused.png", np.zeros((2, 2), np.uint8))
    with pytest.raises(cw4d.InputError, match="normal"):
        cw4d.section(t, ["a", 1, 2, 3], 0.0)


def _png_chunk(kind: bytes, data: bytes) -> bytes:
    import struct
    import zlib

    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def test_read_png_refuses_fifos_devices_and_bombs(tmp_path):
    import os
    import struct
    import zlib

    fifo = tmp_path / "fifo.png"
    os.mkfifo(fifo)
    with pytest.raises(cw4d.ParseError, match="not a regular file"):
        cw4d.read_png(str(fifo))
    zero = tmp_path / "zero.png"
    zero.symlink_to("/dev/zero")
    with pytest.raises(cw4d.ParseError, match="not a regular file"):
        cw4d.read_png(str(zero))
    # A valid PNG of a few dozen bytes declaring 100000 x 100000 gray pixels.
    bomb = (
        b"\x89PNG\r\n\x1a\n"
        + _png_chunk(b"IHDR", struct.pack(">IIBBBBB", 100000, 100000, 8, 0, 0, 0, 0))
        + _png_chunk(b"IDAT", zlib.compress(b"\0" * 4))
        + _png_chunk(b"IEND", b"")
    )
    (tmp_path / "bomb.png").write_bytes(bomb)
    with pytest.raises(cw4d.ParseError, match="100000x100000"):
        cw4d.read_png(str(tmp_path / "bomb.png"))
