// ?selftest=1: the page's checks, written as one JSON object into <pre id="selftest">. The
// browser test (web/test/browser_test.py) compares the counts and volumes with the native
// `cw4d slice` and asserts the GPU/CPU coverage agreement and the error lines.
import { Renderer, iou, tetsFromBuffer } from './renderer.js';

const ROTATION_PLANES = ['xy', 'xz', 'xw', 'yz', 'yw', 'zw'];

// Models, placements (rotations in order, degrees) and planes of the comparison.
export const CASES = [
  { spec: 'tesseract', rotate: [['xw', 30], ['yw', 25], ['zw', 20]], normal: [0, 0, 0, 1], offset: 0.25 },
  { spec: '5-cell', rotate: [['xy', 10], ['zw', 40]], normal: [1, 1, 1, 1], offset: 0.1 },
  { spec: '24-cell', rotate: [['xw', 17]], normal: [1, 2, 3, 4], offset: 0.3 },
  { spec: '120-cell', rotate: [['xw', 10], ['yw', 20]], normal: [0, 0, 0, 1], offset: 0.5 },
  { spec: '600-cell', rotate: [['yz', 33], ['xw', 12]], normal: [0, 1, 0, 1], offset: 0.2 },
  { spec: 'omnitruncated 120-cell', rotate: [['xw', 5], ['zw', 9]], normal: [0, 0, 0, 1], offset: 3.0 },
  { spec: 'duoprism:5,7', rotate: [['xw', 30]], normal: [1, 1, 0, 1], offset: 0.2 },
  { spec: 'spheritorus:2,0.7,16', rotate: [['yw', 15]], normal: [0, 0, 0, 1], offset: 0.1 },
  { spec: 'tiger:2,2,0.6,12', rotate: [], normal: [0, 0, 1, 1], offset: 0.4 },
  { spec: 'cube:3', rotate: [['xz', 20]], normal: [0, 0, 1], offset: 0.3 },
  // Dropped files: Miratope's 24-cell and cantellated 24-cell.
  { file: 'samples/Icositetrachoron.off', rotate: [['xw', 20]], normal: [0, 0, 0, 1], offset: 0.1 },
  { file: 'samples/Cantellated icositetrachoron.off', rotate: [['yw', 7]],
    normal: [0, 0, 1, 1], offset: 0.05 },
  // A star polychoron: self-intersecting cells whose cuts start several loops at one vertex.
  { file: 'samples/Grand stellated hecatonicosachoron.off', rotate: [['yw', 7]],
    normal: [0, 0, 1, 1], offset: 0.05 },
  // Degenerate: the plane through a facet of the tesseract (the general path).
  { spec: 'tesseract', rotate: [], normal: [0, 0, 0, 1], offset: 1.0 },
];

// A sweep (one pass over the model) of a few layers, compared with native slices.
export const SWEEP = { spec: '120-cell', rotate: [['xw', 10], ['yw', 20]], normal: [0, 0, 0, 1],
  offsets: [-3.2, -1.7, 0.0, 0.9, 2.6] };

// The GPU tetrahedral path against the CPU path: same section, same coverage.
export const GPU_CASES = [
  { spec: 'tesseract', rotate: [['xw', 30], ['yw', 25], ['zw', 20]], normal: [0, 0, 0, 1], offset: 0.25 },
  { spec: '24-cell', rotate: [['xw', 17]], normal: [1, 2, 3, 4], offset: 0.3 },
  { spec: '120-cell', rotate: [['xw', 10], ['yw', 20]], normal: [0, 0, 0, 1], offset: 0.5 },
  { spec: 'omnitruncated 120-cell', rotate: [['xw', 5], ['zw', 9]], normal: [0, 0, 0, 1], offset: 3.0 },
  { spec: 'duoprism:5,7', rotate: [['xw', 30]], normal: [1, 1, 0, 1], offset: 0.2 },
];

 // The same comparison on the GPU buffers of the native `cw4d tetrahedralize SPEC -o NAME.bin`
// (served by the browser test under ?buffers=DIR): cones, cubes split in five, a non-convex model.
export const BUFFER_CASES = [
  { spec: '120-cell', name: '120-cell', rotate: [['xw', 10], ['yw', 20]], normal: [0, 0, 0, 1], offset: 0.5 },
  { spec: 'tesseract', name: 'tesseract', rotate: [['xw', 30], ['yw', 25], ['zw', 20]], normal: [0, 0, 0, 1], offset: 0.25 },
  { spec: 'tiger:2,2,0.6,12', name: 'tiger', rotate: [['xz', 25]], normal: [0, 0, 1, 1], offset: 0.4 },
];

