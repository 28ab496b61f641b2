"""Mass properties and the section atlas: the Python API against analytic values, and against
the CLI's `info --json` and `atlas --json` on the same models."""

import json
import math

import numpy as np
import pytest

import cw4d


def test_tesseract_mass():
    m = cw4d.load_model("tesseract").mass_properties()
    assert m["hypervolume"] == pytest.approx(16.0, rel=1e-14)
    assert m["boundary_volume"] == pytest.approx(64.0, rel=1e-14)
    assert np.allclose(m["centroid"], 0.0, atol=1e-14)
    assert m["second_moment"].shape == (4, 4)
    assert np.allclose(m["second_moment"], np.eye(4) * 16 / 3, rtol=1e-14, atol=1e-14)
    assert m["winding_weighted"] is False


def test_moved_box_mass():
    # [0,2] x [0,4] x [0,6] x [0,8] (the tesseract scaled and moved): V = 384, centroid
    # (1,2,3,4), int x_i^2 = V L_i^2 / 3, int x_i x_j = V c_i c_j.
    t = cw4d.AffineTransform.translation([1, 2, 3, 4]) @ cw4d.AffineTransform(
        np.diag([1.0, 2.0, 3.0, 4.0]), np.zeros(4))
    m = cw4d.load_model("tesseract").transformed(t).mass_properties()
    lengths = np.array([2.0, 4.0, 6.0, 8.0])
    c = lengths / 2
    assert m["hypervolume"] == pytest.approx(384.0, rel=1e-13)
    assert np.allclose(m["centroid"], c, rtol=1e-13)
    want = 384.0 * np.outer(c, c)
    np.fill_diagonal(want, 384.0 * lengths**2 / 3)
    assert np.allclose(m["second_moment"], want, rtol=1e-13)


def test_star_mass_is_winding_weighted():
    assert cw4d.load_model("great 120-cell").mass_properties()["winding_weighted"] is True


def test_open_model_mass_is_refused():
    # A cube in R^3 without its top face: its top edges lie in one face each.
    corners = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    faces = [[0, 2, 3, 1], [0, 1, 5, 4], [1, 3, 7, 5], [3, 2, 6, 7], [2, 0, 4, 6]]
    with pytest.raises(cw4d.TopologyError, match="not closed"):
        cw4d.build_complex(corners, faces).mass_properties()


@pytest.mark.parametrize("spec", ["tesseract", "5-cell", "duoprism:5,7", "120-cell"])
def test_info_mass_matches(cli, spec):
    info = json.loads(cli("info", spec, "--json").stdout)
    m = cw4d.load_model(spec).mass_properties()
    assert info["mass"]["hypervolume"] == m["hypervolume"]
    assert info["mass"]["boundary_volume"] == m["boundary_volume"]
    assert info["mass"]["centroid"] == m["centroid"].tolist()
    assert info["mass"]["second_moment"] == m["second_moment"].tolist()
    assert info["mass"]["winding_weighted"] is False
    assert info["mass"]["hypervolume"] == pytest.approx(info["volume"], rel=1e-13)


def test_atlas_tesseract_diagonal():
    a = cw4d.atlas(cw4d.load_model("tesseract"), [1, 1, 1, 1])
    assert a["critical_offsets"] == [-2.0, -1.0, 0.0, 1.0, 2.0]
    assert [i["f_vector"] for i in a["intervals"]] == [[4, 6, 4], [12, 18, 8], [12, 18, 8],
                                                       [4, 6, 4]]
    assert a["critical_sections"][2]["f_vector"] == [6, 12, 8]
    assert all(c["degenerate"] for c in a["critical_sections"])
    # At either end the plane only touches the tesseract, in one vertex.
    ends = [a["critical_sections"][0], a["critical_sections"][-1]]
    assert [c["f_vector"] for c in ends] == [[0, 0, 0], [0, 0, 0]]
    assert [c["contact_f_vector"] for c in ends] == [[1, 0, 0], [1, 0, 0]]
    assert all("contact_f_vector" not in c for c in a["critical_sections"][1:-1])
    # Along (1, 1, 0, 0) it touches in a square.
    b = cw4d.atlas(cw4d.load_model("tesseract"), [1, 1, 0, 0])
    assert b["critical_sections"][0]["contact_f_vector"] == [4, 4, 1]


def test_atlas_sections_are_the_cuts():
    model = cw4d.load_model("24-cell")
    a = cw4d.atlas(model, [1, 2, 3, 4], sections=True)
    for i in a["intervals"]:
        assert i["from"] < i["offset"] < i["to"]
        assert list(i["section"].fvector)[:3] == i["f_vector"]
        again = cw4d.section(model, [1, 2, 3, 4], i["offset"])
        assert again.volume == pytest.approx(i["section"].volume, rel=1e-12)


@pytest.mark.parametrize("spec,normal", [("tesseract", "1,1,1,1"), ("24-cell", "1,2,3,4"),
                                         ("5-cell", "0,0,0,1")])
def test_atlas_matches_cli(cli, spec, normal):
    got = json.loads(cli("atlas", spec, "--normal", normal, "--json").stdout)
    a = cw4d.atlas(cw4d.load_model(spec), [float(x) for x in normal.split(",")])
    assert got["critical_offsets"] == a["critical_offsets"]
    assert [i["f_vector"] for i in got["intervals"]] == [i["f_vector"] for i in a["intervals"]]
    assert [(i["from"], i["to"]) for i in got["intervals"]] == [
        (i["from"], i["to"]) for i in a["intervals"]]
    assert got["critical_sections"] == a["critical_sections"]


def test_atlas_cli_errors(cli):
    done = cli("atlas", "tesseract", "--normal", "0,0,0,0", check=False)
    assert done.returncode == 1 and done.stderr.startswith("cw4d: error:")
    assert len(done.stderr.strip().splitlines()) == 1
    done = cli("atlas", "tesseract", "--normal", "1,0,0", check=False)
    assert done.returncode == 1
    done = cli("atlas", "no-such-model", "--normal", "1,0,0,0", check=False)
    assert done.returncode == 1
    done = cli("atlas", "tesseract", "--normal", "1,0,0,0", "-o", "x.obj", check=False)
    assert done.returncode == 1


def test_glome_volume_converges():
    r = 1.0
    errors = [abs(math.pi**2 / 2 - cw4d.load_model(f"glome:{r},{n}").mass_properties()[
        "hypervolume"]) for n in (4, 6, 8)]
    assert errors[0] > errors[1] > errors[2]
