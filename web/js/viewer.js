// The cw4d viewer: a 4D model placed by a rotation R (world = R . model), cut live by the
// hyperplane n.x = d in the WebAssembly core (or on the GPU, one instance per tetrahedron), and
// drawn with WebGL2 inside the whole polytope's wireframe. Rotations are composed here: a drag
// with Shift turns the model in the planes that mix the hyperplane's normal with the screen's
// own axes (relative to the camera, as Tesserxel does), keys 1-6 in the coordinate planes. The
// view is kept in the URL so that it can be shared.
import { Renderer, tetsFromBuffer, orbitView } from './renderer.js';
import { runSelftest } from './selftest.js';
import { COORDINATE_PLANES, identity, multiply, planeRotation, coordinateRotation, orthonormalize, fromRotations, glMatrix4 } from './math4.js';
import { sectionObj, sectionStl, sectionGlb, saveBlob } from './exporters.js';
import { libraryGroups } from './library.js';

const $ = (id) => document.getElementById(id);
const fmt = (x) => (Math.abs(x) < 1e-12 ? '0' : Number(x.toPrecision(6)).toString());
const WHOLE_MODES = ['shadow', 'persp', 'off'];
const ANIMATIONS = ['sweep', ...COORDINATE_PLANES];
const DEFAULT_MODEL = '120-cell';
// The first view: the 120-cell turned off its axes and cut a third of the way out, so that the
// section shows dozens of cells at once, inside the shadow of the rest.
const DEFAULT_TURN = [['xw', 28], ['yw', 17], ['zw', 9], ['xy', 12]];
const DEFAULT_OFFSET = 0.34;  // times the model's radius
const DEFAULT_CAMERA = { yaw: 35, pitch: 22, zoom: 4.2 };
// A spec made only of x/o/s nodes and branch numbers is a Coxeter diagram.
const DIAGRAM = /^[xos](\d+(\/\d+)?[xos])+$/i;
const specOf = (text) => (DIAGRAM.test(text) ? `wythoff:${text}` : text);

function defaultRotation(n) {
  return fromRotations(DEFAULT_TURN.filter(([p]) => n === 4 || !p.includes('w')), n);
}

// The view from the page's configuration (the one-file export of `cw4d view`), then the URL.
// The rotation is read once the model's dimension is known (R has n * n numbers).
function readState(config) {
  const q = new URLSearchParams(location.search);
  const get = (k, fallback) => (q.has(k) ? q.get(k) : (config[k] ?? fallback));
  const num = (k, fallback) => {
    const v = Number(get(k, fallback));
    return Number.isFinite(v) ? v : fallback;
  };
  const list = (k) => String(get(k, '')).split(',').filter((x) => x !== '').map(Number);
  const cam = list('cam');
  const camera = (i, fallback) => (Number.isFinite(cam[i]) ? cam[i] : fallback);
  const flag = (k, fallback) => String(get(k, fallback ? '1' : '0')) !== '0';
  const oneOf = (k, values, fallback) => (values.includes(get(k, fallback)) ? get(k, fallback) : fallback);
  const rotations = [];
  for (const part of String(get('rot', '')).split(',').filter(Boolean)) {
    const [plane, deg] = part.split(':');
    if (/^[xyzw]{2}$/.test(plane) && Number.isFinite(Number(deg))) rotations.push([plane, Number(deg)]);
  }
  const normal = list('n');
  return {
    model: String(get('model', DEFAULT_MODEL)),
    matrix: list('R'), rotations,
    normal: normal.length && normal.every(Number.isFinite) && normal.some((x) => x !== 0) ? normal : null,
    offset: num('d', NaN),  // NaN: the default, once the model's radius is known
    yaw: camera(0, DEFAULT_CAMERA.yaw) * Math.PI / 180,
    pitch: Math.max(-89, Math.min(89, camera(1, DEFAULT_CAMERA.pitch))) * Math.PI / 180,
    zoom: camera(2, DEFAULT_CAMERA.zoom) > 0 ? Math.min(20, camera(2, DEFAULT_CAMERA.zoom)) : 0,
    whole: oneOf('whole', WHOLE_MODES, 'shadow'), anim: oneOf('anim', ANIMATIONS, 'sweep'),
    playing: flag('play', false), slab: Math.max(0, Math.min(1, num('slab', 0))),
    edges: flag('edges', true), colours: flag('colours', true), back: flag('back', false),
    gpu: flag('gpu', false), texture: flag('tex', false),
  };
}

