// A JavaScript port of the tetrahedral slicing kernel of Tesserxel (Hqak, "Tesserxel: WebGPU based
// 3D screen renderer for 4D objects", github.com/wxyhly/tesserxel, 2022: the compute pass that
// TetraSlicePipeline generates), the reference cw4d's hot slice is timed against.
//
// Per tetrahedron, as that kernel does: the four signed heights of its corners above the plane,
// the side of each (height >= 0), and when the corners are not all on one side, a point on each
// of the six edges (in the order 01 02 03 12 13 23) whose ends differ, interpolating every
// attribute the tetrahedron carries, each a vec4 (position, normal, uvw + cell id), at
// alpha = h_a / (h_a - h_b); three points give one triangle, four give two (0 1 2 and 2 1 3).
// The triangles' corners are written, unindexed, into one array per attribute (vec4 each, as
// the kernel's output buffers), all allocated once for the largest output (six corners per
// tetrahedron): a slice allocates nothing. Written for speed under V8 (typed arrays, one
// monomorphic loop, no closures in it). Unlike Tesserxel's kernel it does not first move each
// corner into camera space (four matrix products per tetrahedron): the heights are dot
// products with the plane's normal, which leaves the port less work than the GPU kernel does.
//
// The tetrahedra are the ones cw4d itself makes (`cw4d tetrahedralize MODEL -o mesh.bin`: per
// tetrahedron 4 corners x 12 float32, position vec4, normal vec4, uvw vec4 with the source cell
// id in w; tetrahedralize/include/cw4d/tetrahedralize/tet_io.hpp).
//
//   node tet_slice.mjs time MESH.bin [MIN_SECONDS]
//       ns per slice over planes with the normal (0.5377, 1.8339, -2.2588, 0.8622) normalised
//       and 256 offsets evenly spaced inside +-0.95 x the largest vertex norm, cycled (the same
//       planes as bench_compare's "offsets" case); prints "js <ns per slice> <triangles per
//       slice>" (process CPU time, after a warm-up that lets V8 optimise the loop)
//   node tet_slice.mjs check CW4D_EXECUTABLE
//       for several models and planes, the total area of the port's triangles against the area
//       of `cw4d slice --triangulate` (the CW section, independent of the tetrahedra); exit 1 on
//       a mismatch
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

const STRIDE = 12;  // floats per corner
const TET = 48;     // floats per tetrahedron

export function loadMesh(path) {
  const bytes = readFileSync(path);
  if (bytes.byteLength % (TET * 4) !== 0) throw new Error(`${path}: not a cw4d .bin tet buffer`);
  // A copy into an aligned Float32Array (the file is little endian, as is every host node runs on).
  const data = new Float32Array(bytes.byteLength / 4);
  new Uint8Array(data.buffer).set(bytes);
  return data;
}

export class TetSlicer {
  constructor(data) {
    this.data = data;
    this.tets = data.length / TET;
    const corners = 6 * this.tets;
    this.position = new Float32Array(4 * corners);
    this.normal = new Float32Array(4 * corners);
    this.uvw = new Float32Array(4 * corners);
    this.count = 0;  // corners written by the last slice (3 per triangle)
  }

  // The plane n . x = d (n unit). Returns the number of triangles.
  slice(nx, ny, nz, nw, d) {
    const src = this.data, P = this.position, N = this.normal, U = this.uvw;
    const tets = this.tets;
    let o = 0;  // output corner
    for (let t = 0, b = 0; t < tets; ++t, b += TET) {
      const h0 = nx * src[b] + ny * src[b + 1] + nz * src[b + 2] + nw * src[b + 3] - d;
      const h1 = nx * src[b + 12] + ny * src[b + 13] + nz * src[b + 14] + nw * src[b + 15] - d;
      const h2 = nx * src[b + 24] + ny * src[b + 25] + nz * src[b + 26] + nw * src[b + 27] - d;
      const h3 = nx * src[b + 36] + ny * src[b + 37] + nz * src[b + 38] + nw * src[b + 39] - d;
      const s0 = h0 >= 0 ? 1 : 0, s1 = h1 >= 0 ? 1 : 0, s2 = h2 >= 0 ? 1 : 0, s3 = h3 >= 0 ? 1 : 0;
      const above = s0 + s1 + s2 + s3;
      if (above === 0 || above === 4) continue;
      // Crossing points k = 0, 1, 2 go to output corners o, o+1, o+2; a fourth to o+5, and the
      // second triangle repeats o+2 and o+1 as o+3 and o+4.
      let k = 0;
      if (s0 !== s1) emit(src, b, b + 12, h0 / (h0 - h1), P, N, U, slot(o, k++));
      if (s0 !== s2) emit(src, b, b + 24, h0 / (h0 - h2), P, N, U, slot(o, k++));
      if (s0 !== s3) emit(src, b, b + 36, h0 / (h0 - h3), P, N, U, slot(o, k++));
      if (s1 !== s2) emit(src, b + 12, b + 24, h1 / (h1 - h2), P, N, U, slot(o, k++));
      if (s1 !== s3) emit(src, b + 12, b + 36, h1 / (h1 - h3), P, N, U, slot(o, k++));
      if (s2 !== s3) emit(src, b + 24, b + 36, h2 / (h2 - h3), P, N, U, slot(o, k++));
      if (k === 4) {
        copy4(P, N, U, o + 2, o + 3);
        copy4(P, N, U, o + 1, o + 4);
        o += 6;
      } else {
        o += 3;
      }
    }
    this.count = o;
    return o / 3;
  }
}