// G4MF files (served by the browser test under ?buffers=DIR), opened as the viewer opens a
// picked or dropped file, as bytes: the native `cw4d convert` of two Miratope files (.g4tf with
// the buffer embedded, binary .g4b) and two samples of tests/data/g4mf written without cw4d's
// code (a binary tesseract in two surfaces; the 5-cell as bare tetrahedra).
// `twin`: the same model as a built-in spec or a sample file, whose native section must be
// the same too.
export const G4MF_CASES = [
  { g4mf: 'icositetrachoron.g4tf', twin: 'Icositetrachoron.off', rotate: [['xw', 20]],
    normal: [0, 0, 0, 1], offset: 0.1 },
  { g4mf: 'cantellated-icositetrachoron.g4b', twin: 'Cantellated icositetrachoron.off',
    rotate: [['yw', 7]], normal: [0, 0, 1, 1], offset: 0.05 },
  { g4mf: 'tesseract-two-surfaces.g4b', twin: 'tesseract', rotate: [['xw', 30], ['yw', 25], ['zw', 20]],
    normal: [0, 0, 0, 1], offset: 0.25 },
  { g4mf: 'pentachoron-tetra.g4tf', rotate: [['xy', 10], ['zw', 40]], normal: [1, 1, 1, 1], offset: 0.1 },
];
// Bad G4MF files: each must give one error line naming the file (the browser test compares it
// with the native CLI's message for the same bytes), the model loaded before staying loaded.
export const G4MF_BAD = ['bad-json.g4tf', 'truncated.g4b', 'tesseract-external.g4tf'];

export const BENCH = ['120-cell', 'omnitruncated 120-cell'];

// The core's tetrahedra (tets()) against a native GPU buffer's, entry by entry: the counts,
// the cells left out, the largest differences of corners and normals, the tetrahedra whose cell
// ids differ, and the UVW components that differ.
function sameTets(a, b) {
  if (a.error) return { error: a.error };
  const maxDiff = (x, y) => {
    let d = 0;
    for (let i = 0; i < Math.min(x.length, y.length); ++i) d = Math.max(d, Math.abs(x[i] - y[i]));
    return d;
  };
  let cells = 0;
  for (let t = 0; t < Math.min(a.count, b.count); ++t) cells += a.cells[t] !== b.cells[t] ? 1 : 0;
  // UVW components equal, or mirrored (u against 1 - u: a cell box frame turned the other way),
  // or neither.
  let mirrored = 0, uvwOther = 0;
  for (let i = 0; i < Math.min(a.uvw.length, b.uvw.length); ++i) {
    if (Math.abs(a.uvw[i] - b.uvw[i]) <= 1e-6) continue;
    if (Math.abs(a.uvw[i] + b.uvw[i] - 1) <= 1e-6) ++mirrored;
    else ++uvwOther;
  }
  return { count: a.count, nativeCount: b.count, skippedCells: a.skippedCells,
    corners: maxDiff(a.corners, b.corners), normals: maxDiff(a.normals, b.normals), cells,
    uvwMirrored: mirrored, uvwOther };
}

async function fetchBytes(url) {
  const res = await fetch(url);
  if (!res.ok) throw new Error(`cannot fetch ${url}: ${res.status}`);
  return new Uint8Array(await res.arrayBuffer());
}

async function load(core, c, buffers = null) {
  const m = new core.Model();
  let err;
  if (c.g4mf) {
    // The core takes a Uint8Array (what the viewer hands it) or an ArrayBuffer: both are used.
    const bytes = await fetchBytes(`${buffers}/${c.g4mf}`);
    err = m.loadG4mf(c.g4mf.endsWith('.g4tf') ? bytes.buffer : bytes, c.g4mf);
  } else if (c.file) {
    const res = await fetch(c.file);
    if (!res.ok) throw new Error(`cannot fetch ${c.file}: ${res.status}`);
    err = m.loadOff(await res.text(), c.file);
  } else {
    err = m.loadSpec(c.spec);
  }
  if (err) throw new Error(`${c.spec || c.file || c.g4mf}: ${err}`);
  const perr = m.setPlacement(c.rotate, []);
  if (perr) throw new Error(`${c.spec}: ${perr}`);
  return m;
}

function unit(n) {
  const len = Math.hypot(...n);
  return n.map((x) => x / len);
}

