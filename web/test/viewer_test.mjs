#!/usr/bin/env node
// The viewer page driven as a user drives it: headless Chromium (Debian's, SwiftShader WebGL2)
// through playwright-core opens index.html from a static server on 127.0.0.1 that this test
// starts and stops itself, then drags, wheels, presses keys, picks models, downloads, copies the
// link and touches the canvas of a phone-sized page. Each user action is checked against an
// independent reading: the page's test hook window.cw4dViewer (state, counts, screen axes), the
// native `cw4d slice` of the same cut, the Khronos glTF-Validator, the downloaded bytes, the
// pixels of the canvas.
//
// usage: node web/test/viewer_test.mjs --site build-web/web/site --cw4d build/apps/cw4d
//                                     --out DIR [--screenshots DIR] [--chromium PATH]
//                                     [--timeout SECONDS] [--bench-seconds SECONDS]
// Prints one line per failed check and closes with `viewer_test: N passed, M failed`; exits 1
// on any failure (2 on a usage error). --timeout bounds the whole run (default 1500 s). Frame
// times are reported (stdout and DIR/viewer_bench.json), never asserted: 20 frames per path, fewer
// when 20 would take longer than --bench-seconds (default 60; SwiftShader draws a million
// tetrahedra in tens of seconds).
import { createRequire } from 'node:module';
import { execFile } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import zlib from 'node:zlib';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const TOOLS = path.resolve(HERE, '../../tests/tools');
const requireTools = createRequire(path.join(TOOLS, 'package.json'));

// ---------------------------------------------------------------------------------------------
// Arguments

function usage(message) {
  if (message) console.error(`viewer_test: ${message}`);
  console.error('usage: node web/test/viewer_test.mjs --site SITE_DIR --cw4d CW4D --out DIR ' +
    '[--screenshots DIR] [--chromium PATH] [--timeout SECONDS] [--bench-seconds SECONDS]');
  process.exit(2);
}

function parseArgs(argv) {
  const args = { chromium: '/usr/bin/chromium', timeout: 1500, benchSeconds: 60 };
  const known = { '--site': 'site', '--cw4d': 'cw4d', '--out': 'out', '--screenshots': 'screenshots',
    '--chromium': 'chromium', '--timeout': 'timeout', '--bench-seconds': 'benchSeconds' };
  for (let i = 0; i < argv.length; i += 1) {
    const key = known[argv[i]];
    if (!key) usage(`unknown argument ${argv[i]}`);
    if (i + 1 >= argv.length) usage(`${argv[i]} needs a value`);
    args[key] = argv[++i];
  }
  for (const k of ['site', 'cw4d', 'out']) if (!args[k]) usage(`--${k} is required`);
  args.timeout = Number(args.timeout);
  if (!(args.timeout > 0)) usage('--timeout must be a positive number of seconds');
  args.benchSeconds = Number(args.benchSeconds);
  if (!(args.benchSeconds > 0)) usage('--bench-seconds must be a positive number of seconds');
  args.site = path.resolve(args.site);
  args.cw4d = path.resolve(args.cw4d);
  args.out = path.resolve(args.out);
  if (args.screenshots) args.screenshots = path.resolve(args.screenshots);
  if (!fs.existsSync(path.join(args.site, 'index.html'))) usage(`${args.site}/index.html not found`);
  return args;
}

// ---------------------------------------------------------------------------------------------
// Checks: each one named, run once with its own time limit; a failure is one line.

const results = [];

class Failure extends Error {}

function ok(cond, message) {
  if (!cond) throw new Failure(message);
}

function withTimeout(promise, ms, what) {
  let timer;
  return Promise.race([
    promise.finally(() => clearTimeout(timer)),
    new Promise((_, reject) => {
      timer = setTimeout(() => reject(new Failure(`${what}: no result within ${ms / 1000} s`)), ms);
    }),
  ]);
}

let stopped = false;  // past the run's deadline: no more checks, no more lines

