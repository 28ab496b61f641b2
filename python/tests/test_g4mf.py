"""G4MF output of the native CLI checked by independent means: every JSON document validated
against the G4MF JSON Schemas (tests/data/g4mf/schema, godot-dimensions/g4mf) with Debian's
python3-jsonschema, the buffers decoded here, and the MUSTs the schemas cannot express checked
(index ranges, alignment, the first two members of every element sharing a boundary element,
unit normals, unique names), then godot-4d's orientation rule recomputed with the spec's
perpendicular_4d: every cell of a convex model faces away from its centre."""

import base64
import json
import pathlib
import struct

import numpy as np
import pytest

import cw4d

REPO = pathlib.Path(__file__).resolve().parents[2]
SCHEMAS = REPO / "tests" / "data" / "g4mf" / "schema"
SAMPLES = REPO / "tests" / "data" / "g4mf"

jsonschema = pytest.importorskip("jsonschema", reason="Debian's python3-jsonschema (./setup.sh test)")


def _no_network(uri):
    raise AssertionError(f"a schema refers to {uri}, which is not in tests/data/g4mf/schema")


@pytest.fixture(scope="module")
def validator():
    # Every schema under its file URI, its relative "$id" made that URI, so that the relative
    # $refs ("mesh/g4mf.mesh.schema.json", "../g4mf_item.schema.json") resolve to the files.
    store = {}
    for path in sorted(SCHEMAS.rglob("*.schema.json")):
        schema = json.loads(path.read_text())
        schema["$id"] = path.as_uri()
        store[path.as_uri()] = schema
    main = store[(SCHEMAS / "g4mf.schema.json").as_uri()]
    cls = jsonschema.Draft202012Validator
    cls.check_schema(main)
    try:  # jsonschema >= 4.18
        from referencing import Registry, Resource
        registry = Registry(retrieve=_no_network).with_resources(
            (uri, Resource.from_contents(s)) for uri, s in store.items())
        return cls(main, registry=registry)
    except ImportError:  # Debian 12's 4.10
        resolver = jsonschema.RefResolver(main["$id"], main, store=store,
                                          handlers={"http": _no_network, "https": _no_network})
        return cls(main, resolver=resolver)


def test_the_schemas_reject_what_they_should(validator):
    assert not validator.is_valid({})  # asset is required
    assert not validator.is_valid({"asset": {}})  # dimension is required
    assert not validator.is_valid({"asset": {"dimension": 4}, "meshes": [{"surfaces": []}]})
    assert not validator.is_valid({"asset": {"dimension": 4},
                                   "buffers": [{"byteLength": 4, "uri": "a", "chunk": 1}]})
    assert validator.is_valid({"asset": {"dimension": 4}})


# --- reading a G4MF file here, without cw4d ------------------------------------------------------

COMPONENTS = {"int8": "b", "int16": "h", "int32": "i", "int64": "q", "uint8": "B",
              "uint16": "H", "uint32": "I", "uint64": "Q", "float32": "f", "float64": "d"}


def load(path):
    """(document, buffers) of a .g4tf or .g4b file."""
    data = path.read_bytes()
    chunks = []
    if data[:4] == b"G4MF":
        magic, version, size = struct.unpack_from("<4sIQ", data, 0)
        assert version == 0 and size == len(data)
        at = 16
        while at + 16 <= size:
            kind, encoding, length = struct.unpack_from("<4sIQ", data, at)
            assert encoding == 0 and at % 16 == 0
            chunks.append((kind, data[at + 16:at + 16 + length]))
            at = (at + 16 + length + 15) // 16 * 16
        assert chunks[0][0] == b"JSON"
        text = chunks[0][1]
        assert all(b >= 0x20 or b in (9, 10) for b in text)  # no control characters
        doc = json.loads(text)
    else:
        assert not data.startswith(b"\xef\xbb\xbf") and b"\r" not in data  # G4TF: no BOM, no CR
        doc = json.loads(data)
    buffers = []
    for buf in doc.get("buffers", []):
        if "chunk" in buf:
            blob = chunks[buf["chunk"]][1]
        elif buf["uri"].startswith("data:"):
            assert buf["uri"].startswith("data:application/octet-stream;base64,")
            blob = base64.b64decode(buf["uri"].split(",", 1)[1], validate=True)
        else:
            blob = (path.parent / buf["uri"]).read_bytes()
        assert len(blob) >= buf["byteLength"]
        buffers.append(blob[:buf["byteLength"]])
    return doc, buffers