export async function runSelftest(core, canvas, buffers = null) {
  const out = { cases: [], sweep: null, gpu: [], buffers: [], bench: [], catalogue: [], errors: {},
    g4mfErrors: {} };
  for (const c of buffers ? CASES.concat(G4MF_CASES) : CASES) {
    const m = await load(core, c, buffers);
    const s = m.slice(c.normal, c.offset);
    if (s.error) throw new Error(`${c.spec || c.file || c.g4mf}: ${s.error}`);
    const info = m.info();
    out.cases.push({ spec: c.spec || null, file: c.file || null, g4mf: c.g4mf || null, twin: c.twin || null,
      modelFvector: info.fvector, rotate: c.rotate, normal: c.normal,
      offset: c.offset, fvector: s.fvector, volume: s.volume, general: s.general,
      triangles: s.indices ? s.indices.length / 3 : 0 });
    m.delete();
  }
  {
    const m = await load(core, SWEEP);
    const layers = m.sweep(SWEEP.normal, SWEEP.offsets);
    if (layers.error) throw new Error(`sweep: ${layers.error}`);
    out.sweep = { spec: SWEEP.spec, rotate: SWEEP.rotate, normal: SWEEP.normal,
      layers: SWEEP.offsets.map((d, i) => ({ offset: d, fvector: layers[i].fvector,
        volume: layers[i].volume })) };
    m.delete();
  }
  // Coverage of the two paths, rendered into the same 256 x 256 target with the same camera.
  const r = new Renderer(canvas);
  const target = r.target(256, 256);
  const compare = async (c, tetsOf, into) => {
    const m = await load(core, c);
    const info = m.info();
    const s = m.slice(c.normal, c.offset);
    const t = await tetsOf(m, info);
    if (t.error) throw new Error(`${c.spec}: ${t.error}`);
    r.setSection(s);
    r.setTets(t);
    const view = { yaw: 0.6, pitch: 0.45, distance: 3.2 * info.radius };
    const opts = { mask: true, backFaces: true, placement: m.placement(), normal: unit(c.normal),
      offset: c.offset, basis: m.planeBasis(c.normal) };
    r.draw(view, { ...opts, gpu: false }, target);
    const cpu = r.coverage(target);
    r.draw(view, { ...opts, gpu: true }, target);
    const gpu = r.coverage(target);
    const q = iou(cpu, gpu);
    into.push({ spec: c.spec, tets: t.count, skippedCells: t.skippedCells, iou: q.iou,
      cpuPixels: q.a, gpuPixels: q.b, same: t.same ?? null });
    m.delete();
  };
  for (const c of GPU_CASES) await compare(c, (m) => m.tets(), out.gpu);
  if (buffers) {
    for (const c of BUFFER_CASES) {
      await compare(c, async (m, info) => {
        const get = async (file) => {
          const res = await fetch(`${buffers}/${file}`);
          if (!res.ok) throw new Error(`cannot fetch ${buffers}/${file}: ${res.status}`);
          return res;
        };
        const header = await (await get(`${c.name}.json`)).json();
        const bytes = await (await get(header.buffer)).arrayBuffer();
        if (header.cells !== info.fvector[3])
          throw new Error(`${c.name}.json: ${header.cells} cells, the model has ${info.fvector[3]}`);
        const native = tetsFromBuffer(header, bytes, core.cellPalette(header.cells));
        native.same = sameTets(m.tets(), native);
        return native;
      }, out.buffers);
    }
  }
  for (const spec of BENCH) {
    const m = await load(core, { spec, rotate: [] });
    const b = m.benchHotPath(1.0);
    if (b.error) throw new Error(`${spec}: ${b.error}`);
    out.bench.push({ spec, us: b.us, triangles: b.triangles });
    m.delete();
  }
  const cat = core.catalogue();
  for (let i = 0; i < cat.length; ++i)
    out.catalogue.push({ spec: cat[i].spec, available: cat[i].available });
  // Bad input: one-line errors, no abort.
  const m = new core.Model();
  out.errors.spec = m.loadSpec('no-such-model');
  out.errors.off = m.loadOff('4OFF\n3 1 1 1\n0 0 0 0\nnot numbers\n', 'bad.4off');
  out.errors.noModel = m.slice([0, 0, 0, 1], 0).error || '';
  out.errors.g4mfNotBytes = m.loadG4mf('{"asset": {}}', 'text.g4tf');
  m.delete();
  if (buffers) {
    // A model is loaded first: a bad file must leave it loaded.
    const kept = await load(core, G4MF_CASES[0], buffers);
    const before = JSON.stringify(kept.info().fvector);
    for (const name of G4MF_BAD) {
      const err = kept.loadG4mf(await fetchBytes(`${buffers}/${name}`), name);
      const after = JSON.stringify(kept.info().fvector);
      out.g4mfErrors[name] = { error: err, kept: after === before };
    }
    kept.delete();
  }
  out.planes = ROTATION_PLANES;
  return out;
}