async function check(name, fn, seconds = 90) {
  if (stopped) return;
  const t0 = Date.now();
  try {
    await withTimeout(Promise.resolve().then(fn), seconds * 1000, name);
    if (stopped) return;
    results.push({ name, ok: true });
    console.log(`viewer_test: ok   ${name} (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
  } catch (e) {
    if (stopped) return;
    const text = String(e && e.message || e).split('\n')[0];
    results.push({ name, ok: false, text });
    console.log(`viewer_test: FAIL ${name}: ${text}`);
  }
}

// ---------------------------------------------------------------------------------------------
// 4x4 matrices (row-major arrays of 16), vectors of 4

const I4 = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
const AXES = { x: 0, y: 1, z: 2, w: 3 };
const PLANES = ['xy', 'xz', 'yz', 'xw', 'yw', 'zw'];  // Digit1..Digit6

function mul(a, b) {
  const c = new Array(16).fill(0);
  for (let i = 0; i < 4; i += 1)
    for (let j = 0; j < 4; j += 1)
      for (let k = 0; k < 4; k += 1) c[i * 4 + j] += a[i * 4 + k] * b[k * 4 + j];
  return c;
}
const transpose = (a) => a.map((_, k) => a[(k % 4) * 4 + Math.floor(k / 4)]);
const apply = (a, v) => [0, 1, 2, 3].map((i) => a[i * 4] * v[0] + a[i * 4 + 1] * v[1] +
  a[i * 4 + 2] * v[2] + a[i * 4 + 3] * v[3]);
const dot = (u, v) => u.reduce((s, x, i) => s + x * v[i], 0);
const sub = (u, v) => u.map((x, i) => x - v[i]);
const scale = (u, s) => u.map((x) => x * s);
const norm = (u) => Math.sqrt(dot(u, u));
const maxDiff = (a, b) => a.reduce((m, x, i) => Math.max(m, Math.abs(x - b[i])), 0);

function det(a) {
  // Gaussian elimination with partial pivoting on a copy.
  const m = [0, 1, 2, 3].map((i) => a.slice(i * 4, i * 4 + 4));
  let d = 1;
  for (let c = 0; c < 4; c += 1) {
    let p = c;
    for (let r = c + 1; r < 4; r += 1) if (Math.abs(m[r][c]) > Math.abs(m[p][c])) p = r;
    if (m[p][c] === 0) return 0;
    if (p !== c) { [m[p], m[c]] = [m[c], m[p]]; d = -d; }
    d *= m[c][c];
    for (let r = c + 1; r < 4; r += 1) {
      const f = m[r][c] / m[c][c];
      for (let k = c; k < 4; k += 1) m[r][k] -= f * m[c][k];
    }
  }
  return d;
}

// The rotation by `deg` in a coordinate plane 'ab', as cw4d's AffineTransform::rotation (and so
// `cw4d slice --rotate ab:deg`): e_a -> cos e_a + sin e_b.
function planeRotation(plane, deg) {
  const i = AXES[plane[0]], j = AXES[plane[1]];
  const t = deg * Math.PI / 180, c = Math.cos(t), s = Math.sin(t);
  const g = I4.slice();
  g[i * 4 + i] = c; g[j * 4 + j] = c; g[j * 4 + i] = s; g[i * 4 + j] = -s;
  return g;
}

// An orthonormal basis of the complement of span(vectors).
function complement(vectors) {
  const basis = [];
  for (const v of vectors) {
    let w = v.slice();
    for (const b of basis) w = sub(w, scale(b, dot(w, b)));
    if (norm(w) > 1e-9) basis.push(scale(w, 1 / norm(w)));
  }
  const rest = [];
  const candidates = [0, 1, 2, 3].map((k) => I4.slice(k * 4, k * 4 + 4));
  while (basis.length + rest.length < 4) {
    let best = null;
    for (const e of candidates) {
      let w = e.slice();
      for (const b of basis.concat(rest)) w = sub(w, scale(b, dot(w, b)));
      if (!best || norm(w) > norm(best)) best = w;
    }
    rest.push(scale(best, 1 / norm(best)));
  }
  return rest;
}

// G = R'·Rᵀ is a proper rotation fixing the complement of span(fixedOutside).
function checkPlaneRotation(before, after, span, what) {
  const g = mul(after, transpose(before));
  const ggt = mul(g, transpose(g));
  ok(maxDiff(ggt, I4) < 1e-6, `${what}: R'·Rᵀ is not orthogonal (|GGᵀ-I| ${maxDiff(ggt, I4).toExponential(2)})`);
  ok(Math.abs(det(g) - 1) < 1e-6, `${what}: det(R'·Rᵀ) = ${det(g)}`);
  ok(maxDiff(g, I4) > 1e-4, `${what}: the rotation did not change`);
  for (const v of complement(span)) {
    const moved = norm(sub(apply(g, v), v));
    ok(moved < 1e-6, `${what}: R'·Rᵀ moves [${v.map((x) => x.toFixed(3))}], orthogonal to ` +
      `span(screen axis, normal), by ${moved.toExponential(2)}`);
  }
  return g;
}

// ---------------------------------------------------------------------------------------------
// PNG: the bytes of a screenshot to RGBA pixels (8-bit, non-interlaced; what Chromium writes)

function pngSize(buf) {
  const sig = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a];
  if (buf.length < 24 || sig.some((b, i) => buf[i] !== b)) return null;
  return { width: buf.readUInt32BE(16), height: buf.readUInt32BE(20) };
}

function decodePng(buf) {
  const size = pngSize(buf);
  if (!size) throw new Failure('not a PNG');
  let pos = 8, depth = 0, type = 0, interlace = 0;
  const idat = [];
  while (pos < buf.length) {
    const len = buf.readUInt32BE(pos), kind = buf.toString('latin1', pos + 4, pos + 8);
    const data = buf.subarray(pos + 8, pos + 8 + len);
    if (kind === 'IHDR') { depth = data[8]; type = data[9]; interlace = data[12]; }
    if (kind === 'IDAT') idat.push(data);
    if (kind === 'IEND') break;
    pos += 12 + len;
  }
  const channels = { 0: 1, 2: 3, 4: 2, 6: 4 }[type];
  if (depth !== 8 || !channels || interlace) throw new Failure(`PNG of depth ${depth}, type ${type}`);
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const { width, height } = size, stride = width * channels;
  const px = Buffer.alloc(stride * height);
  for (let y = 0; y < height; y += 1) {
    const f = raw[y * (stride + 1)], line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; x += 1) {
      const a = x >= channels ? px[y * stride + x - channels] : 0;
      const b = y > 0 ? px[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? px[(y - 1) * stride + x - channels] : 0;
      let v = line[x];
      if (f === 1) v += a;
      else if (f === 2) v += b;
      else if (f === 3) v += (a + b) >> 1;
      else if (f === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        v += pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      px[y * stride + x] = v & 255;
    }
  }
  const rgba = Buffer.alloc(width * height * 4);
  for (let i = 0; i < width * height; i += 1) {
    const s = px.subarray(i * channels, i * channels + channels);
    const grey = channels <= 2;
    rgba[i * 4] = s[0]; rgba[i * 4 + 1] = grey ? s[0] : s[1]; rgba[i * 4 + 2] = grey ? s[0] : s[2];
    rgba[i * 4 + 3] = channels === 4 ? s[3] : channels === 2 ? s[1] : 255;
  }
  return { width, height, rgba };
}

// Pixels that differ from the background: from a picture of the same view with nothing cut
// (same size) when there is one, else from the most common colour of the border.
function foreground(img, empty) {
  const n = img.width * img.height, mask = new Uint8Array(n);
  let bg = null;
  if (!empty) {
    const tally = new Map();
    for (let x = 0; x < img.width; x += 1)
      for (const y of [0, img.height - 1]) {
        const i = (y * img.width + x) * 4;
        const key = img.rgba.readUInt32BE(i);
        tally.set(key, (tally.get(key) || 0) + 1);
      }
    const key = [...tally.entries()].sort((a, b) => b[1] - a[1])[0][0];
    bg = [key >>> 24, (key >>> 16) & 255, (key >>> 8) & 255];
  }
  let count = 0;
  for (let i = 0; i < n; i += 1) {
    const r = empty ? [empty.rgba[i * 4], empty.rgba[i * 4 + 1], empty.rgba[i * 4 + 2]] : bg;
    const d = Math.abs(img.rgba[i * 4] - r[0]) + Math.abs(img.rgba[i * 4 + 1] - r[1]) +
      Math.abs(img.rgba[i * 4 + 2] - r[2]);
    if (d > 30) { mask[i] = 1; count += 1; }
  }
  return { mask, count };
}

function iou(a, b) {
  let inter = 0, union = 0;
  for (let i = 0; i < a.mask.length; i += 1) {
    inter += a.mask[i] & b.mask[i];
    union += a.mask[i] | b.mask[i];
  }
  return union ? inter / union : 1;
}

// ---------------------------------------------------------------------------------------------
// The native command line

function run(file, argv) {
  return new Promise((resolve) => {
    execFile(file, argv, { maxBuffer: 1 << 24, timeout: 300000 }, (error, stdout, stderr) =>
      resolve({ code: error ? (error.code ?? 1) : 0, stdout, stderr }));
  });
}

const COUNT = /(\d+) (vertex|vertices|edges?|faces?|cells?|rank-\d+ elements?)/g;

// `cw4d slice` of the model cut by n·x = d where the page cuts R·model by n·x = d: the same
// section (up to the rotation) as the model itself cut by (Rᵀn)·x = d.
// `model` names the model for the CLI when state.model does not (a file opened in the page is
// `file:NAME`: the path of the same file).
async function nativeSlice(args, tmp, state, model = state.model) {
  const n = apply(transpose(state.rotation), state.normal);
  const argv = ['slice', model, '--normal', n.map((x) => String(x)).join(','),
    '--offset', String(state.offset), '-o', path.join(tmp, 'native-section.obj')];
  const r = await run(args.cw4d, argv);
  const cmd = `cw4d ${argv.map((a) => (/\s/.test(a) ? `'${a}'` : a)).join(' ')}`;
  // A plane that misses the model: `cw4d slice` says so (exit 5) and writes nothing.
  if (r.code === 5 && /misses/.test(r.stderr))
    return { fvector: [], volume: 0, line: r.stderr.trim().split('\n')[0], cmd };
  if (r.code !== 0) throw new Failure(`${cmd} exited ${r.code}: ${r.stderr.trim()}`);
  const line = r.stdout.trim().split('\n')[0];
  const head = line.split(': ').slice(1).join(': ');
  const counts = [...head.split(', volume')[0].matchAll(COUNT)].map((m) => Number(m[1]));
  const vol = /volume (\S+)/.exec(head);
  return { fvector: counts, volume: vol ? Number(vol[1]) : NaN, line, cmd };
}

async function compareWithNative(args, tmp, page, what, model = undefined) {
  const { state, counts } = await page.evaluate(() => ({
    state: window.cw4dViewer.state(), counts: window.cw4dViewer.counts() }));
  const native = await nativeSlice(args, tmp, state, model);
  ok(counts && native.fvector.length > 0 && counts.fvector.some((k) => k > 0), `${what}: the section is empty (offset ${state.offset}, ` +
    `radius ${state.radius}; ${counts ? `counts() (${counts.fvector})` : 'counts() is null'}, native '${native.line}')`);
  ok(JSON.stringify(counts.fvector) === JSON.stringify(native.fvector),
    `${what}: page f-vector (${counts.fvector}) volume ${counts.volume}, native '${native.line}' ` +
    `(${native.cmd})`);
  ok(Math.abs(counts.volume - native.volume) <= 1e-5 * Math.max(Math.abs(native.volume), 1e-9) + 1e-12,
    `${what}: page volume ${counts.volume}, native '${native.line}'`);
  return { state, counts, native };
}

// ---------------------------------------------------------------------------------------------
// The static server

const TYPES = { '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.wasm': 'application/wasm', '.css': 'text/css', '.json': 'application/json', '.png': 'image/png',
  '.svg': 'image/svg+xml', '.ico': 'image/x-icon', '.data': 'application/octet-stream',
  '.bin': 'application/octet-stream', '.4off': 'text/plain', '.off': 'text/plain', '.txt': 'text/plain',
  '.g4tf': 'application/json', '.g4b': 'application/octet-stream' };

function startServer(root) {
  const server = http.createServer((req, res) => {
    let rel;
    try {
      rel = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    } catch {
      res.writeHead(400).end();
      return;
    }
    if (rel.endsWith('/')) rel += 'index.html';
    const file = path.join(root, path.normalize(rel));
    if (!file.startsWith(root + path.sep)) { res.writeHead(403).end(); return; }
    fs.readFile(file, (err, data) => {
      if (err) {
        // The browser asks for a favicon by itself; the page has none to give.
        res.writeHead(rel === '/favicon.ico' ? 204 : 404).end();
        return;
      }
      res.writeHead(200, { 'Content-Type': TYPES[path.extname(file).toLowerCase()] || 'application/octet-stream',
        'Cache-Control': 'no-store' });
      res.end(data);
    });
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

// ---------------------------------------------------------------------------------------------
// The page

const READY = 120000;
const pageErrors = [];

async function openPage(context, base, query = '') {
  const page = await context.newPage();
  page.setDefaultTimeout(15000);
  const log = { errors: [] };
  page.on('console', (m) => { if (m.type() === 'error') log.errors.push(m.text()); });
  page.on('pageerror', (e) => {
    log.errors.push(`uncaught ${e.message}`);
    pageErrors.push(e.message.split('\n')[0]);
  });
  await page.goto(`${base}/index.html${query ? `?${query}` : ''}`, { timeout: 60000 });
  await waitReady(page);
  return { page, log };
}

function waitReady(page, timeout = READY) {
  return page.waitForFunction(() => window.cw4dViewer && window.cw4dViewer.ready === true, null,
    { timeout, polling: 50 });
}

const state = (page) => page.evaluate(() => window.cw4dViewer.state());
const counts = (page) => page.evaluate(() => window.cw4dViewer.counts());
const frames = (page, n = 2) => page.evaluate((k) => new Promise((resolve) => {
  const step = (left) => (left ? requestAnimationFrame(() => step(left - 1)) : resolve());
  step(k);
}), n);

// Polls state() until `pred(state)` holds; returns the last state either way.
async function waitState(page, pred, ms = 5000) {
  const end = Date.now() + ms;
  let s = await state(page);
  while (!pred(s) && Date.now() < end) {
    await page.waitForTimeout(50);
    s = await state(page);
  }
  return s;
}

// Key presses go to the page, not to a focused form control.
async function focusView(page) {
  await page.evaluate(() => {
    const a = document.activeElement;
    if (a && a !== document.body && a.blur) a.blur();
  });
}

async function canvasCentre(page) {
  const box = await page.locator('canvas#view').boundingBox();
  if (!box) throw new Failure('canvas#view has no box');
  return { x: box.x + box.width / 2, y: box.y + box.height / 2, box };
}

async function drag(page, dx, dy, { shift = false, button = 'left' } = {}) {
  const c = await canvasCentre(page);
  await page.mouse.move(c.x, c.y);
  if (shift) await page.keyboard.down('Shift');
  await page.mouse.down({ button });
  await page.mouse.move(c.x + dx, c.y + dy, { steps: 10 });
  await page.mouse.up({ button });
  if (shift) await page.keyboard.up('Shift');
  await frames(page);
}

// The plane put at `fraction` of the model's radius with the offset slider, as a user drags it.
async function setOffset(page, fraction) {
  const r = (await state(page)).radius;
  await page.locator('input#offset').fill(String(fraction * r));
  await frames(page);
  return state(page);
}

async function loadFromPicker(page, spec) {
  await page.selectOption('select#model', spec);
  return waitModel(page, spec);
}

async function waitModel(page, spec) {
  await page.waitForFunction((m) => window.cw4dViewer.state().model === m && window.cw4dViewer.ready === true,
    spec, { timeout: READY, polling: 50 });
  return state(page);
}

// A file dropped on the page as a user drops one from a file manager: a DataTransfer holding a
// File of the file's bytes, dropped on the canvas (the page listens on the window).
async function dropFile(page, file) {
  const transfer = await page.evaluateHandle(({ name, base64 }) => {
    const bytes = Uint8Array.from(atob(base64), (ch) => ch.charCodeAt(0));
    const dt = new DataTransfer();
    dt.items.add(new File([bytes], name));
    return dt;
  }, { name: path.basename(file), base64: fs.readFileSync(file).toString('base64') });
  await page.dispatchEvent('canvas#view', 'dragover', { dataTransfer: transfer });
  await page.dispatchEvent('canvas#view', 'drop', { dataTransfer: transfer });
  await transfer.dispose();
}

// Waits for the status line to show an error; returns {cls, text}.
async function waitError(page) {
  await page.waitForFunction(() => document.querySelector('#status').classList.contains('error'), null,
    { timeout: 15000 }).catch(() => {});
  return page.locator('#status').evaluate((e) => ({ cls: e.className, text: e.textContent.trim() }));
}

// The error line `cw4d info NAME` prints for a bad file, run in the file's folder so that it
// names the file as the page does (by its name alone).
async function nativeError(args, file) {
  const r = await new Promise((resolve) => execFile(args.cw4d, ['info', path.basename(file)],
    { cwd: path.dirname(file), timeout: 60000 }, (error, stdout, stderr) =>
      resolve({ code: error ? (error.code ?? 1) : 0, stderr })));
  return { code: r.code, lines: r.stderr.trim().split('\n') };
}

const sameRotation = (a, b, tol = 1e-9) => maxDiff(a, b) <= tol;
const fmtv = (v, d = 4) => `[${v.map((x) => Number(x).toFixed(d)).join(',')}]`;

async function screenshot(args, page, name, options = {}) {
  if (!args.screenshots) return null;
  const file = path.join(args.screenshots, name);
  await page.screenshot({ path: file, ...options });
  return file;
}

async function download(page, selector, dir) {
  const [dl] = await Promise.all([page.waitForEvent('download', { timeout: 60000 }), page.click(selector)]);
  const name = dl.suggestedFilename();
  const file = path.join(dir, name);
  await dl.saveAs(file);
  const failure = await dl.failure();
  if (failure) throw new Failure(`${selector}: download failed: ${failure}`);
  return { name, file, bytes: fs.readFileSync(file) };
}

// A picture of the canvas alone: whatever the page lays over it (labels, gauges, legends) is
// made invisible first (layout unchanged), so that only what WebGL drew is compared.
const CANVAS_ONLY = '* { visibility: hidden !important; } canvas#view { visibility: visible !important; }';
async function canvasPicture(page) {
  const tag = await page.addStyleTag({ content: CANVAS_ONLY });
  await frames(page, 2);
  const png = await page.locator('canvas#view').screenshot();
  await tag.evaluate((e) => e.remove());
  return png;
}

// frameBench of `path` with 20 frames, or fewer when a frame is so slow (a software GPU) that 20
// would take longer than `seconds`: one frame first (it also warms the path up), then the run.
async function timedFrames(page, path, seconds) {
  const probe = await page.evaluate((p) => window.cw4dViewer.frameBench({ path: p, frames: 1 }), path);
  const frames = Math.max(2, Math.min(20, Math.floor(seconds * 1000 / Math.max(probe.msPerFrame, 1e-3))));
  const r = await page.evaluate(([p, k]) => window.cw4dViewer.frameBench({ path: p, frames: k }), [path, frames]);
  if (!(r && r.frames === frames && Number.isFinite(r.msPerFrame)))
    throw new Failure(`frameBench ${path} of ${frames} frames gave ${JSON.stringify(r)}`);
  return r;
}

// ---------------------------------------------------------------------------------------------
// The checks

async function main() {
  const args = parseArgs(process.argv.slice(2));
  fs.mkdirSync(args.out, { recursive: true });
  if (args.screenshots) fs.mkdirSync(args.screenshots, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'cw4d-viewer-test-'));
  const downloads = path.join(args.out, 'downloads');
  fs.mkdirSync(downloads, { recursive: true });

  let chromium;
  try {
    ({ chromium } = requireTools('playwright-core'));
  } catch (e) {
    usage(`playwright-core not found under ${TOOLS}/node_modules (run npm ci there): ${e.message}`);
  }
  const server = await startServer(args.site);
  const base = `http://127.0.0.1:${server.address().port}`;
  let browser = null, browserPid = 0;
  const closeAll = async () => {
    let closed = !browser;
    if (browser) {
      const closing = browser.close().then(() => true, () => false);
      closed = await Promise.race([closing, new Promise((resolve) => setTimeout(() => resolve(false), 10000).unref())]);
    }
    // A browser that did not close (busy in a long frame) goes with its process group.
    if (!closed && browserPid) {
      try { process.kill(-browserPid, 'SIGKILL'); } catch { /* gone already */ }
    }
    browser = null;
    browserPid = 0;
    await new Promise((resolve) => server.close(resolve));
    server.closeAllConnections?.();
    fs.rmSync(tmp, { recursive: true, force: true });
  };
  // The whole run is bounded too: past --timeout the browser and the server are stopped.
  const deadline = setTimeout(async () => {
    stopped = true;
    console.log(`viewer_test: FAIL the run took longer than ${args.timeout} s; stopped`);
    results.push({ name: 'deadline', ok: false });
    await closeAll();
    finish(args, null);
  }, args.timeout * 1000);
  deadline.unref();
  for (const signal of ['SIGINT', 'SIGTERM', 'SIGHUP'])
    process.on(signal, async () => {
      stopped = true;
      console.log(`viewer_test: FAIL stopped by ${signal}`);
      results.push({ name: signal, ok: false });
      await closeAll();
      finish(args, null);
    });

  const bench = [];
  try {
    browser = await chromium.launch({
      executablePath: args.chromium, headless: true, timeout: 60000,
      args: ['--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-sandbox',
        '--disable-background-networking', '--disable-component-update', '--no-first-run',
        '--disable-renderer-backgrounding', '--disable-background-timer-throttling'],
      handleSIGINT: false, handleSIGTERM: false, handleSIGHUP: false,
    });
    const cdp = await browser.newBrowserCDPSession();
    const { processInfo } = await cdp.send('SystemInfo.getProcessInfo');
    browserPid = (processInfo.find((p) => p.type === 'browser') || {}).id || 0;
    await cdp.detach();
    await runChecks(args, browser, base, tmp, downloads, bench);
  } catch (e) {
    console.log(`viewer_test: FAIL harness: ${String(e && e.message || e).split('\n')[0]}`);
    results.push({ name: 'harness', ok: false });
  } finally {
    clearTimeout(deadline);
    await closeAll();
  }
  finish(args, bench);
}

let renderer = null;  // the WebGL renderer the frame times were measured on

function finish(args, bench) {
  if (bench) {
    fs.writeFileSync(path.join(args.out, 'viewer_bench.json'), `${JSON.stringify({
      note: 'frame times of window.cw4dViewer.frameBench in headless Chromium; "gpu" is the ' +
        'GPU path on the renderer below (SwiftShader draws on the CPU); reported, never asserted',
      renderer, bench }, null, 2)}\n`);
  }
  const passed = results.filter((r) => r.ok).length, failed = results.length - passed;
  console.log(`viewer_test: ${passed} passed, ${failed} failed`);
  process.exit(failed ? 1 : 0);
}

async function runChecks(args, browser, base, tmp, downloads, bench) {
  const desktop = await browser.newContext({ viewport: { width: 1200, height: 800 }, acceptDownloads: true });
  await desktop.grantPermissions(['clipboard-read', 'clipboard-write'], { origin: base });
  let page = null, log = null, initial = null;

  // 1. The default view.
  await check('1 the page opens on its default view', async () => {
    ({ page, log } = await openPage(desktop, base));
    await frames(page, 3);
    initial = await state(page);
    const c = await counts(page);
    const status = await page.locator('#status').evaluate((e) => ({ cls: e.className, text: e.textContent.trim() }));
    ok(log.errors.length === 0, `console errors: ${log.errors.join(' | ')}`);
    ok(!/\berror\b/.test(status.cls), `#status shows an error: '${status.text}'`);
    ok(Array.isArray(c.fvector) && c.fvector.length > 0 && c.fvector.every((k) => k > 0),
      `counts().fvector of the default view is (${c.fvector})`);
    ok(c.triangles > 0, `counts().triangles of the default view is ${c.triangles}`);
    ok(Array.isArray(initial.rotation) && initial.rotation.length === 16, 'state().rotation is not 16 numbers');
    const fv = (await page.locator('#fvector').textContent()).trim();
    ok(c.fvector.every((k) => fv.includes(String(k))), `#fvector '${fv}' does not show (${c.fvector})`);
    // Every control fits the side panel's width: no horizontal scrollbar under it.
    const panel = await page.locator('#panel').evaluate((e) => ({ scroll: e.scrollWidth, client: e.clientWidth }));
    ok(panel.scroll <= panel.client, `#panel is ${panel.scroll} px wide inside ${panel.client} px`);
    await screenshot(args, page, 'viewer-whole.png');
  });
  if (!page) return;  // nothing else can run without the page

  // 2. Drag orbits; Shift-drag rotates in 4D in the plane (screen axis, normal).
  await check('2a drag orbits the camera, not the model', async () => {
    const before = await state(page);
    await drag(page, 90, 50);
    const after = await waitState(page, (s) => s.yaw !== before.yaw || s.pitch !== before.pitch);
    ok(after.yaw !== before.yaw, `yaw stayed ${before.yaw}`);
    ok(after.pitch !== before.pitch, `pitch stayed ${before.pitch}`);
    ok(sameRotation(after.rotation, before.rotation), 'the rotation changed');
    ok(after.offset === before.offset, `the offset changed ${before.offset} -> ${after.offset}`);
  });
  await check('2b Shift-drag (horizontal) rotates in the plane (screen right, normal)', async () => {
    const axes = await page.evaluate(() => window.cw4dViewer.screenAxes());
    const [before, cBefore] = [await state(page), await counts(page)];
    ok(Math.abs(dot(axes.right, axes.normal)) < 1e-6 && Math.abs(dot(axes.up, axes.normal)) < 1e-6,
      `screenAxes(): right·normal ${dot(axes.right, axes.normal)}, up·normal ${dot(axes.up, axes.normal)}`);
    const n = norm(before.normal);
    ok(maxDiff(axes.normal, scale(before.normal, 1 / n)) < 1e-6,
      `screenAxes().normal ${fmtv(axes.normal)} is not state().normal ${fmtv(before.normal)} made unit`);
    await drag(page, 120, 0, { shift: true });
    const after = await waitState(page, (s) => !sameRotation(s.rotation, before.rotation));
    checkPlaneRotation(before.rotation, after.rotation, [axes.right, axes.normal], 'Shift-drag right');
    ok(after.offset === before.offset, `the offset changed ${before.offset} -> ${after.offset}`);
    ok(after.yaw === before.yaw && after.pitch === before.pitch, 'the camera moved too');
    const cAfter = await counts(page);
    ok(JSON.stringify(cAfter) !== JSON.stringify(cBefore), `the section stayed (${cBefore.fvector}), volume ${cBefore.volume}`);
  });
  await check('2c Shift-drag (vertical) rotates in the plane (screen up, normal)', async () => {
    const axes = await page.evaluate(() => window.cw4dViewer.screenAxes());
    const before = await state(page);
    await drag(page, 0, -100, { shift: true });
    const after = await waitState(page, (s) => !sameRotation(s.rotation, before.rotation));
    checkPlaneRotation(before.rotation, after.rotation, [axes.up, axes.normal], 'Shift-drag up');
    ok(after.offset === before.offset, `the offset changed ${before.offset} -> ${after.offset}`);
  });
  await check('2d right-drag rotates in 4D like Shift-drag', async () => {
    const axes = await page.evaluate(() => window.cw4dViewer.screenAxes());
    const before = await state(page);
    await drag(page, -80, 0, { button: 'right' });
    const after = await waitState(page, (s) => !sameRotation(s.rotation, before.rotation));
    checkPlaneRotation(before.rotation, after.rotation, [axes.right, axes.normal], 'right-drag');
    ok(after.yaw === before.yaw && after.pitch === before.pitch, 'the camera moved too');
  });

  // 3. Wheel and arrows move the plane; Shift-wheel zooms.
  await check('3a wheel down lowers the offset, wheel up raises it', async () => {
    const c = await canvasCentre(page);
    await page.mouse.move(c.x, c.y);
    const s0 = await state(page);
    await page.mouse.wheel(0, 100);
    const s1 = await waitState(page, (s) => s.offset !== s0.offset);
    ok(s1.offset < s0.offset, `wheel down: offset ${s0.offset} -> ${s1.offset}`);
    await page.mouse.wheel(0, -100);
    const s2 = await waitState(page, (s) => s.offset !== s1.offset);
    ok(s2.offset > s1.offset, `wheel up: offset ${s1.offset} -> ${s2.offset}`);
    ok(sameRotation(s2.rotation, s0.rotation) && s2.zoom === s0.zoom, 'the wheel changed the rotation or the zoom');
  });
  await check('3b ArrowUp raises the offset, ArrowDown lowers it', async () => {
    await focusView(page);
    const s0 = await state(page);
    await page.keyboard.press('ArrowUp');
    const s1 = await waitState(page, (s) => s.offset !== s0.offset);
    ok(s1.offset > s0.offset, `ArrowUp: offset ${s0.offset} -> ${s1.offset}`);
    await page.keyboard.press('ArrowDown');
    await page.keyboard.press('ArrowDown');
    const s2 = await waitState(page, (s) => s.offset < s1.offset);
    ok(s2.offset < s1.offset, `ArrowDown: offset ${s1.offset} -> ${s2.offset}`);
    await frames(page);
    const slider = Number(await page.locator('input#offset').inputValue());
    // (a range input rounds its value to its step; the page's is a 500th of the radius)
    ok(Math.abs(slider - s2.offset) <= (s2.radius || 1) / 400,
      `input#offset shows ${slider}, state().offset ${s2.offset}`);
  });
  await check('3c Shift-wheel zooms without moving the plane', async () => {
    const c = await canvasCentre(page);
    await page.mouse.move(c.x, c.y);
    const s0 = await state(page);
    await page.keyboard.down('Shift');
    await page.mouse.wheel(0, 100);
    await page.keyboard.up('Shift');
    const s1 = await waitState(page, (s) => s.zoom !== s0.zoom);
    ok(s1.zoom !== s0.zoom, `zoom stayed ${s0.zoom}`);
    ok(s1.offset === s0.offset, `the offset moved ${s0.offset} -> ${s1.offset}`);
  });

  // 4. Keys rotate by 5° in the world's coordinate planes; KeyR resets.
  await check('4a Digit1..Digit6 rotate by +5° in xy xz yz xw yw zw: R\' = G(5°)·R', async () => {
    await focusView(page);
    for (let k = 0; k < 6; k += 1) {
      const before = await state(page);
      await page.keyboard.press(`Digit${k + 1}`);
      const after = await waitState(page, (s) => !sameRotation(s.rotation, before.rotation));
      const want = mul(planeRotation(PLANES[k], 5), before.rotation);
      ok(maxDiff(after.rotation, want) <= 1e-5,
        `Digit${k + 1}: R' differs from G_${PLANES[k]}(5°)·R by ${maxDiff(after.rotation, want).toExponential(2)}` +
        (maxDiff(after.rotation, mul(planeRotation(PLANES[k], -5), before.rotation)) <= 1e-5 ? ' (it is G(-5°)·R)' :
          maxDiff(after.rotation, mul(before.rotation, planeRotation(PLANES[k], 5))) <= 1e-5 ? ' (it is R·G(5°))' : ''));
    }
  });
  await check('4b Shift+Digit4 undoes Digit4', async () => {
    await focusView(page);
    const s0 = await state(page);
    await page.keyboard.press('Digit4');
    const s1 = await waitState(page, (s) => !sameRotation(s.rotation, s0.rotation));
    ok(maxDiff(s1.rotation, mul(planeRotation('xw', 5), s0.rotation)) <= 1e-5, 'Digit4 is not G_xw(5°)·R');
    await page.keyboard.press('Shift+Digit4');
    const s2 = await waitState(page, (s) => !sameRotation(s.rotation, s1.rotation));
    ok(maxDiff(s2.rotation, s0.rotation) <= 1e-5,
      `Shift+Digit4 after Digit4 leaves R off by ${maxDiff(s2.rotation, s0.rotation).toExponential(2)}`);
  });
  await check('4c KeyR resets rotation, offset and camera to the opening view', async () => {
    await focusView(page);
    const moved = await state(page);
    ok(!sameRotation(moved.rotation, initial.rotation, 1e-6) || moved.yaw !== initial.yaw,
      'the view was not moved before the reset');
    await page.keyboard.press('KeyR');
    const s = await waitState(page, (x) => sameRotation(x.rotation, initial.rotation, 1e-9) &&
      x.offset === initial.offset && x.yaw === initial.yaw);
    ok(sameRotation(s.rotation, initial.rotation, 1e-9), `rotation after KeyR ${fmtv(s.rotation, 3)}, opening ${fmtv(initial.rotation, 3)}`);
    ok(Math.abs(s.offset - initial.offset) < 1e-12, `offset after KeyR ${s.offset}, opening ${initial.offset}`);
    ok(s.yaw === initial.yaw && s.pitch === initial.pitch && s.zoom === initial.zoom,
      `camera after KeyR ${s.yaw},${s.pitch},${s.zoom}, opening ${initial.yaw},${initial.pitch},${initial.zoom}`);
    await page.click('button#reset');
    const r = await state(page);
    ok(sameRotation(r.rotation, initial.rotation, 1e-9) && r.offset === initial.offset, 'button#reset does not keep the reset view');
  });

  // 5. Space plays and pauses.
  await check('5 Space starts and stops playback', async () => {
    await focusView(page);
    const s0 = await state(page);
    ok(!s0.playing, 'playing before Space');
    await page.keyboard.press('Space');
    const s1 = await waitState(page, (s) => s.playing, 2000);
    ok(s1.playing, 'state().playing is not true after Space');
    await page.waitForTimeout(600);
    const s2 = await state(page);
    ok(s2.offset !== s1.offset || !sameRotation(s2.rotation, s1.rotation),
      `nothing moved in 0.6 s of playback (anim ${s2.anim})`);
    await focusView(page);
    await page.keyboard.press('Space');
    const s3 = await waitState(page, (s) => !s.playing, 2000);
    ok(!s3.playing, 'state().playing is still true after the second Space');
    await page.waitForTimeout(300);
    const s4 = await state(page);
    ok(s4.offset === s3.offset && sameRotation(s4.rotation, s3.rotation), 'the view still moves after the pause');
    await page.keyboard.press('KeyR');
    await waitReady(page);
  });

  // 6. Model change through the picker and the library; the section is the native one.
  await check('6a select#model picks the 24-cell; the section equals cw4d slice', async () => {
    // Picked after a larger model, the plane may stay at the new model's rim (an empty
    // section): said, not failed; the slider then puts it through the model.
    const s = await loadFromPicker(page, '24-cell');
    await frames(page);
    const c = await counts(page);
    const empty = !c || c.fvector.every((k) => k === 0);
    if (empty)
      console.log(`viewer_test: note: the 24-cell picked from the previous model shows an empty section ` +
        `(offset ${s.offset}, radius ${s.radius})`);
    if (!empty) {
      await compareWithNative(args, tmp, page, '24-cell as picked');
    } else {
      const native = await nativeSlice(args, tmp, await state(page));
      ok(native.fvector.length === 0, `24-cell as picked: the page shows no section, native '${native.line}'`);
    }
    const moved = await setOffset(page, 0.3);
    ok(Math.abs(moved.offset - 0.3 * moved.radius) <= moved.radius / 400,
      `the offset slider set to 0.3 r gives offset ${moved.offset} (r ${moved.radius})`);
    const shown = await page.locator('select#model').evaluate((e) => ({ value: e.value,
      text: e.selectedOptions[0] ? e.selectedOptions[0].textContent : '' }));
    ok(shown.value === '24-cell', `select#model shows '${shown.value}' ('${shown.text}')`);
    ok(s.model === '24-cell', `state().model is '${s.model}'`);
    await compareWithNative(args, tmp, page, '24-cell');
    const groups = await page.locator('select#model optgroup').count();
    ok(groups >= 2, `select#model has ${groups} optgroups`);
  });
  await check('6b the same view, turned by keys and the plane moved, still equals cw4d slice', async () => {
    await focusView(page);
    for (const k of ['Digit4', 'Digit4', 'Digit5', 'Digit1', 'Digit6', 'ArrowUp']) await page.keyboard.press(k);
    await frames(page);
    await compareWithNative(args, tmp, page, '24-cell turned');
  });
  await check('6c the library lists its groups and loads a duoprism', async () => {
    await page.click('button#library-button');
    await page.locator('div#library').waitFor({ state: 'visible', timeout: 10000 });
    const text = (await page.locator('div#library').textContent()).toLowerCase();
    for (const heading of ['regular', 'convex uniform', 'star', 'prisms and duoprisms', 'round', 'toratopes'])
      ok(text.includes(heading), `the library has no '${heading}' group`);
    await screenshot(args, page, 'viewer-library.png');
    const specs = await page.locator('div#library [data-spec]').evaluateAll((els) => els.map((e) => e.dataset.spec));
    const spec = specs.find((x) => /^duoprism:/.test(x));
    ok(spec, `no duoprism among the library's ${specs.length} buttons`);
    await page.locator(`div#library [data-spec="${spec}"]`).first().click();
    const s = await waitModel(page, spec);
    const shown = await page.locator('select#model').evaluate((e) => ({ value: e.value,
      text: e.selectedOptions[0] ? e.selectedOptions[0].textContent : '' }));
    ok(shown.value === spec || shown.text.includes(spec), `select#model shows '${shown.value}' ('${shown.text}') for ${spec}`);
    ok(s.model === spec, `state().model is '${s.model}'`);
    await setOffset(page, 0.2);
    await compareWithNative(args, tmp, page, spec);
    if (await page.locator('div#library').isVisible()) await page.keyboard.press('Escape');
  });
  await check('6d a model outside the list shows as its own option', async () => {
    const spec = 'duoprism:4,9';
    await page.evaluate((x) => window.cw4dViewer.load(x), spec);
    await waitModel(page, spec);
    const shown = await page.locator('select#model').evaluate((e) => ({ value: e.value,
      text: e.selectedOptions[0] ? e.selectedOptions[0].textContent : '' }));
    ok(shown.value === spec || shown.text.includes(spec), `select#model shows '${shown.value}' ('${shown.text}') for ${spec}`);
  });

  // 6e. G4MF files, opened as a person opens them: the file picker and a drop on the page.
  await check('6e G4MF: a .g4tf from the file picker, .g4b files dropped; sections equal cw4d slice; bad files are one error line', async () => {
    const files = path.join(tmp, 'g4mf');
    fs.mkdirSync(files, { recursive: true });
    const miratope = path.resolve(HERE, '../../tests/data/miratope');
    const samples = path.resolve(HERE, '../../tests/data/g4mf');
    const convert = async (source, name) => {
      const out = path.join(files, name);
      const r = await run(args.cw4d, ['convert', path.join(miratope, source), '-o', out]);
      ok(r.code === 0 && fs.existsSync(out), `cw4d convert ${source} -o ${name} exited ${r.code}: ${r.stderr.trim()}`);
      return out;
    };
    const g4tf = await convert('convex uniform/Runcitruncated tesseract.off', 'runcitruncated-tesseract.g4tf');
    const g4b = await convert('convex uniform/Bitruncated icositetrachoron.off', 'bitruncated-24-cell.g4b');
    const bytes = fs.readFileSync(g4b);
    ok(bytes.subarray(0, 4).toString('latin1') === 'G4MF' && bytes.includes(0) && bytes.some((b) => b >= 0x80),
      `${g4b} is not binary G4MF (magic, zero bytes and bytes >= 0x80 expected)`);
    const foreign = path.join(files, 'tesseract-two-surfaces.g4b');
    fs.copyFileSync(path.join(samples, 'tesseract-two-surfaces.g4b'), foreign);
    const badJson = path.join(files, 'broken.g4tf');
    const text = fs.readFileSync(g4tf);
    fs.writeFileSync(badJson, text.subarray(0, Math.floor(text.length / 2)));
    const badBinary = path.join(files, 'truncated.g4b');
    fs.writeFileSync(badBinary, bytes.subarray(0, Math.floor(bytes.length / 2)));

    const { page: p, log: plog } = await openPage(desktop, base);
    try {
      // The whole model as the page read it against `cw4d info` of the same file, then the
      // section at two offsets against `cw4d slice` of the same file.
      const sameModel = async (file) => {
        const name = path.basename(file);
        // Loaded, or refused with an error line (said at once, not after a timeout).
        await p.waitForFunction((m) => (window.cw4dViewer.state().model === m && window.cw4dViewer.ready) ||
          document.querySelector('#status').classList.contains('error'), `file:${name}`, { timeout: READY, polling: 50 });
        const refused = await p.locator('#status').evaluate((e) => (e.classList.contains('error') ? e.textContent.trim() : ''));
        ok(!refused, `opening ${name} shows the error '${refused}'`);
        const s = await waitModel(p, `file:${name}`);
        const r = await run(args.cw4d, ['info', file, '--json']);
        ok(r.code === 0, `cw4d info ${file} exited ${r.code}: ${r.stderr.trim()}`);
        const native = JSON.parse(r.stdout).fvector;
        const modelinfo = (await p.locator('#modelinfo').textContent()).trim();
        ok(modelinfo.startsWith(`${name}: (${native.join(', ')})`),
          `#modelinfo '${modelinfo}', cw4d info f-vector (${native})`);
        const status = await p.locator('#status').evaluate((e) => ({ cls: e.className, text: e.textContent.trim() }));
        ok(!/\berror\b/.test(status.cls), `#status after opening ${name}: '${status.text}'`);
        const picked = await p.locator('select#model').evaluate((e) => e.selectedOptions[0] ? e.selectedOptions[0].textContent : '');
        ok(picked === name, `select#model shows '${picked}' for ${name}`);
        await frames(p);
        await compareWithNative(args, tmp, p, `${name} as opened`, file);
        await setOffset(p, -0.2);
        await compareWithNative(args, tmp, p, `${name} at d = -0.2 r`, file);
        return s;
      };
      await p.locator('input#file').setInputFiles(g4tf);
      await sameModel(g4tf);
      await screenshot(args, p, 'viewer-g4tf.png');
      await dropFile(p, g4b);
      await sameModel(g4b);
      await focusView(p);
      for (const k of ['Digit4', 'Digit5', 'Digit6']) await p.keyboard.press(k);
      await frames(p);
      await compareWithNative(args, tmp, p, 'bitruncated-24-cell.g4b turned', g4b);
      await screenshot(args, p, 'viewer-g4b.png');
      await dropFile(p, foreign);
      await sameModel(foreign);
      // Written without cw4d's code, the file is the tesseract [-1, 1]^4: the built-in's section.
      await compareWithNative(args, tmp, p, 'tesseract-two-surfaces.g4b against the built-in tesseract', 'tesseract');

      // Bad files: one error line, the native CLI's message for the same bytes; the model
      // shown stays.
      for (const [file, how] of [[badJson, 'picker'], [badBinary, 'drop']]) {
        const name = path.basename(file);
        const before = await state(p);
        if (how === 'picker') await p.locator('input#file').setInputFiles(file);
        else await dropFile(p, file);
        const shown = await waitError(p);
        ok(/\berror\b/.test(shown.cls) && shown.text.includes(name) && !shown.text.includes('\n'),
          `#status after the bad ${name} (${how}): class '${shown.cls}', '${shown.text}'`);
        const native = await nativeError(args, file);
        ok(native.code !== 0 && native.lines.length === 1 && native.lines[0].endsWith(shown.text),
          `${name}: the page says '${shown.text}', cw4d info exits ${native.code} with '${native.lines.join(' | ')}'`);
        if (how === 'drop') await screenshot(args, p, 'viewer-g4mf-error.png');
        const after = await state(p);
        ok(after.model === before.model, `the bad ${name} replaced the model (${before.model} -> ${after.model})`);
        await compareWithNative(args, tmp, p, `${before.model} after the bad ${name}`, foreign);
      }
      // A good file after a bad one clears the error.
      await p.locator('input#file').setInputFiles(g4tf);
      await waitModel(p, `file:${path.basename(g4tf)}`);
      const cleared = await p.locator('#status').evaluate((e) => e.className);
      ok(!/\berror\b/.test(cleared), `#status keeps the error after ${path.basename(g4tf)} opened`);
      ok(plog.errors.length === 0, `console errors: ${plog.errors.join(' | ')}`);
    } finally {
      await p.close();
    }
  }, 240);

  // 7. The spec / Coxeter-diagram box.
  await check('7 the Coxeter box: an invalid diagram is an error line, x4o3o3x loads and clears it', async () => {
    const before = await state(page);
    await page.fill('input#spec', 'x4o3q3x');
    await page.press('input#spec', 'Enter');
    await page.waitForFunction(() => document.querySelector('#status').classList.contains('error'), null, { timeout: 10000 })
      .catch(() => {});
    const bad = await page.locator('#status').evaluate((e) => ({ cls: e.className, text: e.textContent.trim() }));
    ok(/\berror\b/.test(bad.cls) && bad.text.length > 0, `#status after 'x4o3q3x': class '${bad.cls}', '${bad.text}'`);
    ok(!bad.text.includes('\n'), `the error is not one line: '${bad.text}'`);
    ok((await state(page)).model === before.model, 'the invalid diagram replaced the model');
    await page.fill('input#spec', 'x4o3o3x');
    await page.press('input#spec', 'Enter');
    await page.waitForFunction(() => /x4o3o3x/.test(window.cw4dViewer.state().model) && window.cw4dViewer.ready,
      null, { timeout: READY, polling: 50 });
    const good = await page.locator('#status').evaluate((e) => ({ cls: e.className, text: e.textContent.trim() }));
    ok(!/\berror\b/.test(good.cls), `#status after x4o3o3x: class '${good.cls}', '${good.text}'`);
    await setOffset(page, -0.25);
    await compareWithNative(args, tmp, page, 'x4o3o3x');
  }, 180);

  // 8. Downloads.
  await check('8 downloads: OBJ, GLB, STL and PNG of the shown section', async () => {
    await loadFromPicker(page, 'tesseract');
    await setOffset(page, 0.15);
    await focusView(page);
    for (const k of ['Digit4', 'Digit5', 'Digit6', 'ArrowUp']) await page.keyboard.press(k);
    await frames(page);
    const c = await counts(page);
    ok(c.triangles > 0, `the section has ${c.triangles} triangles`);
    const failures = [];
    const soft = (cond, msg) => { if (!cond) failures.push(msg); };
    // OBJ: its faces, triangulated (a k-gon is k-2 triangles), are the section's triangles.
    const obj = await download(page, 'button#dl-obj', downloads);
    soft(obj.name === 'cw4d-section.obj', `OBJ named '${obj.name}'`);
    const faces = obj.bytes.toString('utf8').split('\n').filter((l) => /^f\s/.test(l))
      .map((l) => l.trim().split(/\s+/).length - 1);
    const objTriangles = faces.reduce((s, k) => s + k - 2, 0);
    soft(faces.length === c.triangles || objTriangles === c.triangles,
      `OBJ has ${faces.length} faces (${objTriangles} triangles), counts().triangles ${c.triangles}`);
    // GLB: the Khronos glTF-Validator finds no error.
    const glb = await download(page, 'button#dl-glb', downloads);
    soft(glb.name === 'cw4d-section.glb', `GLB named '${glb.name}'`);
    soft(glb.bytes.length > 12 && glb.bytes.toString('latin1', 0, 4) === 'glTF', 'the GLB has no glTF magic');
    const validator = requireTools('gltf-validator');
    const report = await validator.validateBytes(new Uint8Array(glb.bytes), { uri: glb.name, maxIssues: 0 });
    const issues = report.issues;
    soft(issues.numErrors === 0, `glTF-Validator: ${issues.numErrors} errors, first: ` +
      `${(issues.messages.find((m) => m.severity === 0) || {}).code} ${(issues.messages.find((m) => m.severity === 0) || {}).message}`);
    const glbTriangles = (report.info && report.info.totalTriangleCount);
    // STL: binary (84 + 50 n bytes) or ASCII (one 'facet' per triangle).
    const stl = await download(page, 'button#dl-stl', downloads);
    soft(stl.name === 'cw4d-section.stl', `STL named '${stl.name}'`);
    let stlTriangles = -1;
    if (stl.bytes.length >= 84 && stl.bytes.length === 84 + 50 * stl.bytes.readUInt32LE(80))
      stlTriangles = stl.bytes.readUInt32LE(80);
    else if (stl.bytes.toString('latin1', 0, 5) === 'solid')
      stlTriangles = (stl.bytes.toString('latin1').match(/\bfacet\s+normal\b/g) || []).length;
    soft(stlTriangles === c.triangles, `STL has ${stlTriangles} triangles, counts().triangles ${c.triangles}`);
    // PNG: a PNG of the canvas's size.
    const png = await download(page, 'button#dl-png', downloads);
    soft(png.name === 'cw4d-view.png', `PNG named '${png.name}'`);
    const size = pngSize(png.bytes);
    const canvas = await page.locator('canvas#view').evaluate((e) => ({ width: e.width, height: e.height }));
    soft(size !== null, 'the PNG has no PNG signature');
    soft(size && size.width === canvas.width && size.height === canvas.height,
      `PNG ${size && size.width}x${size && size.height}, canvas ${canvas.width}x${canvas.height}`);
    for (const d of [obj, glb, stl, png]) soft(d.bytes.length > 0, `${d.name} is empty`);
    console.log(`viewer_test: downloads: ${c.triangles} triangles; OBJ ${faces.length} faces, GLB ` +
      `${glbTriangles ?? '?'} triangles (${issues.numWarnings} validator warnings), STL ${stlTriangles}, ` +
      `PNG ${size && size.width}x${size && size.height}`);
    ok(failures.length === 0, failures.join('; '));
  }, 180);

  // 9. Copy link.
  let link = null, linked = null;
  await check('9a KeyV cycles the whole-view mode and KeyG toggles the GPU path', async () => {
    await focusView(page);
    const s0 = await state(page);
    await page.keyboard.press('KeyV');
    const s1 = await waitState(page, (s) => s.whole !== s0.whole);
    ok(s1.whole !== s0.whole && ['shadow', 'persp', 'off'].includes(s1.whole), `KeyV: whole ${s0.whole} -> ${s1.whole}`);
    ok((await page.locator('select#whole').inputValue()) === s1.whole, 'select#whole does not follow KeyV');
    await page.keyboard.press('KeyG');
    const s2 = await waitState(page, (s) => s.gpu !== s0.gpu);
    ok(s2.gpu !== s0.gpu, `KeyG: gpu stayed ${s0.gpu}`);
    ok((await page.locator('input#gpu').isChecked()) === Boolean(s2.gpu), 'input#gpu does not follow KeyG');
    await waitReady(page);
  });
  await check('9b Copy link: the link reopens the same view', async () => {
    await focusView(page);
    for (const k of ['Digit2', 'Digit6', 'Digit6', 'ArrowUp']) await page.keyboard.press(k);
    await frames(page);
    const s = await state(page);
    await page.click('button#copy-link');
    await page.waitForFunction(() => {
      const e = document.querySelector('#link-text');
      return e && (e.value || e.textContent || e.href || '').trim().length > 0;
    }, null, { timeout: 5000 }).catch(() => {});
    const shown = await page.evaluate(() => {
      const e = document.querySelector('#link-text');
      return e ? (e.value || e.textContent || e.href || '').trim() : '';
    });
    const href = await page.evaluate(() => location.href);
    link = shown || href;
    ok(/^https?:\/\//.test(link), `#link-text shows '${shown}'`);
    const clip = await page.evaluate(() => navigator.clipboard.readText()).catch(() => null);
    if (clip !== null) ok(clip === link, `the clipboard holds '${clip}', #link-text '${link}'`);
    const fresh = await openPage(desktop, base);
    await fresh.page.goto(link, { timeout: 60000 });
    await waitReady(fresh.page);
    linked = await state(fresh.page);
    ok(linked.model === s.model, `model ${linked.model}, copied from ${s.model}`);
    ok(maxDiff(linked.rotation, s.rotation) <= 1e-4, `rotation differs by ${maxDiff(linked.rotation, s.rotation).toExponential(2)}`);
    ok(Math.abs(linked.offset - s.offset) <= 1e-4, `offset ${linked.offset}, copied from ${s.offset}`);
    ok(linked.whole === s.whole, `whole ${linked.whole}, copied from ${s.whole}`);
    ok(Boolean(linked.gpu) === Boolean(s.gpu), `gpu ${linked.gpu}, copied from ${s.gpu}`);
    ok(fresh.log.errors.length === 0, `console errors on the linked page: ${fresh.log.errors.join(' | ')}`);
    await fresh.page.close();
  });

  // 10. Help.
  await check('10 ? shows the help, Escape hides it; KeyH toggles it', async () => {
    await focusView(page);
    ok(!(await page.locator('div#help').isVisible()), '#help is visible before ?');
    await page.keyboard.press('?');
    await page.locator('div#help').waitFor({ state: 'visible', timeout: 3000 }).catch(() => {});
    ok(await page.locator('div#help').isVisible(), '#help is not visible after ?');
    await page.keyboard.press('Escape');
    await page.locator('div#help').waitFor({ state: 'hidden', timeout: 3000 }).catch(() => {});
    ok(!(await page.locator('div#help').isVisible()), '#help is still visible after Escape');
    await focusView(page);
    await page.keyboard.press('KeyH');
    await page.locator('div#help').waitFor({ state: 'visible', timeout: 3000 }).catch(() => {});
    ok(await page.locator('div#help').isVisible(), '#help is not visible after KeyH');
    await page.keyboard.press('KeyH');
    await page.locator('div#help').waitFor({ state: 'hidden', timeout: 3000 }).catch(() => {});
    ok(!(await page.locator('div#help').isVisible()), '#help is still visible after a second KeyH');
    await page.click('button#help-button');
    await page.locator('div#help').waitFor({ state: 'visible', timeout: 3000 }).catch(() => {});
    ok(await page.locator('div#help').isVisible(), '#help is not visible after button#help-button');
    await page.keyboard.press('Escape');
  });

  // 11. A phone.
  await check('11 a phone (390x844, touch): layout, panel sheet, touch gestures', async () => {
    const phone = await browser.newContext({ viewport: { width: 390, height: 844 }, hasTouch: true,
      isMobile: true, deviceScaleFactor: 2 });
    try {
      const { page: p, log: plog } = await openPage(phone, base, 'model=24-cell');
      await frames(p, 3);
      const failures = [];
      const soft = (cond, msg) => { if (!cond) failures.push(msg); };
      const width = await p.evaluate(() => Math.max(document.documentElement.scrollWidth, document.body.scrollWidth));
      soft(width <= 390, `the page is ${width} px wide`);
      const box = await p.locator('canvas#view').boundingBox();
      soft(box && box.height >= 300, `the canvas is ${box && box.height} px tall`);
      soft(await p.locator('canvas#view').isVisible(), 'the canvas is not visible');
      soft(await p.locator('button#panel-toggle').isVisible(), 'button#panel-toggle is not visible');
      // The sheet: tapping #panel-toggle opens it (every control shown); if it was open
      // already, a tap closes it (some control hidden) and a second one opens it again.
      const CONTROLS = ['select#model', 'input#spec', 'input#offset', 'button#play', 'select#anim',
        'button#reset', 'select#whole', 'input#gpu', 'button#dl-obj', 'button#copy-link'];
      const shown = async () => {
        const v = [];
        for (const sel of CONTROLS) if (await p.locator(sel).isVisible()) v.push(sel);
        return v;
      };
      const tapToggle = async () => {
        await p.locator('button#panel-toggle').tap();
        await p.waitForTimeout(400);  // (a sheet may slide)
      };
      const v0 = await shown();
      await tapToggle();
      let v1 = await shown();
      if (v0.length === CONTROLS.length) {
        soft(v1.length < CONTROLS.length, 'the panel was open and tapping #panel-toggle hid nothing');
        await tapToggle();
        v1 = await shown();
      }
      soft(v1.length === CONTROLS.length, `after tapping #panel-toggle, hidden: ` +
        `${CONTROLS.filter((x) => !v1.includes(x)).join(' ')}`);
      const box1 = await p.locator('canvas#view').boundingBox();
      soft(box1 && box1.height >= 300, `with the panel open the canvas is ${box1 && box1.height} px tall`);
      const width1 = await p.evaluate(() => Math.max(document.documentElement.scrollWidth, document.body.scrollWidth));
      soft(width1 <= 390, `with the panel open the page is ${width1} px wide`);
      const sheet = await p.locator('#panel').evaluate((e) => ({ scroll: e.scrollWidth, client: e.clientWidth }));
      soft(sheet.scroll <= sheet.client, `the open sheet is ${sheet.scroll} px wide inside ${sheet.client} px`);
      await screenshot(args, p, 'viewer-phone.png');
      await p.locator('canvas#view').scrollIntoViewIfNeeded();
      const cdp = await phone.newCDPSession(p);
      const c = await canvasCentre(p);
      const touch = (type, points) => cdp.send('Input.dispatchTouchEvent', { type, touchPoints: points });
      const gesture = async (at) => {
        await touch('touchStart', at(0));
        for (let i = 1; i <= 12; i += 1) await touch('touchMove', at(i / 12));
        await touch('touchEnd', []);
        await frames(p);
      };
      // One finger: orbit.
      let s0 = await state(p);
      await gesture((t) => [{ x: c.x + 60 * t, y: c.y + 20 * t, id: 1 }]);
      let s1 = await waitState(p, (s) => s.yaw !== s0.yaw || s.pitch !== s0.pitch, 2000);
      soft(s1.yaw !== s0.yaw || s1.pitch !== s0.pitch, 'a one-finger drag did not orbit');
      soft(sameRotation(s1.rotation, s0.rotation), 'a one-finger drag changed the 4D rotation');
      // Two fingers moving together: 4D rotation.
      s0 = await state(p);
      await gesture((t) => [{ x: c.x - 50 + 80 * t, y: c.y, id: 1 }, { x: c.x + 50 + 80 * t, y: c.y, id: 2 }]);
      s1 = await waitState(p, (s) => !sameRotation(s.rotation, s0.rotation), 2000);
      soft(!sameRotation(s1.rotation, s0.rotation), 'a two-finger drag did not change the rotation');
      // Pinch (fingers closing): zoom.
      s0 = await state(p);
      await gesture((t) => [{ x: c.x - 90 + 60 * t, y: c.y, id: 1 }, { x: c.x + 90 - 60 * t, y: c.y, id: 2 }]);
      s1 = await waitState(p, (s) => s.zoom !== s0.zoom, 2000);
      soft(s1.zoom !== s0.zoom, `a pinch did not zoom (zoom ${s0.zoom})`);
      soft(plog.errors.length === 0, `console errors: ${plog.errors.join(' | ')}`);
      ok(failures.length === 0, failures.join('; '));
    } finally {
      await phone.close();
    }
  }, 150);

  // 12. The GPU path draws what the CPU path draws.
  await check('12a the GPU path and the CPU path cover the same pixels (IoU >= 0.95)', async () => {
    const view = 'model=24-cell&R=' + mul(planeRotation('xw', 25), mul(planeRotation('yz', 20), planeRotation('zw', -15)))
      .map((x) => x.toFixed(12)).join(',') + '&n=0,0,0,1&d=0.3&whole=off&tex=0&play=0';
    const shots = {};
    const { page: p } = await openPage(desktop, base, `${view}&gpu=0`);
    try {
      const s = await state(p);
      ok(!s.gpu && s.whole === 'off', `the URL asked gpu=0 whole=off, state() has gpu ${s.gpu} whole ${s.whole}`);
      await frames(p, 3);
      const cpuPng = await canvasPicture(p);
      shots.cpu = decodePng(cpuPng);
      await p.locator('input#gpu').check();
      await waitState(p, (x) => x.gpu, 5000);
      await waitReady(p);
      await frames(p, 3);
      ok((await state(p)).gpu, 'input#gpu did not switch the GPU path on');
      const gpuPng = await canvasPicture(p);
      shots.gpu = decodePng(gpuPng);
      // The same view with the plane beyond the model: the background alone.
      const radius = s.radius || 10;
      const e = await openPage(desktop, base, `${view.replace('d=0.3', `d=${(radius * 0.999).toFixed(6)}`)}&gpu=0`);
      await frames(e.page, 3);
      const emptyCounts = await counts(e.page);
      const empty = emptyCounts && emptyCounts.triangles === 0 ? decodePng(await canvasPicture(e.page)) : null;
      await e.page.close();
      const a = foreground(shots.cpu, empty), b = foreground(shots.gpu, empty);
      const score = iou(a, b);
      console.log(`viewer_test: GPU/CPU picture of the 24-cell: IoU ${score.toFixed(4)} (${a.count} and ${b.count} ` +
        `pixels, background ${empty ? 'from an empty cut' : 'from the border'})`);
      ok(a.count >= 1000, `the CPU picture covers only ${a.count} pixels`);
      ok(score >= 0.95, `IoU ${score.toFixed(4)} < 0.95 (CPU ${a.count}, GPU ${b.count} pixels)`);
      fs.writeFileSync(path.join(args.out, 'viewer-iou-cpu.png'), cpuPng);
      fs.writeFileSync(path.join(args.out, 'viewer-iou-gpu.png'), gpuPng);
    } finally {
      await p.close();
    }
  }, 180);
  await check('14 a checker on a lattice wall does not speckle (the tesseract at w = 0), on both paths', async () => {
    // The cells' UVW along w is exactly on a checker wall at d = 0; the oracle is the same view
    // with the plane 1e-4 above the wall, where no sample is near it: same picture.
    const view = 'model=tesseract&R=1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1&n=0,0,0,1&whole=off&tex=1&edges=0&play=0';
    for (const gpu of [0, 1]) {
      const pictures = [];
      for (const d of ['0', '0.0001']) {
        const { page: p } = await openPage(desktop, base, `${view}&d=${d}&gpu=${gpu}`);
        try {
          await frames(p, 3);
          ok((await state(p)).gpu === (gpu === 1), `gpu=${gpu} was not applied`);
          pictures.push(decodePng(await canvasPicture(p)));
        } finally {
          await p.close();
        }
      }
      const [a, b] = pictures;
      let differ = 0, covered = 0;
      for (let i = 0; i < a.width * a.height; i += 1) {
        const d = Math.abs(a.rgba[4 * i] - b.rgba[4 * i]) + Math.abs(a.rgba[4 * i + 1] - b.rgba[4 * i + 1]) +
          Math.abs(a.rgba[4 * i + 2] - b.rgba[4 * i + 2]);
        if (d > 30) differ += 1;
        if (b.rgba[4 * i] + b.rgba[4 * i + 1] + b.rgba[4 * i + 2] > 120) covered += 1;
      }
      console.log(`viewer_test: checker on the wall, ${gpu ? 'GPU' : 'CPU'} path: ${differ} of ${covered} covered pixels differ from d = 1e-4`);
      ok(covered > 10000, `the section covers only ${covered} pixels`);
      ok(differ <= covered / 1000, `${differ} pixels differ between d = 0 and d = 1e-4 (speckle)`);
    }
  }, 180);
  await check('12b frameBench runs both paths on the same tetrahedra', async () => {
    await page.evaluate(() => window.cw4dViewer.load('24-cell'));
    await waitModel(page, '24-cell');
    const before = await state(page);
    const cpu = await page.evaluate(() => window.cw4dViewer.frameBench({ path: 'cpu', frames: 5 }));
    const gpu = await page.evaluate(() => window.cw4dViewer.frameBench({ path: 'gpu', frames: 5 }));
    for (const [k, r] of [['cpu', cpu], ['gpu', gpu]]) {
      ok(r && r.frames === 5, `frameBench ${k}: frames ${r && r.frames}`);
      ok(Number.isFinite(r.msPerFrame) && r.msPerFrame > 0, `frameBench ${k}: msPerFrame ${r.msPerFrame}`);
    }
    ok(gpu.tetrahedra > 0, `frameBench gpu: tetrahedra ${gpu.tetrahedra}`);
    // The CPU path slices the cells themselves; when it names tetrahedra they are the GPU's.
    ok(!cpu.tetrahedra || cpu.tetrahedra === gpu.tetrahedra,
      `frameBench: cpu ${cpu.tetrahedra}, gpu ${gpu.tetrahedra} tetrahedra`);
    const s = await state(page);
    ok(!s.gpu === !before.gpu && s.offset === before.offset && s.whole === before.whole,
      'frameBench left the view changed');
  }, 120);

  // 13. Frame time (reported, never asserted).
  for (const spec of ['omnitruncated 120-cell', 'duoprism:360,360']) {
    await check(`13 frame time of ${spec} (reported)`, async () => {
      const t0 = Date.now();
      await page.evaluate((x) => window.cw4dViewer.load(x), spec);
      await waitModel(page, spec);
      const loadSeconds = (Date.now() - t0) / 1000;
      if (!renderer) {
        renderer = await page.evaluate(() => {
          const gl = document.createElement('canvas').getContext('webgl2');
          const ext = gl && gl.getExtension('WEBGL_debug_renderer_info');
          return gl ? gl.getParameter(ext ? ext.UNMASKED_RENDERER_WEBGL : gl.RENDERER) : 'no WebGL2';
        });
        console.log(`viewer_test: WebGL renderer: ${renderer}`);
      }
      const cpu = await timedFrames(page, 'cpu', args.benchSeconds);
      const gpu = await timedFrames(page, 'gpu', args.benchSeconds);
      const row = { model: spec, tetrahedra: gpu.tetrahedra ?? cpu.tetrahedra, loadSeconds,
        cpu: { msPerFrame: cpu.msPerFrame, fps: cpu.fps, frames: cpu.frames },
        gpu: { msPerFrame: gpu.msPerFrame, fps: gpu.fps, frames: gpu.frames },
        gpuOverCpu: gpu.fps / cpu.fps };
      bench.push(row);
      console.log(`viewer_test: frame time ${spec} (${row.tetrahedra} tetrahedra, load ${loadSeconds.toFixed(1)} s): ` +
        `CPU ${cpu.fps.toFixed(2)} fps (${cpu.msPerFrame.toFixed(1)} ms, ${cpu.frames} frames), ` +
        `GPU ${gpu.fps.toFixed(2)} fps (${gpu.msPerFrame.toFixed(1)} ms, ${gpu.frames} frames), ` +
        `GPU/CPU ${row.gpuOverCpu.toFixed(2)}x`);
    }, 120 + 6 * args.benchSeconds);
  }

  await check('no uncaught exception in any page', async () => {
    ok(pageErrors.length === 0, pageErrors.join(' | '));
  });
}

main();