def accessor(doc, buffers, index):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    fmt = COMPONENTS[acc["componentType"]]
    size = struct.calcsize(fmt)
    vs = acc.get("vectorSize", 1)
    offset, length = view.get("byteOffset", 0), view["byteLength"]
    blob = buffers[view.get("buffer", 0)]
    assert offset + length <= len(blob)
    assert offset % size == 0 and length % (size * vs) == 0
    values = np.frombuffer(blob, dtype="<" + fmt, count=length // size, offset=offset)
    return values.reshape(-1, vs) if vs > 1 else values, acc["componentType"]


def lists(flat):
    out, j = [], 0
    while j < len(flat):
        count = int(flat[j])
        assert count >= 1 and j + 1 + count <= len(flat)
        out.append([int(x) for x in flat[j + 1:j + 1 + count]])
        j += 1 + count
    return out


def perpendicular_4d(a, b, c):
    """The spec's perpendicular_4d (specification/parts/math.md)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    cx, cy, cz, cw = c
    return np.array([
        -ay * (bz * cw - bw * cz) + az * (by * cw - bw * cy) - aw * (by * cz - bz * cy),
        ax * (bz * cw - bw * cz) - az * (bx * cw - bw * cx) + aw * (bx * cz - bz * cx),
        -ax * (by * cw - bw * cy) + ay * (bx * cw - bw * cx) - aw * (bx * cy - by * cx),
        ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)])


def check_document(path, validator, convex=False):
    """Schema, then the spec's MUSTs on the data; returns (dimension, vertices, edges, tiers)."""
    doc, buffers = load(path)
    errors = sorted(validator.iter_errors(doc), key=lambda e: list(e.absolute_path))
    assert not errors, f"{path.name}: " + "; ".join(
        f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in errors[:5])
    names = []

    def walk(item):
        if isinstance(item, dict):
            if isinstance(item.get("name"), str):
                names.append(item["name"])
            for v in item.values():
                walk(v)
        elif isinstance(item, list):
            for v in item:
                walk(v)
    walk({k: v for k, v in doc.items() if k != "asset"})
    assert len(names) == len(set(names)), "names must be unique"
    for name in names:
        assert not set(name) & set('"#*.:|?@<>{}[]/\\%') and all(ord(ch) >= 0x20 for ch in name)

    dim = doc["asset"]["dimension"]
    mesh = doc["meshes"][0]
    vertices, vtype = accessor(doc, buffers, mesh["vertices"])
    assert vtype.startswith("float") and vertices.shape[1] == dim
    surface = mesh["surfaces"][0]
    edges, etype = accessor(doc, buffers, surface["edges"])
    assert etype.startswith("uint") and edges.shape[1] == 2 and edges.max() < len(vertices)
    tiers = []
    below = len(edges)
    for t, index in enumerate(surface.get("geometry", [])):
        flat, gtype = accessor(doc, buffers, index)
        assert gtype.startswith("uint") and flat.ndim == 1
        rows = lists(flat)
        assert all(0 <= m < below for r in rows for m in r)
        tiers.append(rows)
        below = len(rows)
    # Faces: consecutive edges share a vertex and close the loop.
    for face in tiers[0]:
        for a, b in zip(face, face[1:] + face[:1]):
            assert set(edges[a]) & set(edges[b]), f"face {face} is not a closed loop of edges"
    # Higher elements: the first two members share a boundary element.
    for t in range(1, len(tiers)):
        for row in tiers[t]:
            assert len(row) >= 2 and set(tiers[t - 1][row[0]]) & set(tiers[t - 1][row[1]])
    if "normals" in surface:
        values, ntype = accessor(doc, buffers, surface["normals"]["values"])
        assert ntype.startswith("float") and values.shape[1] == dim
        assert np.allclose(np.linalg.norm(values, axis=1), 1.0, atol=1e-9)
    if "textureMap" in surface:
        values, ttype = accessor(doc, buffers, surface["textureMap"]["values"])
        assert ttype.startswith("float")
        for g in surface["textureMap"]["geometry"]:
            assert g["geometryDimension"] == dim - 1 and g.get("decomposeDimension", 0) == 0
            corners = lists(accessor(doc, buffers, g["accessor"])[0])
            assert len(corners) == len(tiers[dim - 3])
            assert all(0 <= x < len(values) for c in corners for x in c)
    if dim == 4 and len(tiers) >= 2 and convex:
        # godot-4d's boundary normals (PolyMesh4D::_get_cell_face_4_vertex_index_sequence and
        # _compute_boundary_normals_based_on_cell_orientation) point away from the centre.
        centre = vertices.mean(axis=0)
        for cell in tiers[1]:
            a, b = tiers[0][cell[0]], tiers[0][cell[1]]
            ia, ib = next((i, b.index(e)) for i, e in enumerate(a) if e in b)
            start, end = edges[a[ia]]

            def far(e):
                x, y = edges[e]
                return y if x in (start, end) else x
            v = [far(a[(ia + 1) % len(a)]), start, end, far(b[(ib + 1) % len(b)])]
            p = vertices[v]
            normal = perpendicular_4d(p[1] - p[0], p[2] - p[0], p[3] - p[0])
            members = {int(x) for f in cell for e in tiers[0][f] for x in edges[e]}
            assert normal @ (vertices[sorted(members)].mean(axis=0) - centre) > 0
    return dim, vertices, edges, tiers


MODELS = [
    ("tesseract", True, [16, 32, 24, 8]),
    ("120-cell", True, [600, 1200, 720, 120]),
    ("great grand stellated 120-cell", False, [600, 1200, 720, 120]),
    ("spheritorus:2,1,8", False, None),
]


@pytest.mark.parametrize("spec,convex,fvector", MODELS, ids=[m[0] for m in MODELS])
@pytest.mark.parametrize("ext", ["g4tf", "g4b", "g4tf-bin"])
def test_models_validate(cli, tmp_path, validator, spec, convex, fvector, ext):
    out = tmp_path / ("m.g4b" if ext == "g4b" else "m.g4tf")
    cli("convert", spec, "-o", out, *(["--format", ext] if ext == "g4tf-bin" else []))
    assert (tmp_path / "m.bin").exists() == (ext == "g4tf-bin")
    dim, vertices, edges, tiers = check_document(out, validator, convex)
    counts = [len(vertices), len(edges)] + [len(t) for t in tiers]
    if fvector:
        assert counts[:4] == fvector
    # The Python module reads it back (through the model-spec parser) with the same counts.
    model = cw4d.load_model(str(out))
    assert list(model.fvector)[:len(counts)] == counts


def test_sections_validate(cli, tmp_path, validator):
    # A convex section, a star section and a scene's, as 3D G4MF meshes with UVW.
    cli("slice", "120-cell", "--normal", "1,2,3,4", "--offset", "0.3", "-o", tmp_path / "a.g4tf")
    cli("slice", "great grand stellated 120-cell", "--normal", "0.1,0.2,0.3,1", "--offset", "0.2",
        "-o", tmp_path / "b.g4b")
    cli("slice", "--scene", REPO / "data" / "example-scene.json", "--normal", "0,0,0,1",
        "--offset", "0.1", "--format", "g4tf-bin", "-o", tmp_path / "c.g4tf")
    cli("slice", "24-cell", "--method", "tet", "--normal", "1,1,1,1", "--offset", "0.3",
        "-o", tmp_path / "d.g4tf")
    for name in ("a.g4tf", "b.g4b", "c.g4tf", "d.g4tf"):
        dim, vertices, edges, tiers = check_document(tmp_path / name, validator)
        assert dim == 3
        doc, _ = load(tmp_path / name)
        assert "textureMap" in doc["meshes"][0]["surfaces"][0]


def test_sweep_and_net_validate(cli, tmp_path, validator):
    cli("sweep", "tesseract", "--normal", "1,1,1,1", "--from", "-1", "--to", "1", "--layers", "3",
        "--format", "g4b", "-o", tmp_path / "layers")
    files = sorted((tmp_path / "layers").glob("*.g4b"))
    assert len(files) == 3
    for f in files:
        check_document(f, validator)
    cli("net", "tesseract", "-o", tmp_path / "net.g4tf")
    check_document(tmp_path / "net.g4tf", validator)


@pytest.mark.parametrize("name,fvector", [
    ("pentachoron-tetra.g4tf", [5, 10, 10, 5]),
    ("tesseract-two-surfaces.g4b", [16, 32, 24, 8]),
    ("tesseract-external.g4tf", [16, 32, 24, 8]),
    ("cube-triangles.g4tf", [8, 12, 6]),
])
def test_samples(cli, validator, name, fvector):
    doc, _ = load(SAMPLES / name)
    assert validator.is_valid(doc)
    info = json.loads(cli("info", SAMPLES / name, "--json").stdout)
    assert info["fvector"] == fvector and info["valid"]


def test_the_module_writes_and_reads_g4mf(tmp_path, validator):
    model = cw4d.load_model("24-cell")
    files = cw4d.write_g4mf(str(tmp_path / "m.g4tf"), model, separate_buffer=True)
    assert [pathlib.Path(f).name for f in files] == ["m.bin", "m.g4tf"]
    check_document(tmp_path / "m.g4tf", validator, convex=True)
    back = cw4d.read_g4mf(str(tmp_path / "m.g4tf"))
    assert list(back.fvector) == list(model.fvector)
    assert np.array_equal(back.positions, model.positions)
    cut = cw4d.section(model, [1, 1, 1, 1], 0.5)
    cw4d.write_g4mf(str(tmp_path / "s.g4b"), cut, model=model, description="a cut")
    check_document(tmp_path / "s.g4b", validator)
    doc, _ = load(tmp_path / "s.g4b")
    assert doc["asset"]["extras"]["description"] == "a cut"
    assert "textureMap" in doc["meshes"][0]["surfaces"][0]
    with pytest.raises(cw4d.InputError):
        cw4d.write_g4mf(str(tmp_path / "x.obj"), model)
    with pytest.raises(cw4d.ParseError):
        cw4d.read_g4mf(str(tmp_path / "m.bin"))


@pytest.mark.parametrize("spec", ["120-cell", "spheritorus:2,1,8"])
def test_tetrahedra_validate(cli, tmp_path, validator, spec):
    # `cw4d tetrahedralize -o x.g4b`: godot-4d's tetrahedral mesh. Every simplex's normal (the
    # spec's perpendicular of its corners, as godot-4d's ArrayTetraMesh4D computes it) agrees
    # with its cell's outward normal.
    out = tmp_path / "t.g4b"
    cli("tetrahedralize", spec, "-o", out)
    doc, buffers = load(out)
    assert not list(validator.iter_errors(doc))
    mesh = doc["meshes"][0]
    surface = mesh["surfaces"][0]
    vertices, _ = accessor(doc, buffers, mesh["vertices"])
    simplexes, stype = accessor(doc, buffers, surface["simplexes"])
    assert stype.startswith("uint") and simplexes.shape[1] == 4
    normals, _ = accessor(doc, buffers, surface["normals"]["values"])
    per_simplex, _ = accessor(doc, buffers, surface["normals"]["perSimplex"])
    corner, _ = accessor(doc, buffers, surface["normals"]["simplexes"])
    assert len(per_simplex) == len(simplexes) and corner.shape == simplexes.shape
    uvw, _ = accessor(doc, buffers, surface["textureMap"]["values"])
    assert uvw.shape == (4 * len(simplexes), 3)
    for i, t in enumerate(simplexes):
        p = vertices[t]
        assert perpendicular_4d(p[1] - p[0], p[2] - p[0], p[3] - p[0]) @ normals[per_simplex[i]] > 0
    info = json.loads(cli("info", out, "--json").stdout)
    assert info["valid"] and info["fvector"][3] == len(simplexes)
