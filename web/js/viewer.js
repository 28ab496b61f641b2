// The cw4d viewer: a 4D model placed by rotations in the six coordinate planes, cut live by the
// hyperplane n.x = d in the WebAssembly core (or on the GPU, one instance per tetrahedron), and
// drawn with WebGL2. The view is kept in the URL so that it can be shared.
import { Renderer, tetsFromBuffer } from './renderer.js';
import { runSelftest } from './selftest.js';

const PLANES = ['xy', 'xz', 'xw', 'yz', 'yw', 'zw'];
const PRESETS = ['5-cell', 'tesseract', '16-cell', '24-cell', '120-cell', '600-cell',
  'omnitruncated 120-cell', 'rectified 600-cell', 'duoprism:5,7', 'duocylinder:1,24',
  'spheritorus:2,0.7,16', 'tiger:2,2,0.6,12', 'ditorus:3,1.6,0.5,12'];

const $ = (id) => document.getElementById(id);
const fmt = (x) => (Math.abs(x) < 1e-12 ? '0' : Number(x.toPrecision(6)).toString());

// The view: from the page's configuration (the one-file export), then the URL.
function readState(config) {
  const q = new URLSearchParams(location.search);
  const get = (k, fallback) => (q.has(k) ? q.get(k) : (config[k] ?? fallback));
  const num = (k, fallback) => {
    const v = Number(get(k, fallback));
    return Number.isFinite(v) ? v : fallback;
  };
  const rot = Object.fromEntries(PLANES.map((p) => [p, 0]));
  for (const part of String(get('rot', '')).split(',').filter(Boolean)) {
    const [plane, deg] = part.split(':');
    if (plane in rot && Number.isFinite(Number(deg))) rot[plane] = Number(deg);
  }
  const normal = String(get('n', '0,0,0,1')).split(',').map(Number);
  const cam = String(get('cam', '35,25,0')).split(',').map(Number);
  const flag = (k, fallback) => String(get(k, fallback ? '1' : '0')) !== '0';
  return {
    model: String(get('model', 'tesseract')), rot,
    normal: normal.every(Number.isFinite) && normal.some((x) => x !== 0) ? normal : [0, 0, 0, 1],
    offset: num('d', 0), yaw: (cam[0] || 0) * Math.PI / 180, pitch: (cam[1] || 0) * Math.PI / 180,
    zoom: cam[2] > 0 ? cam[2] : 0, edges: flag('edges', true), colours: flag('colours', true),
    back: flag('back', false), gpu: flag('gpu', false), texture: flag('tex', true),
  };
}

function writeUrl(state, fromFile) {
  if (fromFile) return;  // a dropped file is not in the URL
  const q = new URLSearchParams();
  q.set('model', state.model);
  const rot = PLANES.filter((p) => state.rot[p] !== 0).map((p) => `${p}:${fmt(state.rot[p])}`);
  if (rot.length) q.set('rot', rot.join(','));
  q.set('n', state.normal.map(fmt).join(','));
  q.set('d', fmt(state.offset));
  q.set('cam', [state.yaw, state.pitch].map((a) => fmt(a * 180 / Math.PI)).concat(
    [fmt(state.zoom)]).join(','));
  for (const [k, v] of [['edges', state.edges], ['colours', state.colours], ['back', state.back],
    ['gpu', state.gpu], ['tex', state.texture]]) q.set(k, v ? '1' : '0');
  history.replaceState(null, '', `${location.pathname}?${q}`);
}

