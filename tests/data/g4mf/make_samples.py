#!/usr/bin/env python3
"""Writes the sample G4MF files of this folder from scratch, by the G4MF specification alone
(no cw4d code), the way other writers lay files out:

  pentachoron-tetra.g4tf      godot-4d's tetrahedral mesh style: only "simplexes" (the five
                              tetrahedra of the 5-cell's boundary, in arbitrary winding), one
                              color per simplex (baseColor elementMap perSimplex), no edges
  tesseract-two-surfaces.g4b  the tesseract as a binary file with two surfaces (two materials,
                              a plain color each): each surface lists its own edges (the second
                              one reversed) and faces, so the 8 faces between the two halves and
                              their edges appear in both; no cw4d extras
  tesseract-external.g4tf     the tesseract with float32 vertices, uint16 indices and its buffer
                              in tesseract-external.bin
  cube-triangles.g4tf         a 3D cube as 12 triangles with "polytopeSimplexes": the two
                              triangles of each square share their first vertex

Cells are ordered by the rule of the spec's topology.md as godot-4d reads it: the first two
faces share an edge, and the simplex (far end of the edge after the shared edge in the first
face, the shared edge's start and end, far end of the edge after it in the second face) has a
perpendicular vector pointing out of the tesseract.

Run from anywhere: python3 tests/data/g4mf/make_samples.py (the files are committed).
"""

import base64
import itertools
import json
import pathlib
import struct

HERE = pathlib.Path(__file__).resolve().parent


class Buffer:
    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def add(self, fmt, values, component, vector_size=1):
        while len(self.data) % 8:
            self.data.append(0)
        raw = struct.pack("<" + fmt * len(values), *values)
        view = {"byteLength": len(raw)}
        if self.data:
            view["byteOffset"] = len(self.data)
        self.views.append(view)
        self.data += raw
        acc = {"bufferView": len(self.views) - 1, "componentType": component}
        if vector_size != 1:
            acc["vectorSize"] = vector_size
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def document(self, dimension, rest, uri=None, chunk=False):
        buf = {"byteLength": len(self.data)}
        if chunk:
            buf["chunk"] = 1
        elif uri:
            buf["uri"] = uri
        else:
            buf["uri"] = "data:application/octet-stream;base64," + base64.b64encode(
                bytes(self.data)).decode()
        doc = {"asset": {"dimension": dimension, "generator": "cw4d tests/data/g4mf/make_samples.py"},
               "accessors": self.accessors, "bufferViews": self.views, "buffers": [buf]}
        doc.update(rest)
        return doc


def write_text(name, doc):
    (HERE / name).write_text(json.dumps(doc, indent="\t") + "\n")