function slot(o, k) {
  return k === 3 ? o + 5 : o + k;
}

// Corner c of the output: mix(a, b, alpha) of the three vec4 attributes of corners a and b.
function emit(src, a, b, alpha, P, N, U, c) {
  const q = 4 * c;
  const beta = 1 - alpha;
  P[q] = beta * src[a] + alpha * src[b];
  P[q + 1] = beta * src[a + 1] + alpha * src[b + 1];
  P[q + 2] = beta * src[a + 2] + alpha * src[b + 2];
  P[q + 3] = beta * src[a + 3] + alpha * src[b + 3];
  N[q] = beta * src[a + 4] + alpha * src[b + 4];
  N[q + 1] = beta * src[a + 5] + alpha * src[b + 5];
  N[q + 2] = beta * src[a + 6] + alpha * src[b + 6];
  N[q + 3] = beta * src[a + 7] + alpha * src[b + 7];
  U[q] = beta * src[a + 8] + alpha * src[b + 8];
  U[q + 1] = beta * src[a + 9] + alpha * src[b + 9];
  U[q + 2] = beta * src[a + 10] + alpha * src[b + 10];
  U[q + 3] = beta * src[a + 11] + alpha * src[b + 11];
}

// Output corner `to` = corner `from` (element by element: a typed array's copyWithin is a call
// into the runtime, far slower for four floats).
function copy4(P, N, U, from, to) {
  const f = 4 * from, q = 4 * to;
  P[q] = P[f];
  P[q + 1] = P[f + 1];
  P[q + 2] = P[f + 2];
  P[q + 3] = P[f + 3];
  N[q] = N[f];
  N[q + 1] = N[f + 1];
  N[q + 2] = N[f + 2];
  N[q + 3] = N[f + 3];
  U[q] = U[f];
  U[q + 1] = U[f + 1];
  U[q + 2] = U[f + 2];
  U[q + 3] = U[f + 3];
}

// The largest norm of a corner's position (cw4d::max_radius of the model, in float32).
export function maxRadius(data) {
  let r2 = 0;
  for (let i = 0; i < data.length; i += STRIDE) {
    const v = data[i] * data[i] + data[i + 1] * data[i + 1] + data[i + 2] * data[i + 2] +
              data[i + 3] * data[i + 3];
    if (v > r2) r2 = v;
  }
  return Math.sqrt(r2);
}

// The benchmark's planes: the fixed generic normal, 256 offsets inside +-0.95 radius.
export function benchPlanes(radius) {
  const n = [0.5377, 1.8339, -2.2588, 0.8622];
  const len = Math.hypot(...n);
  const offsets = new Float64Array(256);
  for (let i = 0; i < 256; ++i) offsets[i] = radius * (-0.95 + (1.9 * (i + 0.5)) / 256);
  return { n: n.map((x) => x / len), offsets };
}

function cpuNs() {
  const u = process.cpuUsage();
  return (u.user + u.system) * 1e3;
}

function time(path, minSeconds) {
  const slicer = new TetSlicer(loadMesh(path));
  const { n, offsets } = benchPlanes(maxRadius(slicer.data));
  const [nx, ny, nz, nw] = n;
  let sink = 0;
  // Warm-up: enough slices for V8's optimising tier, and at least 0.1 s.
  const w0 = cpuNs();
  for (let i = 0; i < 2048 || cpuNs() - w0 < 1e8; ++i) sink += slicer.slice(nx, ny, nz, nw, offsets[i & 255]);
  let total = 0, triangles = 0, elapsed = 0, batch = 16;
  while (elapsed < minSeconds * 1e9) {
    const t0 = cpuNs();
    for (let i = 0; i < batch; ++i) triangles += slicer.slice(nx, ny, nz, nw, offsets[(total + i) & 255]);
    elapsed += cpuNs() - t0;
    total += batch;
    if (batch < 1 << 16) batch *= 2;
    sink += slicer.position[0];
  }
  console.log(`js ${(elapsed / total).toPrecision(6)} ${(triangles / total).toPrecision(6)}`);
  if (sink === 0.123456789) console.log("");
}

