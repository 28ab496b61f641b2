// The viewer's plain modules under Node's test runner (no browser): the 4D rotations of
// math4.js against their defining properties and the native convention, and the section files
// of exporters.js read back by independent readers (a parser of our own for OBJ and STL, the
// Khronos glTF-Validator for GLB).
//   node --test web/test/modules_test.mjs   (the validator from tests/tools/node_modules)
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import path from 'node:path';
import { identity, multiply, transpose, apply, planeRotation, coordinateRotation,
  orthonormalize, fromRotations, glMatrix4 } from '../js/math4.js';
import { sectionObj, sectionStl, sectionGlb } from '../js/exporters.js';

const here = path.dirname(fileURLToPath(import.meta.url));
const close = (a, b, tol = 1e-12) => a.every((x, i) => Math.abs(x - b[i]) <= tol);

// A seeded generator (mulberry32), so every run checks the same matrices.
function random(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

function det(m, n) {
  if (n === 1) return m[0];
  let sum = 0;
  for (let c = 0; c < n; ++c) {
    const minor = [];
    for (let r = 1; r < n; ++r) for (let k = 0; k < n; ++k) if (k !== c) minor.push(m[r * n + k]);
    sum += (c % 2 ? -1 : 1) * m[c] * det(minor, n - 1);
  }
  return sum;
}

test('a plane rotation turns u towards v, fixes what is orthogonal to both, and is a rotation', () => {
  const rnd = random(20261205);
  for (let trial = 0; trial < 50; ++trial) {
    const u = [0, 1, 2, 3].map(() => rnd() - 0.5), v = [0, 1, 2, 3].map(() => rnd() - 0.5);
    const a = (rnd() - 0.5) * 6;
    const g = planeRotation(u, v, a, 4);
    assert.ok(close(multiply(g, transpose(g, 4), 4), identity(4), 1e-12), 'G G^T = I');
    assert.ok(Math.abs(det(g, 4) - 1) < 1e-12, 'det G = 1');
    // Orthonormal e1 = u/|u|, e2 = the part of v orthogonal to u: G e1 = cos a e1 + sin a e2.
    const lu = Math.hypot(...u), e1 = u.map((x) => x / lu);
    const d = v.reduce((s, x, i) => s + x * e1[i], 0);
    const w = v.map((x, i) => x - d * e1[i]), lw = Math.hypot(...w), e2 = w.map((x) => x / lw);
    assert.ok(close(apply(g, e1, 4), e1.map((x, i) => Math.cos(a) * x + Math.sin(a) * e2[i]), 1e-12));
    // A vector orthogonal to u and v is fixed: the generalized cross product of u, v and a third.
    const z = [0, 1, 2, 3].map(() => rnd() - 0.5);
    const p = z.map((x, i) => x - z.reduce((s, y, k) => s + y * e1[k], 0) * e1[i]);
    const q = p.map((x, i) => x - p.reduce((s, y, k) => s + y * e2[k], 0) * e2[i]);
    assert.ok(close(apply(g, q, 4), q, 1e-12), 'the orthogonal complement is fixed');
  }
  assert.equal(planeRotation([1, 0, 0, 0], [2, 0, 0, 0], 1, 4), null, 'parallel vectors span no plane');
});

test('coordinate rotations follow the CLI: --rotate xw:A takes e_x to cos A e_x + sin A e_w', () => {
  const a = 30 * Math.PI / 180;
  const g = coordinateRotation('xw', 30, 4);
  assert.ok(close(apply(g, [1, 0, 0, 0], 4), [Math.cos(a), 0, 0, Math.sin(a)], 1e-15));
  assert.ok(close(apply(g, [0, 1, 0, 0], 4), [0, 1, 0, 0], 0));
  // Rotations listed in order compose on the left: R = R_2 R_1.
  const r = fromRotations([['xw', 30], ['yz', 20]], 4);
  assert.ok(close(r, multiply(coordinateRotation('yz', 20, 4), g, 4), 1e-15));
  assert.equal(coordinateRotation('zw', 10, 3), null, 'a 3D model has no w');
});

test('orthonormalize repairs drift and refuses a singular matrix', () => {
  let r = identity(4);
  const g = planeRotation([1, 2, 0, 1], [0, 1, 3, -1], 0.01, 4);
  for (let i = 0; i < 2000; ++i) r = multiply(g, r, 4).map((x) => x * (1 + 1e-9));
  const o = orthonormalize(r, 4);
  assert.ok(close(multiply(o, transpose(o, 4), 4), identity(4), 1e-12));
  assert.ok(close(o, r, 1e-5), 'the repair moves the matrix only by its drift');
  assert.equal(orthonormalize([1, 0, 0, 0, 1, 0, 0, 0, 0], 3), null);
});

test('glMatrix4 is column-major and embeds a 3 x 3 placement with w untouched', () => {
  const m = glMatrix4([1, 2, 3, 4, 5, 6, 7, 8, 9], 3);
  assert.deepEqual([...m], [1, 4, 7, 0, 2, 5, 8, 0, 3, 6, 9, 0, 0, 0, 0, 1]);
});

// A section as the core returns it: two triangles of a unit square in the plane z = 0.5 and one
// triangle facing x, corners with positions, normals and colours.
const SECTION = {
  positions: new Float32Array([0, 0, 0.5, 1, 0, 0.5, 1, 1, 0.5, 0, 1, 0.5, 2, 0, 0, 2, 1, 0, 2, 0, 1]),
  normals: new Float32Array([0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 1, 0, 0]),
  colours: new Float32Array(21).fill(0.5),
  indices: new Uint32Array([0, 1, 2, 0, 2, 3, 4, 5, 6]),
};

test('OBJ: one v and vn per corner, one face per triangle, ids from 1', async () => {
  const text = await sectionObj(SECTION, 'test').text();
  const lines = text.split('\n');
  const v = lines.filter((l) => l.startsWith('v ')).map((l) => l.split(' ').slice(1).map(Number));
  const f = lines.filter((l) => l.startsWith('f ')).map((l) => l.split(' ').slice(1).map((c) => Number(c.split('//')[0])));
  assert.equal(v.length, 7);
  assert.equal(lines.filter((l) => l.startsWith('vn ')).length, 7);
  assert.deepEqual(f, [[1, 2, 3], [1, 3, 4], [5, 6, 7]]);
  assert.ok(close(v[2], [1, 1, 0.5], 0));
});

test('STL: 84 + 50 n bytes, unit normals from the winding, the corners as given', async () => {
  const bytes = new DataView(await sectionStl(SECTION).arrayBuffer());
  assert.equal(bytes.byteLength, 84 + 50 * 3);
  assert.equal(bytes.getUint32(80, true), 3);
  const normal = (t) => [0, 1, 2].map((j) => bytes.getFloat32(84 + 50 * t + 4 * j, true));
  assert.ok(close(normal(0), [0, 0, 1], 1e-7));
  assert.ok(close(normal(2), [1, 0, 0], 1e-7), 'the third triangle winds about +x');
  const corner = (t, k) => [0, 1, 2].map((j) => bytes.getFloat32(84 + 50 * t + 12 + 12 * k + 4 * j, true));
  assert.ok(close(corner(1, 2), [0, 1, 0.5], 0));
});

test('GLB: the Khronos glTF-Validator finds no error, and the accessors hold the section', async () => {
  const require = createRequire(path.join(here, '../../tests/tools/package.json'));
  const validator = require('gltf-validator');
  const bytes = new Uint8Array(await sectionGlb(SECTION, 'test').arrayBuffer());
  const report = await validator.validateBytes(bytes);
  assert.equal(report.issues.numErrors, 0, JSON.stringify(report.issues.messages));
  assert.equal(report.info.totalTriangleCount ?? 3, 3);
  // The JSON chunk: three attributes of 7 corners, 9 indices, min/max of the positions.
  const view = new DataView(bytes.buffer);
  const jsonLength = view.getUint32(12, true);
  const gltf = JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + jsonLength)));
  assert.deepEqual(gltf.accessors.map((a) => a.count), [7, 7, 7, 9]);
  assert.deepEqual(gltf.accessors[0].min, [0, 0, 0]);
  assert.deepEqual(gltf.accessors[0].max, [2, 1, 1]);
});