export async function start(createCw4d, config = {}) {
  const core = await createCw4d();
  const canvas = $('view');
  if (new URLSearchParams(location.search).get('selftest') === '1') {
    const pre = $('selftest');
    try {
      const result = await runSelftest(core, canvas,
        new URLSearchParams(location.search).get('buffers'));
      pre.textContent = JSON.stringify({ ok: true, ...result });
    } catch (e) {
      pre.textContent = JSON.stringify({ ok: false, error: String(e && e.message || e) });
    }
    // The browser test's own server takes the result (the timed checks cannot run under
    // --dump-dom's virtual time, which stands still while a script runs).
    if (new URLSearchParams(location.search).get('report') === '1')
      await fetch('selftest-result', { method: 'POST', body: pre.textContent });
    return;
  }
  const state = readState(config);
  const renderer = new Renderer(canvas);
  let model = new core.Model();
  let info = null, fromFile = false, section = null, tets = null;

  const status = (text, isError = false) => {
    $('status').textContent = text;
    $('status').className = isError ? 'error' : '';
  };

  // Catalogue: presets in the picker, and every family with its availability.
  const picker = $('model');
  for (const spec of PRESETS) picker.add(new Option(spec, spec));
  const cat = core.catalogue();
  const list = $('catalogue');
  for (let i = 0; i < cat.length; ++i) {
    const li = document.createElement('li');
    li.textContent = `${cat[i].spec} — ${cat[i].description}` +
      (cat[i].available ? '' : ` (${cat[i].reason})`);
    if (!cat[i].available) li.className = 'unavailable';
    list.appendChild(li);
  }

  const sliderOffset = $('offset');
  const applyPlacement = () => {
    const err = model.setPlacement(PLANES.map((p) => [p, state.rot[p]]), []);
    if (err) status(err, true);
  };

  const reslice = () => {
    if (!info) return;
    const s = model.slice(state.normal, state.offset);
    if (s.error) {
      status(s.error, true);
      return;
    }
    section = s;
    renderer.setSection(s);
    const f = s.fvector.join(', ');
    const n = state.normal.map(fmt).join(', ');
    $('plane').textContent = `n = (${n}), d = ${fmt(state.offset)}`;
    $('fvector').textContent = s.fvector.length ? `(${f})` : 'empty (the plane misses the model)';
    $('volume').textContent = fmt(s.volume);
    $('time').textContent = `${s.sliceMs.toFixed(2)} ms${s.general ? ' (general path)' : ''}`;
    writeUrl(state, fromFile);
    draw();
  };

  const draw = () => {
    if (!info) return;
    const len = Math.hypot(...state.normal);
    const dpr = window.devicePixelRatio || 1;
    const w = Math.round(canvas.clientWidth * dpr), h = Math.round(canvas.clientHeight * dpr);
    if (canvas.width !== w || canvas.height !== h) canvas.width = w, canvas.height = h;
    const gpu = state.gpu && tets && tets.count > 0;
    renderer.draw({ yaw: state.yaw, pitch: state.pitch,
      distance: (state.zoom || 3.2) * info.radius }, {
      gpu, edges: state.edges, cellColours: state.colours, backFaces: state.back,
      texture: state.texture, placement: model.placement(),
      normal: state.normal.map((x) => x / len), offset: state.offset,
      basis: model.planeBasis(state.normal) });
    $('path').textContent = gpu
      ? `GPU: ${tets.count} tetrahedra cut in the vertex shader` +
        (tets.skippedCells ? ` (${tets.skippedCells} non-convex cells left out)` : '')
      : `CPU: ${section ? section.indices ? section.indices.length / 3 : 0 : 0} triangles from the WebAssembly section`;
  };

  const loaded = (err, label) => {
    if (err) {
      status(err, true);
      return false;
    }
    info = model.info();
    const r = info.radius;
    sliderOffset.min = -r;
    sliderOffset.max = r;
    sliderOffset.step = r / 500;
    if (Math.abs(state.offset) > r) state.offset = 0;
    sliderOffset.value = state.offset;
    tets = null;
    $('gpu').disabled = info.dim !== 4;
    if (info.dim === 4) {
      const t = model.tets();
      tets = t.error ? null : t;
      renderer.setTets(tets);
    }
    if (state.normal.length !== info.dim)
      state.normal = info.dim === 4 ? [0, 0, 0, 1] : [0, 0, 1];
    $('normal').value = state.normal.map(fmt).join(',');
    $('modelinfo').textContent = `${label}: f-vector (${info.fvector.join(', ')})` +
      (info.fast ? '' : ', general path');
    status('');
    applyPlacement();
    reslice();
    return true;
  };

  const loadSpec = (spec) => {
    fromFile = false;
    const next = new core.Model();
    const err = next.loadSpec(spec);
    if (err) {
      next.delete();
      status(err, true);
      return;
    }
    model.delete();
    model = next;
    state.model = spec;
    $('spec').value = spec;
    loaded('', spec);
  };

  const loadText = (text, name) => {
    const next = new core.Model();
    const err = next.loadOff(text, name);
    if (err) {
      next.delete();
      status(err, true);
      return;
    }
    model.delete();
    model = next;
    fromFile = true;
    loaded('', name);
  };

  // Sliders and toggles.
  for (const p of PLANES) {
    const s = $(`rot-${p}`);
    s.value = state.rot[p];
    s.addEventListener('input', () => {
      state.rot[p] = Number(s.value);
      $(`rot-${p}-value`).textContent = `${s.value}°`;
      applyPlacement();
      reslice();
    });
    $(`rot-${p}-value`).textContent = `${s.value}°`;
  }
  sliderOffset.addEventListener('input', () => {
    state.offset = Number(sliderOffset.value);
    reslice();
  });
  $('normal').addEventListener('change', () => {
    const n = $('normal').value.split(',').map(Number);
    if (n.length !== info.dim || !n.every(Number.isFinite) || n.every((x) => x === 0)) {
      status(`the normal needs ${info.dim} numbers, not all zero`, true);
      return;
    }
    state.normal = n;
    reslice();
  });
  for (const [id, key] of [['edges', 'edges'], ['colours', 'colours'], ['back', 'back'],
    ['gpu', 'gpu'], ['texture', 'texture']]) {
    const box = $(id);
    box.checked = state[key];
    box.addEventListener('change', () => {
      state[key] = box.checked;
      writeUrl(state, fromFile);
      draw();
    });
  }
  picker.addEventListener('change', () => loadSpec(picker.value));
  $('spec').addEventListener('change', () => loadSpec($('spec').value.trim()));

  // Drag: orbit; shift-drag: rotate in xw (horizontal) and yw (vertical); alt- or ctrl-drag:
  // zw. Wheel: move the hyperplane; shift-wheel: zoom.
  let drag = null;
  canvas.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointerup', () => (drag = null));
  canvas.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag = { x: e.clientX, y: e.clientY };
    if (e.shiftKey || e.altKey || e.ctrlKey) {
      const turn = (p, deg) => {
        state.rot[p] = Math.round(((state.rot[p] + deg + 540) % 360 - 180) * 10) / 10;
        $(`rot-${p}`).value = state.rot[p];
        $(`rot-${p}-value`).textContent = `${state.rot[p]}°`;
      };
      if (e.shiftKey) {
        turn('xw', dx * 0.5);
        turn('yw', dy * 0.5);
      } else {
        turn('zw', dx * 0.5);
      }
      applyPlacement();
      reslice();
    } else {
      state.yaw += dx * 0.01;
      state.pitch = Math.max(-1.55, Math.min(1.55, state.pitch + dy * 0.01));
      writeUrl(state, fromFile);
      draw();
    }
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    if (e.shiftKey) {
      state.zoom = Math.max(0.5, Math.min(20, (state.zoom || 3.2) * Math.exp(e.deltaY * 0.001)));
      writeUrl(state, fromFile);
      draw();
      return;
    }
    const r = info ? info.radius : 1;
    state.offset = Math.max(-r, Math.min(r, state.offset - Math.sign(e.deltaY) * r / 100));
    sliderOffset.value = state.offset;
    reslice();
  }, { passive: false });
  window.addEventListener('resize', draw);

  // GPU buffers of `cw4d tetrahedralize MODEL -o NAME.bin` (NAME.json and NAME.bin dropped
  // together) replace the GPU path's tetrahedra of the loaded model.
  const loadBuffers = async (files) => {
    const json = files.find((f) => f.name.endsWith('.json'));
    const bin = files.find((f) => f.name.endsWith('.bin'));
    try {
      const header = JSON.parse(await json.text());
      if (header.cells !== info.fvector[3])
        throw new Error(`${json.name} holds ${header.cells} cells, the model has ${info.fvector[3]}`);
      tets = tetsFromBuffer(header, await bin.arrayBuffer(), core.cellPalette(header.cells));
      renderer.setTets(tets);
      state.gpu = true;
      $('gpu').checked = true;
      status(`GPU path: ${tets.count} tetrahedra from ${bin.name}`);
      draw();
    } catch (err) {
      status(`${json.name}: ${err.message}`, true);
    }
  };

  // Drop a .4off / .off file anywhere on the page (or a .json + .bin pair, above).
  window.addEventListener('dragover', (e) => e.preventDefault());
  window.addEventListener('drop', async (e) => {
    e.preventDefault();
    const files = [...e.dataTransfer.files];
    if (files.some((f) => f.name.endsWith('.json')) && files.some((f) => f.name.endsWith('.bin')))
      return loadBuffers(files);
    if (files[0]) loadText(await files[0].text(), files[0].name);
  });
  $('file').addEventListener('change', async () => {
    const file = $('file').files[0];
    if (file) loadText(await file.text(), file.name);
  });

  if (config.off) {
    fromFile = true;
    loadText(config.off, config.name || 'model.4off');
  } else {
    if (PRESETS.includes(state.model)) picker.value = state.model;
    loadSpec(state.model);
  }
}