// Area of the triangles (4D corners) of the last slice.
export function sliceArea(slicer) {
  const P = slicer.position;
  let area = 0;
  for (let c = 0; c < slicer.count; c += 3) {
    const a = 4 * c, b = a + 4, e = a + 8;
    let uu = 0, vv = 0, uv = 0;
    for (let i = 0; i < 4; ++i) {
      const u = P[b + i] - P[a + i], v = P[e + i] - P[a + i];
      uu += u * u;
      vv += v * v;
      uv += u * v;
    }
    area += 0.5 * Math.sqrt(Math.max(0, uu * vv - uv * uv));
  }
  return area;
}

// Area of the faces of an OBJ file (triangles in 3D, `f` records, 1-based indices).
function objArea(text) {
  const v = [];
  let area = 0, faces = 0;
  for (const line of text.split("\n")) {
    const f = line.trim().split(/\s+/);
    if (f[0] === "v") {
      v.push([Number(f[1]), Number(f[2]), Number(f[3])]);
    } else if (f[0] === "f") {
      const idx = f.slice(1).map((s) => Number(s.split("/")[0]) - 1);
      for (let k = 1; k + 1 < idx.length; ++k) {
        const p = v[idx[0]], q = v[idx[k]], r = v[idx[k + 1]];
        const u = [q[0] - p[0], q[1] - p[1], q[2] - p[2]], w = [r[0] - p[0], r[1] - p[1], r[2] - p[2]];
        area += 0.5 * Math.hypot(u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]);
      }
      ++faces;
    }
  }
  return { area, faces };
}

function check(cw4d) {
  const dir = mkdtempSync(join(tmpdir(), "cw4d-js-"));
  let failures = 0, checks = 0;
  try {
    const planes = [
      [[0.5377, 1.8339, -2.2588, 0.8622], 0.1],
      [[0.5377, 1.8339, -2.2588, 0.8622], -0.55],
      [[1, 2, 3, 4], 0.37],
      [[-0.3, 0.2, 0.9, -0.4], 0.71],
    ];
    for (const model of ["tesseract", "24-cell", "120-cell", "600-cell", "duoprism:32,32"]) {
      const bin = join(dir, "mesh.bin");
      execFileSync(cw4d, ["tetrahedralize", model, "-o", bin]);
      const slicer = new TetSlicer(loadMesh(bin));
      const radius = maxRadius(slicer.data);
      for (const [normal, frac] of planes) {
        const len = Math.hypot(...normal);
        const d = frac * radius;
        const obj = join(dir, "slice.obj");
        execFileSync(cw4d, ["slice", model, "--normal", normal.join(","), "--offset", String(d),
                            "--triangulate", "-o", obj]);
        const cw = objArea(readFileSync(obj, "utf8"));
        const tris = slicer.slice(normal[0] / len, normal[1] / len, normal[2] / len, normal[3] / len, d);
        const js = sliceArea(slicer);
        const rel = Math.abs(js - cw.area) / Math.max(cw.area, 1e-300);
        const ok = cw.faces > 0 && tris > 0 && rel < 1e-5;
        ++checks;
        if (!ok) ++failures;
        console.log(`${ok ? "ok  " : "FAIL"} ${model} n=(${normal}) d=${d.toFixed(4)}: ` +
                    `port ${tris} triangles, area ${js.toPrecision(9)}; cw4d ${cw.faces} triangles, ` +
                    `area ${cw.area.toPrecision(9)} (relative difference ${rel.toExponential(2)})`);
      }
    }
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
  console.log(`${checks - failures}/${checks} slices agree`);
  return failures === 0 && checks > 0;
}

const [mode, arg, extra] = process.argv.slice(2);
if (mode === "time" && arg) {
  time(arg, extra ? Number(extra) : 0.25);
} else if (mode === "check" && arg) {
  process.exitCode = check(arg) ? 0 : 1;
} else if (import.meta.url === `file://${process.argv[1]}`) {
  console.error("usage: node tet_slice.mjs time MESH.bin [MIN_SECONDS] | check CW4D_EXECUTABLE");
  process.exitCode = 2;
}
