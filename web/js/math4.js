// Small dense linear algebra for the viewer's placement: n x n matrices as plain arrays, row by
// row (m[r * n + c]), n = 3 or 4. A placement is a rotation R (world = R . model); the viewer
// composes it from plane rotations, x -> G x, where G turns the plane of two orthonormal
// vectors u, v by an angle and leaves everything orthogonal to them alone:
//   G = I + (cos a - 1)(u u^T + v v^T) + sin a (v u^T - u v^T),   so G u = cos a u + sin a v.

export const AXES = 'xyzw';
// The six coordinate planes, in the order of the keys 1-6.
export const COORDINATE_PLANES = ['xy', 'xz', 'yz', 'xw', 'yw', 'zw'];

export function identity(n) {
  const m = new Array(n * n).fill(0);
  for (let i = 0; i < n; ++i) m[i * n + i] = 1;
  return m;
}

export function multiply(a, b, n) {
  const out = new Array(n * n).fill(0);
  for (let r = 0; r < n; ++r)
    for (let c = 0; c < n; ++c) {
      let sum = 0;
      for (let k = 0; k < n; ++k) sum += a[r * n + k] * b[k * n + c];
      out[r * n + c] = sum;
    }
  return out;
}

export function transpose(a, n) {
  const out = new Array(n * n);
  for (let r = 0; r < n; ++r) for (let c = 0; c < n; ++c) out[c * n + r] = a[r * n + c];
  return out;
}

export function apply(m, x, n) {
  const out = new Array(n).fill(0);
  for (let r = 0; r < n; ++r) for (let c = 0; c < n; ++c) out[r] += m[r * n + c] * x[c];
  return out;
}

export const dot = (a, b) => a.reduce((s, x, i) => s + x * b[i], 0);
export const norm = (a) => Math.sqrt(dot(a, a));
export const scaled = (a, s) => a.map((x) => x * s);

// The rotation by `angle` (radians) in the plane of the vectors u and v (made orthonormal
// here: v loses its part along u). Returns null when they do not span a plane.
export function planeRotation(u, v, angle, n) {
  const lu = norm(u);
  if (!(lu > 1e-12)) return null;
  const e1 = scaled(u, 1 / lu);
  const w = v.map((x, i) => x - dot(v, e1) * e1[i]);
  const lw = norm(w);
  if (!(lw > 1e-12)) return null;
  const e2 = scaled(w, 1 / lw);
  const c = Math.cos(angle) - 1, s = Math.sin(angle);
  const g = identity(n);
  for (let r = 0; r < n; ++r)
    for (let k = 0; k < n; ++k)
      g[r * n + k] += c * (e1[r] * e1[k] + e2[r] * e2[k]) + s * (e2[r] * e1[k] - e1[r] * e2[k]);
  return g;
}

// The rotation by `degrees` in a coordinate plane such as 'xw' (x turns towards w).
export function coordinateRotation(plane, degrees, n) {
  const a = AXES.indexOf(plane[0]), b = AXES.indexOf(plane[1]);
  if (a < 0 || b < 0 || a >= n || b >= n || a === b) return null;
  const u = new Array(n).fill(0), v = new Array(n).fill(0);
  u[a] = 1;
  v[b] = 1;
  return planeRotation(u, v, degrees * Math.PI / 180, n);
}

// The nearest rotation by Gram-Schmidt on the rows: repeated products drift from orthogonal.
// Returns null for a (nearly) singular matrix. A reflection (det < 0) keeps its sign.
export function orthonormalize(m, n) {
  const rows = [];
  for (let r = 0; r < n; ++r) {
    let row = m.slice(r * n, r * n + n);
    for (const q of rows) {
      const d = dot(row, q);
      row = row.map((x, i) => x - d * q[i]);
    }
    const l = norm(row);
    if (!(l > 1e-6)) return null;
    rows.push(scaled(row, 1 / l));
  }
  return rows.flat();
}

// A 4D rotation from a list of [plane, degrees] applied in order (as the CLI's --rotate).
export function fromRotations(list, n) {
  let m = identity(n);
  for (const [plane, deg] of list) {
    const g = coordinateRotation(plane, deg, n);
    if (g) m = multiply(g, m, n);
  }
  return m;
}

// The matrix embedded in a 4 x 4 one (a 3 x 3 placement gets w untouched), column-major
// Float32Array for WebGL.
export function glMatrix4(m, n) {
  const out = new Float32Array(16);
  for (let r = 0; r < 4; ++r)
    for (let c = 0; c < 4; ++c)
      out[4 * c + r] = r < n && c < n ? m[r * n + c] : (r === c ? 1 : 0);
  return out;
}