def write_binary(name, doc, blob):
    text = json.dumps(doc, separators=(",", ":")).encode()
    size = len(text)
    text += b" " * (-len(text) % 16)
    total = 16 + 16 + len(text) + 16 + len(blob)
    out = struct.pack("<4sIQ", b"G4MF", 0, total)
    out += struct.pack("<4sIQ", b"JSON", 0, size) + text
    out += struct.pack("<4sIQ", b"BLOB", 0, len(blob)) + bytes(blob)
    (HERE / name).write_bytes(out)


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def perp4(a, b, c):
    """The spec's perpendicular_4d (math.md)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    cx, cy, cz, cw = c
    return [
        -ay * (bz * cw - bw * cz) + az * (by * cw - bw * cy) - aw * (by * cz - bz * cy),
        ax * (bz * cw - bw * cz) - az * (bx * cw - bw * cx) + aw * (bx * cz - bz * cx),
        -ax * (by * cw - bw * cy) + ay * (bx * cw - bw * cx) - aw * (bx * cy - by * cx),
        ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx),
    ]


def tesseract():
    """Vertices, edges, faces (edge cycles) and cells (face lists in G4MF order)."""
    verts = [list(p) for p in itertools.product((-1.0, 1.0), repeat=4)]
    edges = []
    edge_id = {}
    for a, b in itertools.combinations(range(16), 2):
        if sum(x != y for x, y in zip(verts[a], verts[b])) == 1:
            edge_id[frozenset((a, b))] = len(edges)
            edges.append((a, b))
    faces = []
    face_key = {}
    for i, j in itertools.combinations(range(4), 2):
        others = [k for k in range(4) if k not in (i, j)]
        for s0, s1 in itertools.product((-1.0, 1.0), repeat=2):
            def vertex(u, v):
                p = [0.0] * 4
                p[i], p[j], p[others[0]], p[others[1]] = u, v, s0, s1
                return verts.index(p)
            cycle = [vertex(-1, -1), vertex(1, -1), vertex(1, 1), vertex(-1, 1)]
            face = [edge_id[frozenset((cycle[q], cycle[(q + 1) % 4]))] for q in range(4)]
            face_key[frozenset(face)] = len(faces)
            faces.append(face)
    cells = []
    for axis in range(4):
        for sign in (-1.0, 1.0):
            members = [f for f, face in enumerate(faces)
                       if all(verts[v][axis] == sign for e in face for v in edges[e])]
            outward = [0.0] * 4
            outward[axis] = sign
            cells.append(order_cell(members, faces, edges, verts, outward))
    return verts, edges, faces, cells


def order_cell(members, faces, edges, verts, outward):
    for a, b in itertools.permutations(members, 2):
        common = [(ia, ib) for ia, ea in enumerate(faces[a]) for ib, eb in enumerate(faces[b])
                  if ea == eb]
        if not common:
            continue
        ia, ib = common[0]
        e = edges[faces[a][ia]]

        def far(next_edge):
            x = edges[next_edge]
            return x[1] if x[0] in e else x[0]

        v0 = far(faces[a][(ia + 1) % len(faces[a])])
        v3 = far(faces[b][(ib + 1) % len(faces[b])])
        n = perp4(sub(verts[e[0]], verts[v0]), sub(verts[e[1]], verts[v0]),
                  sub(verts[v3], verts[v0]))
        if sum(x * y for x, y in zip(n, outward)) > 0:
            return [a, b] + [f for f in members if f not in (a, b)]
    raise AssertionError("no ordering")


def flat(rows):
    out = []
    for r in rows:
        out += [len(r)] + list(r)
    return out


def pentachoron():
    verts = [[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    buf = Buffer()
    vacc = buf.add("f", [x for v in verts for x in v], "float32", 4)
    tets = [[v for v in range(5) if v != drop] for drop in range(5)]
    sacc = buf.add("B", [x for t in tets for x in t], "uint8", 4)
    colors = buf.add("f", [1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1], "float32", 4)
    per = buf.add("B", [0, 1, 2, 0, 1], "uint8")
    doc = buf.document(4, {
        "materials": [{"name": "Colors", "baseColor": {"elementMap": {"values": colors, "perSimplex": per}}}],
        "meshes": [{"name": "PentachoronMesh", "vertices": vacc,
                    "surfaces": [{"simplexes": sacc, "material": 0}]}],
        "nodes": [{"name": "Pentachoron", "meshInstance": {"mesh": 0}}],
    })
    write_text("pentachoron-tetra.g4tf", doc)


def tesseract_two_surfaces():
    verts, edges, faces, cells = tesseract()
    buf = Buffer()
    vacc = buf.add("d", [x for v in verts for x in v], "float64", 4)
    surfaces = []
    for part, reverse in (([0, 1, 2, 3], False), ([4, 5, 6, 7], True)):
        used_faces = sorted({f for c in part for f in cells[c]})
        used_edges = sorted({e for f in used_faces for e in faces[f]})
        local_edge = {e: q for q, e in enumerate(used_edges)}
        local_face = {f: q for q, f in enumerate(used_faces)}
        ends = [edges[e][::-1] if reverse else edges[e] for e in used_edges]
        # The second surface walks its faces the other way round (the same faces, reversed).
        rows = [[local_edge[e] for e in (faces[f][::-1] if reverse else faces[f])] for f in used_faces]
        # The cells ordered anew on the surface's own edges and faces.
        cell_rows = []
        for c in part:
            axis, sign = divmod(c, 2)
            outward = [0.0] * 4
            outward[axis] = 1.0 if sign else -1.0
            cell_rows.append(order_cell([local_face[f] for f in cells[c]], rows, ends, verts, outward))
        surfaces.append({
            "edges": buf.add("B", [v for e in ends for v in e], "uint8", 2),
            "geometry": [buf.add("B", flat(rows), "uint8"), buf.add("B", flat(cell_rows), "uint8")],
            "material": len(surfaces),
        })
    doc = buf.document(4, {
        "materials": [{"name": "Red", "baseColor": {"factor": [1, 0, 0, 1]}},
                      {"name": "Blue", "baseColor": {"factor": [0, 0, 1, 1]}}],
        "meshes": [{"name": "TesseractMesh", "vertices": vacc, "surfaces": surfaces}],
        "nodes": [{"name": "Tesseract", "children": [1]},
                  {"name": "TesseractInstance", "meshInstance": {"mesh": 0}}],
    }, chunk=True)
    write_binary("tesseract-two-surfaces.g4b", doc, buf.data)


def tesseract_external():
    verts, edges, faces, cells = tesseract()
    buf = Buffer()
    vacc = buf.add("f", [x for v in verts for x in v], "float32", 4)
    eacc = buf.add("H", [v for e in edges for v in e], "uint16", 2)
    geometry = [buf.add("H", flat(faces), "uint16"), buf.add("H", flat(cells), "uint16")]
    doc = buf.document(4, {
        "meshes": [{"vertices": vacc, "surfaces": [{"edges": eacc, "geometry": geometry}]}],
    }, uri="tesseract-external.bin")
    write_text("tesseract-external.g4tf", doc)
    (HERE / "tesseract-external.bin").write_bytes(bytes(buf.data))


def cube_triangles():
    verts = [list(p) for p in itertools.product((-1.0, 1.0), repeat=3)]
    squares = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, v = [k for k in range(3) if k != axis]
            def vertex(a, b):
                p = [0.0] * 3
                p[axis], p[u], p[v] = sign, a, b
                return verts.index(p)
            cycle = [vertex(-1, -1), vertex(1, -1), vertex(1, 1), vertex(-1, 1)]
            # Counter-clockwise seen from outside.
            a, b, c = (verts[cycle[q]] for q in range(3))
            n = [(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                 (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                 (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])]
            if n[axis] * sign < 0:
                cycle.reverse()
            squares.append(cycle)
    # Consecutive squares must not start at the same vertex (they would merge).
    tris = []
    last = None
    for sq in squares:
        if sq[0] == last:
            sq = sq[1:] + sq[:1]
        tris += [[sq[0], sq[1], sq[2]], [sq[0], sq[2], sq[3]]]
        last = sq[0]
    buf = Buffer()
    vacc = buf.add("d", [x for v in verts for x in v], "float64", 3)
    sacc = buf.add("B", [x for t in tris for x in t], "uint8", 3)
    doc = buf.document(3, {
        "meshes": [{"name": "CubeMesh", "vertices": vacc,
                    "surfaces": [{"simplexes": sacc, "polytopeSimplexes": True}]}],
        "nodes": [{"name": "Cube", "meshInstance": {"mesh": 0}}],
    })
    write_text("cube-triangles.g4tf", doc)


if __name__ == "__main__":
    pentachoron()
    tesseract_two_surfaces()
    tesseract_external()
    cube_triangles()