// The browser compiles a WebAssembly function the first time it runs, so the first slice of a
// page also pays for compiling the slicer (tens of milliseconds, against a fraction of one for
// the slices after it, whatever the model). A throwaway model is cut once through a generic plane
// and once through a vertex (the general path) before the first view, so that the slice time the
// panel shows is the slice's.
function warmUp(core) {
  const m = new core.Model();
  try {
    if (m.loadSpec('tesseract') === '') {
      m.slice([0.1, 0.2, 0.3, 0.9], 0.1);
      m.slice([0, 0, 0, 1], 1);
    }
  } finally {
    m.delete();
  }
}

export async function start(createCw4d, config = {}) {
  const core = await createCw4d();
  warmUp(core);
  const canvas = $('view');
  const query = new URLSearchParams(location.search);
  if (query.get('selftest') === '1') {
    const pre = $('selftest');
    try {
      const result = await runSelftest(core, canvas, query.get('buffers'));
      pre.textContent = JSON.stringify({ ok: true, ...result });
    } catch (e) {
      pre.textContent = JSON.stringify({ ok: false, error: String(e && e.message || e) });
    }
    // The browser test's own server takes the result (the timed checks cannot run under
    // --dump-dom's virtual time, which stands still while a script runs).
    if (query.get('report') === '1')
      await fetch('selftest-result', { method: 'POST', body: pre.textContent });
    return;
  }
  const initial = readState(config);
  const state = { ...initial, dim: 4, R: identity(4), normal: initial.normal || [0, 0, 0, 1] };
  const renderer = new Renderer(canvas);
  let model = new core.Model();
  let info = null, fromFile = null, section = null, tets = null, sliced = false;
  let firstLoad = true, errorFrom = null;

  // --- status: an error stays until the input that caused it (or a later one) is valid -----
  const status = (text, isError = false, source = null) => {
    $('status').textContent = text;
    $('status').className = isError ? 'error' : '';
    errorFrom = isError ? source : null;
  };
  const clearError = () => {
    if ($('status').className === 'error') status('');
  };

  // --- the picker and the library -----------------------------------------------------------
  const picker = $('model');
  const groups = libraryGroups(core);
  const current = document.createElement('optgroup');
  current.label = 'shown now';
  picker.appendChild(current);
  for (const g of groups) {
    const og = document.createElement('optgroup');
    og.label = g.group;
    for (const e of g.entries) og.appendChild(new Option(e.diagram ? `${e.name} (${e.diagram})` : e.name, e.spec));
    picker.appendChild(og);
  }
  const showPicked = () => {
    // The model being viewed is selected; one the lists do not hold gets an option of its own.
    current.textContent = '';
    const wanted = fromFile ? `file:${fromFile}` : state.model;
    const listed = [...picker.options].find((o) => o.value === wanted);
    if (listed) {
      current.hidden = true;
    } else {
      current.appendChild(new Option(fromFile || state.model, wanted));
      current.hidden = false;
    }
    // The selected attribute too, so that a saved or printed page names its model.
    for (const o of picker.options) o.defaultSelected = o.value === wanted;
    picker.value = wanted;
  };
  const libraryBox = $('library-groups');
  for (const g of groups) {
    const h = document.createElement('h3');
    h.textContent = g.group;
    const div = document.createElement('div');
    div.className = 'entries';
    for (const e of g.entries) {
      const b = document.createElement('button');
      b.dataset.spec = e.spec;
      b.textContent = e.name;
      if (e.diagram) {
        const small = document.createElement('small');
        small.textContent = e.diagram;
        b.appendChild(small);
      }
      b.addEventListener('click', () => {
        if (loadSpec(e.spec, 'library')) $('library').hidden = true;
      });
      div.appendChild(b);
    }
    libraryBox.append(h, div);
  }
  const cat = core.catalogue();
  const unavailable = [];
  for (let i = 0; i < cat.length; ++i) if (!cat[i].available) unavailable.push(cat[i].spec);
  const note = document.createElement('p');
  note.className = 'note';
  note.textContent = `Also by spec in the box of the panel: simplex:N, cube:N, orthoplex:N, ` +
    `duoprism:P,Q, prism:MODEL, product:A*B, pyramid:MODEL, dual:MODEL, wythoff:DIAGRAM, ` +
    `round shapes and toratopes with your own parameters. Native only (cw4d CLI): ` +
    `${unavailable.join(', ')}.`;
  libraryBox.appendChild(note);

  // --- geometry of the view -----------------------------------------------------------------
  const n = () => state.dim;
  const unitNormal = () => {
    const len = Math.hypot(...state.normal);
    return state.normal.map((x) => x / len);
  };
  // The hyperplane's orthonormal basis (n x (n-1), column-major) from the core.
  let basisCache = null;
  const basis = () => {
    const key = state.normal.join(',');
    if (!basisCache || basisCache.key !== key)
      basisCache = { key, b: model.planeBasis(state.normal) };
    return basisCache.b;
  };
  // The basis as four rows by three columns for the shaders. A 3D model's section is a polygon
  // in the plane z = 0 of the view; its third column is the normal, so that the whole model
  // stands around the polygon (z = n.x - d) instead of being flattened onto it.
  const basis4 = () => {
    const b = basis(), d = n(), out = new Float32Array(12);
    for (let c = 0; c < d - 1; ++c) for (let r = 0; r < d; ++r) out[4 * c + r] = b[d * c + r];
    if (d === 3) unitNormal().forEach((x, r) => (out[8 + r] = x));
    return out;
  };
  const glPlacement = () => {
    const out = new Float32Array(20);
    out.set(glMatrix4(state.R, n()));
    return out;
  };
  const normal4 = () => {
    const u = unitNormal();
    return [0, 1, 2, 3].map((i) => u[i] ?? 0);
  };
  // The world directions of the screen's horizontal and vertical axes, inside the hyperplane.
  const screenAxes = () => {
    const mv = orbitView(state.yaw, state.pitch, 1);
    const d = n(), b = basis();
    const toWorld = (v3) => {
      const out = new Array(d).fill(0);
      for (let c = 0; c < d - 1; ++c) for (let r = 0; r < d; ++r) out[r] += b[d * c + r] * v3[c];
      return out;
    };
    return { right: toWorld([mv[0], mv[4], mv[8]]), up: toWorld([mv[1], mv[5], mv[9]]),
      normal: unitNormal() };
  };
  const radius = () => (info ? info.radius : 1);

  // --- the URL ------------------------------------------------------------------------------
  let urlTimer = null;
  const writeUrl = () => {
    clearTimeout(urlTimer);
    urlTimer = null;
    const q = new URLSearchParams();
    if (!fromFile) q.set('model', state.model);
    q.set('R', state.R.map((x) => Number(x.toFixed(6))).join(','));
    q.set('n', state.normal.map(fmt).join(','));
    q.set('d', fmt(state.offset));
    q.set('cam', [state.yaw, state.pitch].map((a) => fmt(a * 180 / Math.PI)).concat([fmt(state.zoom)]).join(','));
    q.set('whole', state.whole);
    if (state.slab > 0) q.set('slab', fmt(state.slab));
    q.set('anim', state.anim);
    if (state.playing) q.set('play', '1');
    for (const [k, v] of [['edges', state.edges], ['colours', state.colours], ['back', state.back],
      ['gpu', state.gpu], ['tex', state.texture]]) q.set(k, v ? '1' : '0');
    try {
      history.replaceState(null, '', `${location.pathname}?${q}`);
    } catch (e) {
      // (a browser may refuse frequent replacements: the view goes on, the link catches up)
    }
  };
  // Written once the view has rested for 300 ms, not at every frame of a drag or animation.
  const scheduleUrl = () => {
    clearTimeout(urlTimer);
    urlTimer = setTimeout(writeUrl, 300);
  };

  // --- slicing and drawing ------------------------------------------------------------------
  // The CPU path slices in the core whenever the placement or the plane changes; the GPU path
  // only draws (the section is cut in the vertex shader), and counts the section on the CPU
  // once the view rests, for the readout.
  let frame = 0, sliceDirty = true, countTimer = null;
  const applyPlacement = () => {
    const err = model.setMatrix(state.R, []);
    if (err) status(err, true, 'placement');
    sliceDirty = true;
  };
  const slice = () => {
    const s = model.slice(state.normal, state.offset);
    if (s.error) {
      status(s.error, true, 'slice');
      return null;
    }
    if (errorFrom === 'slice' || errorFrom === 'placement') clearError();
    return s;
  };
  const showCounts = (s) => {
    const f = s.fvector.join(', ');
    $('fvector').textContent = s.fvector.length ? `(${f})` : 'empty: the plane misses the model';
    $('volume').textContent = fmt(s.volume);
    $('time').textContent = `${s.sliceMs.toFixed(2)} ms${s.general ? ' (general path)' : ''}`;
  };
  const resliceNow = () => {
    const s = slice();
    if (!s) return;
    section = s;
    sliced = true;
    renderer.setSection(s);
    showCounts(s);
  };
  const invalidate = (resliced = true) => {
    if (resliced) sliceDirty = true;
    if (!frame) frame = requestAnimationFrame(render);
  };
  const gpuActive = () => state.gpu && tets && tets.count > 0;
  const drawOnly = () => {
    if (!info) return;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== w || canvas.height !== h) canvas.width = w, canvas.height = h;
    renderer.draw({ yaw: state.yaw, pitch: state.pitch, distance: (state.zoom || 3.2) * radius(),
      radius: radius() }, {
      gpu: gpuActive(), edges: state.edges, cellColours: state.colours, backFaces: state.back,
      texture: state.texture, placement: glPlacement(), normal: normal4(), offset: state.offset,
      basis: basis4(), whole: state.whole, slab: state.slab * radius() });
  };
  const render = (now) => {
    frame = 0;
    if (!info) return;
    if (state.playing) animate(now);
    if (sliceDirty) {
      sliceDirty = false;
      if (gpuActive()) {
        // The section is cut on the GPU; its counts follow once the view rests.
        clearTimeout(countTimer);
        countTimer = setTimeout(() => {
          const s = slice();
          if (s) section = s, sliced = true, showCounts(s);
        }, 300);
        sliced = false;
      } else {
        resliceNow();
      }
    }
    drawOnly();
    showPlane();
    scheduleUrl();
    if (state.playing) invalidate(false);
  };
  const showPlane = () => {
    const r = radius();
    $('plane').textContent = `n = (${state.normal.map(fmt).join(', ')}), d = ${fmt(state.offset)}`;
    $('offset').value = state.offset;
    $('offset-value').textContent = fmt(state.offset);
    const t = Math.max(0, Math.min(1, (r - state.offset) / (2 * r)));
    document.querySelector('#gauge .mark').style.top = `${100 * t}%`;
    const label = document.querySelector('#gauge .label');
    label.style.top = `${100 * t}%`;
    label.textContent = `d = ${Number(state.offset.toPrecision(3))}`;
    $('path').textContent = gpuActive()
      ? `GPU: ${tets.count} tetrahedra cut in the vertex shader every frame` +
        (tets.skippedCells ? ` (${tets.skippedCells} non-convex cells left out)` : '')
      : `CPU: ${section && section.indices ? section.indices.length / 3 : 0} triangles from the WebAssembly section`;
    $('legend').innerHTML = state.whole === 'off' ? '' :
      `whole polytope (${state.whole === 'persp' ? '4D perspective' : 'shadow along n'}): ` +
      '<b style="color:#ff9e52">n·x &gt; d</b> · <b style="color:#6aa8ff">n·x &lt; d</b> · ' +
      '<b style="color:#fff3a0">crossing</b>';
  };

  // --- animation ----------------------------------------------------------------------------
  let lastTime = null, sweepPhase = 0;
  const animate = (now) => {
    const dt = lastTime === null ? 0 : Math.min(0.1, (now - lastTime) / 1000);
    lastTime = now;
    if (state.anim === 'sweep') {
      // d = 0.95 r sin(phase): one sweep through the model and back in 10 seconds.
      sweepPhase += dt * 2 * Math.PI / 10;
      state.offset = 0.95 * radius() * Math.sin(sweepPhase);
    } else {
      const g = coordinateRotation(state.anim, 24 * dt, n());
      if (g) {
        state.R = multiply(g, state.R, n());
        applyPlacement();
      }
    }
    sliceDirty = true;
  };
  const setPlaying = (on) => {
    state.playing = on;
    lastTime = null;
    if (on && state.anim === 'sweep') {
      const r = radius();
      sweepPhase = Math.asin(Math.max(-1, Math.min(1, state.offset / (0.95 * r))));
    }
    $('play').textContent = on ? '❚❚ Pause' : '▶ Play';
    $('play').classList.toggle('on', on);
    writeUrl();
    invalidate(false);
  };

  // --- rotations ----------------------------------------------------------------------------
  const turn = (g) => {
    if (!g) return;
    const next = orthonormalize(multiply(g, state.R, n()), n());
    if (!next) return;
    state.R = next;
    applyPlacement();
    invalidate();
  };
  // A drag of (dx, dy) pixels with Shift: the plane (screen right, normal) turns by dx, the
  // plane (screen up, normal) by dy, so the parts of the model at the screen's right (or top)
  // move along the normal, into or out of the slice.
  const turn4D = (dx, dy) => {
    const a = screenAxes();
    const k = 0.008;
    let g = identity(n());
    const gh = planeRotation(a.right, a.normal, dx * k, n());
    const gv = planeRotation(a.up, a.normal, -dy * k, n());
    if (gh) g = multiply(gh, g, n());
    if (gv) g = multiply(gv, g, n());
    turn(g);
  };
  const moveOffset = (delta) => {
    const r = radius();
    state.offset = Math.max(-r, Math.min(r, state.offset + delta));
    invalidate();
  };
  const reset = () => {
    state.R = defaultRotation(n());
    state.normal = n() === 4 ? [0, 0, 0, 1] : [0, 0, 1];
    $('normal').value = state.normal.join(',');
    state.offset = DEFAULT_OFFSET * radius();
    state.yaw = DEFAULT_CAMERA.yaw * Math.PI / 180;
    state.pitch = DEFAULT_CAMERA.pitch * Math.PI / 180;
    state.zoom = DEFAULT_CAMERA.zoom;
    applyPlacement();
    writeUrl();
    invalidate();
  };

  // --- loading ------------------------------------------------------------------------------
  const loaded = (label) => {
    const previousRadius = info ? info.radius : null;
    info = model.info();
    const d = info.dim;
    const r = info.radius;
    const sameDim = d === state.dim;
    state.dim = d;
    if (firstLoad && initial.matrix.length === d * d && orthonormalize(initial.matrix, d)) {
      state.R = orthonormalize(initial.matrix, d);
    } else if (firstLoad && initial.rotations.length) {
      state.R = fromRotations(initial.rotations, d);
    } else if (firstLoad && config.off) {
      state.R = identity(d);  // `cw4d view` wrote the model already placed
    } else if (firstLoad || !sameDim) {
      state.R = defaultRotation(d);
    }
    if (state.normal.length !== d) state.normal = d === 4 ? [0, 0, 0, 1] : [0, 0, 1];
    // A new model keeps the plane where it fits; an offset from the URL beyond the model is 0.
    if (Number.isNaN(state.offset)) state.offset = config.off ? 0 : DEFAULT_OFFSET * r;
    // Another model keeps the plane at the same fraction of its radius.
    if (!firstLoad && previousRadius > 0) state.offset *= r / previousRadius;
    if (Math.abs(state.offset) > r) {
      if (firstLoad) status(`d = ${fmt(state.offset)} lies beyond the model (radius ${fmt(r)}): showing d = 0`, true, 'url');
      state.offset = firstLoad ? 0 : Math.sign(state.offset) * r;
    }
    firstLoad = false;
    basisCache = null;
    const slider = $('offset');
    slider.min = -r;
    slider.max = r;
    slider.step = r / 500;
    $('normal').value = state.normal.map(fmt).join(',');
    $('gpu').disabled = d !== 4;
    $('modelinfo').textContent = `${label}: (${info.fvector.join(', ')})` +
      (info.fast ? '' : ', general path');
    renderer.setWireframe(model.wireframe());
    tets = null;
    renderer.setTets(null);
    if (state.gpu) makeTets();
    applyPlacement();
    showPicked();
    writeUrl();
    // The first picture now, not at the next animation frame (a page opened by a script or
    // printed has it at once).
    if (frame) cancelAnimationFrame(frame);
    sliceDirty = true;
    render(performance.now());
    hook.ready = false;
    requestAnimationFrame(() => requestAnimationFrame(() => (hook.ready = true)));
  };
  const makeTets = () => {
    if (!info || info.dim !== 4) return null;
    if (!tets) {
      const t = model.tets();
      const err = t.error || (t.count === 0
        ? `all ${t.skippedCells} cells are non-convex (the buffers of cw4d tetrahedralize can be dropped)`
        : renderer.setTets(t));
      tets = err ? null : t;
      if (err) status(`GPU path: ${err}`, true, 'gpu');
    }
    return tets;
  };
  // Loads a spec; returns true when it is shown, else shows the error (nothing else changes).
  const loadSpec = (spec, source = 'spec') => {
    const next = new core.Model();
    const err = next.loadSpec(specOf(spec));
    if (err) {
      next.delete();
      status(err, true, source);
      return false;
    }
    model.delete();
    model = next;
    state.model = specOf(spec);
    fromFile = null;
    clearError();
    loaded(state.model);
    return true;
  };
  // A model file's contents: nOFF text (a string) or the bytes of a G4MF file (.g4tf, .g4b).
  const loadContents = (contents, name) => {
    const next = new core.Model();
    const err = typeof contents === 'string' ? next.loadOff(contents, name) : next.loadG4mf(contents, name);
    if (err) {
      next.delete();
      status(err, true, 'file');
      return false;
    }
    model.delete();
    model = next;
    fromFile = name;
    clearError();
    loaded(name);
    return true;
  };

  // --- the panel ----------------------------------------------------------------------------
  $('offset').addEventListener('input', () => {
    state.offset = Number($('offset').value);
    if (errorFrom === 'url') clearError();
    invalidate();
  });
  $('normal').addEventListener('change', () => {
    const v = $('normal').value.split(',').map((x) => Number(x.trim()));
    if (v.length !== n() || !v.every(Number.isFinite) || v.every((x) => x === 0)) {
      status(`the normal needs ${n()} numbers, not all zero`, true, 'normal');
      return;
    }
    state.normal = v;
    basisCache = null;
    if (errorFrom === 'normal') clearError();
    invalidate();
  });
  for (const [id, key] of [['edges', 'edges'], ['colours', 'colours'], ['back', 'back'],
    ['texture', 'texture']]) {
    const box = $(id);
    box.checked = state[key];
    box.addEventListener('change', () => {
      state[key] = box.checked;
      writeUrl();
      invalidate(false);
    });
  }
  const setGpu = (on) => {
    if (on && !makeTets()) on = false;
    state.gpu = on;
    $('gpu').checked = on;
    writeUrl();
    invalidate();
  };
  $('gpu').checked = state.gpu;
  $('gpu').addEventListener('change', () => setGpu($('gpu').checked));
  const setWhole = (mode) => {
    state.whole = mode;
    $('whole').value = mode;
    writeUrl();
    invalidate(false);
  };
  $('whole').value = state.whole;
  $('whole').addEventListener('change', () => setWhole($('whole').value));
  const slabLabel = () => ($('slab-value').textContent = state.slab > 0 ? `${fmt(state.slab)} r` : 'all');
  $('slab').value = state.slab;
  slabLabel();
  $('slab').addEventListener('input', () => {
    state.slab = Number($('slab').value);
    slabLabel();
    scheduleUrl();
    invalidate(false);
  });
  $('anim').value = state.anim;
  $('anim').addEventListener('change', () => {
    state.anim = $('anim').value;
    setPlaying(state.playing);
  });
  $('play').addEventListener('click', () => setPlaying(!state.playing));
  $('reset').addEventListener('click', reset);
  picker.addEventListener('change', () => {
    if (!picker.value.startsWith('file:') && !loadSpec(picker.value, 'picker')) showPicked();
    picker.blur();  // the keys 1-6 turn the model, not pick by their first letter
  });
  for (const id of ['anim', 'whole']) $(id).addEventListener('change', () => $(id).blur());
  $('spec').addEventListener('change', () => {
    const text = $('spec').value.trim();
    if (text) loadSpec(text, 'spec');
  });
  $('diagram').addEventListener('change', () => {
    const text = $('diagram').value.trim();
    if (!text) return;
    if (!DIAGRAM.test(text)) {
      status(`'${text}' is not a Coxeter diagram: nodes x, o or s joined by branch numbers (x4o3o3x)`, true, 'diagram');
      return;
    }
    if (loadSpec(text, 'diagram')) $('library').hidden = true;
  });
  const toggle = (id, show) => {
    const el = $(id);
    el.hidden = show === undefined ? !el.hidden : !show;
    if (!el.hidden) for (const other of ['library', 'help']) if (other !== id) $(other).hidden = true;
  };
  $('help-button').addEventListener('click', () => toggle('help'));
  $('help-close').addEventListener('click', () => toggle('help', false));
  $('library-button').addEventListener('click', () => toggle('library'));
  $('library-close').addEventListener('click', () => toggle('library', false));
  $('panel-toggle').addEventListener('click', () => $('panel').classList.toggle('collapsed'));
  if (window.matchMedia('(max-width: 480px)').matches) $('panel').classList.add('collapsed');

  // --- keeping what you see -----------------------------------------------------------------
  const title = () => `${fromFile || state.model}, n = (${state.normal.map(fmt).join(', ')}), d = ${fmt(state.offset)}`;
  const currentSection = () => {
    const s = sliced && section ? section : slice();
    if (!s) return null;
    if (!s.indices || s.indices.length === 0) {
      status('the plane misses the model: there is no section to save', true, 'download');
      return null;
    }
    return s;
  };
  const download = (kind) => {
    if (kind === 'png') {
      drawOnly();
      canvas.toBlob((blob) => saveBlob(blob, 'cw4d-view.png'), 'image/png');
      return;
    }
    const s = currentSection();
    if (!s) return;
    if (errorFrom === 'download') clearError();
    const blob = kind === 'obj' ? sectionObj(s, title()) : kind === 'stl' ? sectionStl(s) : sectionGlb(s, title());
    saveBlob(blob, `cw4d-section.${kind}`);
  };
  for (const kind of ['obj', 'glb', 'stl', 'png'])
    $(`dl-${kind}`).addEventListener('click', () => download(kind));
  $('copy-link').addEventListener('click', async () => {
    writeUrl();
    const link = location.href;
    $('link-text').value = link;
    $('link-text').placeholder = ' ';
    try {
      await navigator.clipboard.writeText(link);
      $('copy-link').textContent = 'Copied';
    } catch (e) {
      $('link-text').select();
      $('copy-link').textContent = 'Select the link';
    }
    setTimeout(() => ($('copy-link').textContent = 'Copy link'), 1500);
  });

  // --- pointer, wheel, touch ----------------------------------------------------------------
  // One mouse button or finger orbits; Shift, the right button or two fingers turn in 4D;
  // two fingers pinching zoom.
  const pointers = new Map();
  let pinch = null;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('pointerdown', (e) => {
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
    canvas.setPointerCapture(e.pointerId);
    pinch = null;
  });
  const release = (e) => {
    pointers.delete(e.pointerId);
    pinch = null;
  };
  canvas.addEventListener('pointerup', release);
  canvas.addEventListener('pointercancel', release);
  canvas.addEventListener('pointermove', (e) => {
    const p = pointers.get(e.pointerId);
    if (!p) return;
    const dx = e.clientX - p.x, dy = e.clientY - p.y;
    p.x = e.clientX;
    p.y = e.clientY;
    if (pointers.size >= 2) {
      const [a, b] = [...pointers.values()];
      const spread = Math.hypot(a.x - b.x, a.y - b.y);
      if (pinch) {
        const ratio = spread / pinch;
        state.zoom = Math.max(0.5, Math.min(20, (state.zoom || 3.2) / ratio));
      }
      pinch = spread;
      // Each finger contributes half of the common motion.
      turn4D(dx / 2, dy / 2);
      return;
    }
    if (e.shiftKey || (e.buttons & 2)) {
      turn4D(dx, dy);
    } else {
      state.yaw += dx * 0.01;
      state.pitch = Math.max(-1.55, Math.min(1.55, state.pitch + dy * 0.01));
      invalidate(false);
    }
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    if (e.shiftKey || e.ctrlKey) {
      const amount = e.deltaY || e.deltaX;
      state.zoom = Math.max(0.5, Math.min(20, (state.zoom || 3.2) * Math.exp(amount * 0.001)));
      invalidate(false);
      return;
    }
    moveOffset(-Math.sign(e.deltaY) * radius() / 100);
  }, { passive: false });
  const gauge = $('gauge');
  const gaugeAt = (e) => {
    const box = gauge.getBoundingClientRect();
    const t = Math.max(0, Math.min(1, (e.clientY - box.top) / box.height));
    state.offset = radius() * (1 - 2 * t);
    invalidate();
  };
  gauge.addEventListener('pointerdown', (e) => {
    gauge.setPointerCapture(e.pointerId);
    gaugeAt(e);
  });
  gauge.addEventListener('pointermove', (e) => {
    if (e.buttons) gaugeAt(e);
  });
  window.addEventListener('resize', () => invalidate(false));

  // --- keys ---------------------------------------------------------------------------------
  window.addEventListener('keydown', (e) => {
    const t = e.target;
    if (t && (t.tagName === 'INPUT' && t.type === 'text' || t.tagName === 'SELECT' || t.tagName === 'TEXTAREA'))
      return;
    if (t && t.tagName === 'INPUT' && t.type === 'checkbox' && e.code === 'Space') return;
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    const digit = /^Digit([1-6])$/.exec(e.code);
    if (digit) {
      turn(coordinateRotation(COORDINATE_PLANES[Number(digit[1]) - 1], e.shiftKey ? -5 : 5, n()));
    } else if (e.code === 'ArrowUp' || e.code === 'ArrowDown') {
      moveOffset((e.code === 'ArrowUp' ? 1 : -1) * radius() / (e.shiftKey ? 20 : 100));
    } else if (e.code === 'Space') {
      setPlaying(!state.playing);
    } else if (e.code === 'KeyR') {
      reset();
    } else if (e.code === 'KeyV') {
      setWhole(WHOLE_MODES[(WHOLE_MODES.indexOf(state.whole) + 1) % WHOLE_MODES.length]);
    } else if (e.code === 'KeyG') {
      if (!$('gpu').disabled) setGpu(!state.gpu);
    } else if (e.code === 'KeyL') {
      toggle('library');
    } else if (e.key === '?' || e.code === 'KeyH') {
      toggle('help');
    } else if (e.code === 'Escape') {
      toggle('help', false);
      toggle('library', false);
    } else {
      return;
    }
    e.preventDefault();
  });

  // GPU buffers of `cw4d tetrahedralize MODEL -o NAME.bin` (NAME.json and NAME.bin dropped
  // together) replace the GPU path's tetrahedra of the loaded model.
  const loadBuffers = async (files) => {
    const json = files.find((f) => f.name.endsWith('.json'));
    const bin = files.find((f) => f.name.endsWith('.bin'));
    try {
      const header = JSON.parse(await json.text());
      if (info.dim !== 4 || header.cells !== info.fvector[3])
        throw new Error(`${json.name} holds ${header.cells} cells, the model has ${info.fvector[3]}`);
      const dropped = tetsFromBuffer(header, await bin.arrayBuffer(), core.cellPalette(header.cells));
      const err = renderer.setTets(dropped);
      if (err) {
        tets = null;
        makeTets();
        throw new Error(err);
      }
      tets = dropped;
      setGpu(true);
      status(`GPU path: ${tets.count} tetrahedra from ${bin.name}`);
    } catch (err) {
      status(`${json.name}: ${err.message}`, true, 'file');
    }
  };
  // A model file: G4MF (.g4tf text, .g4b binary) goes to the core as bytes, anything else as
  // nOFF text.
  const G4MF = /\.(g4tf|g4b)$/i;
  const openFile = async (file) => {
    try {
      loadContents(G4MF.test(file.name) ? new Uint8Array(await file.arrayBuffer()) : await file.text(), file.name);
    } catch (err) {
      status(`${file.name}: cannot read the file (${err.message})`, true, 'file');
    }
  };
  // Drop a .4off / .off / .g4tf / .g4b file anywhere on the page (or a .json + .bin pair, above).
  window.addEventListener('dragover', (e) => e.preventDefault());
  window.addEventListener('drop', async (e) => {
    e.preventDefault();
    const files = [...e.dataTransfer.files];
    if (files.some((f) => f.name.endsWith('.json')) && files.some((f) => f.name.endsWith('.bin')))
      return loadBuffers(files);
    if (files[0]) await openFile(files.find((f) => G4MF.test(f.name)) || files[0]);
  });
  $('file').addEventListener('change', async () => {
    const file = $('file').files[0];
    if (file) await openFile(file);
  });

  // --- the test hook ------------------------------------------------------------------------
  // What the browser test reads and drives, as a user's eyes and hands cannot: the state, the
  // counts, the screen's axes in 4D, and a timed loop of frames on either path.
  const rowMajor4 = () => {
    const out = identity(4);
    for (let r = 0; r < n(); ++r) for (let c = 0; c < n(); ++c) out[4 * r + c] = state.R[r * n() + c];
    return out;
  };
  const hook = {
    ready: false,
    state: () => ({ model: fromFile ? `file:${fromFile}` : state.model, rotation: rowMajor4(),
      normal: unitNormal(), offset: state.offset, yaw: state.yaw, pitch: state.pitch,
      zoom: state.zoom, whole: state.whole, gpu: state.gpu, playing: state.playing,
      anim: state.anim, radius: radius(), dim: n() }),
    counts: () => {
      const s = slice();
      return s ? { fvector: s.fvector, volume: s.volume, triangles: s.indices ? s.indices.length / 3 : 0 }
        : null;
    },
    screenAxes,
    load: (spec) => new Promise((resolve, reject) => {
      if (!loadSpec(spec, 'spec')) return reject(new Error($('status').textContent));
      const wait = () => (hook.ready ? resolve(hook.state()) : setTimeout(wait, 20));
      wait();
    }),
    // frames frames with the offset moving each frame: 'cpu' slices in the core, uploads and
    // draws; 'gpu' only draws. Each frame ends with a one-pixel read, so the GPU has finished.
    frameBench: async ({ path = 'cpu', frames = 20 } = {}) => {
      const wasGpu = state.gpu, wasOffset = state.offset, wasWhole = state.whole;
      if (path === 'gpu' && !makeTets()) throw new Error('the GPU path has no tetrahedra');
      state.gpu = path === 'gpu';
      state.whole = 'off';
      const gl = renderer.gl, px = new Uint8Array(4);
      const r = radius();
      const t0 = performance.now();
      for (let i = 0; i < frames; ++i) {
        state.offset = 0.5 * r * Math.sin(i * 0.37);
        if (path === 'cpu') resliceNow();
        drawOnly();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
      }
      const ms = (performance.now() - t0) / frames;
      state.gpu = wasGpu;
      state.offset = wasOffset;
      state.whole = wasWhole;
      invalidate();
      return { msPerFrame: ms, fps: 1000 / ms, frames, tetrahedra: tets ? tets.count : 0,
        triangles: section && section.indices ? section.indices.length / 3 : 0 };
    },
  };
  window.cw4dViewer = hook;

  if (config.off) {
    loadContents(config.off, config.name || 'model.4off');
  } else if (!loadSpec(initial.model, 'url')) {
    const why = $('status').textContent;
    loadSpec(DEFAULT_MODEL, 'url');
    status(`${why} (showing the ${DEFAULT_MODEL})`, true, 'url');
  }
  if (initial.playing) setPlaying(true);
}
