// WebGL2 drawing of a section: the CPU path (triangles from the WebAssembly core), the polygon
// outlines, the GPU tetrahedral path and the whole polytope's wireframe around the section
// (shaders.js); an orbit camera; coverage readback.
import { FRAGMENT, CPU_VERTEX, LINE_VERTEX, LINE_FRAGMENT, TET_VERTEX, TETS_PER_ROW, WIRE_VERTEX, WIRE_FRAGMENT } from './shaders.js';

export function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
  return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0,
    2 * far * near * nf, 0]);
}

// Column-major 4x4 product a * b.
export function mul4(a, b) {
  const out = new Float32Array(16);
  for (let c = 0; c < 4; ++c)
    for (let r = 0; r < 4; ++r) {
      let sum = 0;
      for (let k = 0; k < 4; ++k) sum += a[4 * k + r] * b[4 * c + k];
      out[4 * c + r] = sum;
    }
  return out;
}

// The camera on a sphere around the origin: T(0, 0, -distance) * Rx(pitch) * Ry(yaw).
export function orbitView(yaw, pitch, distance) {
  const cy = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
  const ry = new Float32Array([cy, 0, -sy, 0, 0, 1, 0, 0, sy, 0, cy, 0, 0, 0, 0, 1]);
  const rx = new Float32Array([1, 0, 0, 0, 0, cp, sp, 0, 0, -sp, cp, 0, 0, 0, 0, 1]);
  const t = new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -distance, 1]);
  return mul4(t, mul4(rx, ry));
}

function compile(gl, type, source) {
  const s = gl.createShader(type);
  gl.shaderSource(s, source);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS))
    throw new Error('shader: ' + gl.getShaderInfoLog(s));
  return s;
}

function program(gl, vs, fs) {
  const p = gl.createProgram();
  gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, vs));
  gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, fs));
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error('link: ' + gl.getProgramInfoLog(p));
  const uniforms = {};
  const n = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < n; ++i) {
    const name = gl.getActiveUniform(p, i).name;
    uniforms[name] = gl.getUniformLocation(p, name);
  }
  return { p, u: uniforms, a: (name) => gl.getAttribLocation(p, name) };
}

function buffer(gl, target, data) {
  const b = gl.createBuffer();
  gl.bindBuffer(target, b);
  gl.bufferData(target, data, gl.STATIC_DRAW);
  return b;
}

export class Renderer {
  constructor(canvas) {
    const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
    if (!gl) throw new Error('this browser has no WebGL2');
    this.gl = gl;
    this.canvas = canvas;
    this.cpu = program(gl, CPU_VERTEX, FRAGMENT);
    this.line = program(gl, LINE_VERTEX, LINE_FRAGMENT);
    this.tet = program(gl, TET_VERTEX, FRAGMENT);
    this.wire = program(gl, WIRE_VERTEX, WIRE_FRAGMENT);
    this.emptyVao = gl.createVertexArray();  // the GPU path reads no attributes
    this.mesh = null;
    this.tets = null;
    this.wires = null;
  }

  // Uploads the model's wireframe (the core's wireframe(): 4 numbers per vertex, vertex id
  // pairs): one instance per edge holding both ends.
  setWireframe(w) {
    const gl = this.gl;
    if (this.wires) {
      gl.deleteBuffer(this.wires.buffer);
      gl.deleteVertexArray(this.wires.vao);
      this.wires = null;
    }
    if (!w || w.error || w.edges.length === 0) return;
    const count = w.edges.length / 2;
    const ends = new Float32Array(8 * count);
    for (let e = 0; e < count; ++e)
      for (let k = 0; k < 2; ++k) {
        const v = w.edges[2 * e + k];
        for (let j = 0; j < 4; ++j) ends[8 * e + 4 * k + j] = w.positions[4 * v + j];
      }
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const b = buffer(gl, gl.ARRAY_BUFFER, ends);
    ['aP0', 'aP1'].forEach((name, k) => {
      const loc = this.wire.a(name);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, 4, gl.FLOAT, false, 32, 16 * k);
      gl.vertexAttribDivisor(loc, 1);
    });
    gl.bindVertexArray(null);
    this.wires = { vao, buffer: b, count };
  }

  // Uploads a slice of the core (positions, normals, colours, uvw, indices, outline).
  setSection(slice) {
    const gl = this.gl;
    this.dropMesh();
    if (!slice || !slice.indices || slice.indices.length === 0) return;
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const buffers = [];
    for (const [name, data] of [['aPosition', slice.positions], ['aNormal', slice.normals],
      ['aColour', slice.colours], ['aUvw', slice.uvw]]) {
      buffers.push(buffer(gl, gl.ARRAY_BUFFER, data));
      const loc = this.cpu.a(name);
      if (loc < 0) continue;
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, 3, gl.FLOAT, false, 0, 0);
    }
    buffers.push(buffer(gl, gl.ELEMENT_ARRAY_BUFFER, slice.indices));
    gl.bindVertexArray(null);
    const lineVao = gl.createVertexArray();
    gl.bindVertexArray(lineVao);
    buffers.push(buffer(gl, gl.ARRAY_BUFFER, slice.outline));
    gl.enableVertexAttribArray(this.line.a('aPosition'));
    gl.vertexAttribPointer(this.line.a('aPosition'), 3, gl.FLOAT, false, 0, 0);
    gl.bindVertexArray(null);
    this.mesh = { vao, lineVao, buffers, count: slice.indices.length,
      lines: slice.outline.length / 3 };
  }

  dropMesh() {
    if (!this.mesh) return;
    const gl = this.gl;
    this.mesh.buffers.forEach((b) => gl.deleteBuffer(b));
    gl.deleteVertexArray(this.mesh.vao);
    gl.deleteVertexArray(this.mesh.lineVao);
    this.mesh = null;
  }

  // Uploads the tetrahedra of the core (tets()) into the GPU path's float texture (shaders.js:
  // nine texels per tetrahedron). Returns an error line when the GPU cannot hold them.
  setTets(t) {
    const gl = this.gl;
    if (this.tets) {
      gl.deleteTexture(this.tets.texture);
      this.tets = null;
    }
    if (!t || t.error || t.count === 0) return '';
    const rows = Math.ceil(t.count / TETS_PER_ROW), width = 9 * TETS_PER_ROW;
    if (rows > gl.getParameter(gl.MAX_TEXTURE_SIZE) || width > gl.getParameter(gl.MAX_TEXTURE_SIZE))
      return `${t.count} tetrahedra need a ${width} x ${rows} texture, more than this GPU's ` +
        `${gl.getParameter(gl.MAX_TEXTURE_SIZE)}`;
    const data = new Float32Array(width * rows * 4);
    for (let k = 0; k < t.count; ++k) {
      const at = 36 * k;  // 9 texels of 4 floats
      data.set(t.corners.subarray(16 * k, 16 * k + 16), at);
      data.set(t.uvw.subarray(12 * k, 12 * k + 12), at + 16);
      data.set(t.normals.subarray(4 * k, 4 * k + 4), at + 28);
      data.set(t.colours.subarray(3 * k, 3 * k + 3), at + 32);
    }
    const texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, width, rows, 0, gl.RGBA, gl.FLOAT, data);
    gl.bindTexture(gl.TEXTURE_2D, null);
    this.tets = { texture, count: t.count };
    return '';
  }

  // view: {yaw, pitch, distance, radius}; opts: {gpu, edges, cellColours, backFaces, texture,
  // mask, placement (Float32Array 16 + 4), normal (4), offset, basis (Float32Array 12),
  // whole ('shadow', 'persp' or 'off'), slab (> 0: the half-width of a thick slice)}.
  draw(view, opts, target = null) {
    const gl = this.gl;
    const w = target ? target.width : this.canvas.width;
    const h = target ? target.height : this.canvas.height;
    gl.bindFramebuffer(gl.FRAMEBUFFER, target ? target.fb : null);
    gl.viewport(0, 0, w, h);
    gl.clearColor(opts.mask ? 0 : 0.09, opts.mask ? 0 : 0.1, opts.mask ? 0 : 0.12, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    if (opts.backFaces) gl.disable(gl.CULL_FACE);
    else gl.enable(gl.CULL_FACE);
    const proj = perspective(0.7, w / h, view.distance * 0.05, view.distance * 4);
    const mv = orbitView(view.yaw, view.pitch, view.distance);
    const shade = (prog) => {
      gl.useProgram(prog.p);
      gl.uniformMatrix4fv(prog.u.uProjection, false, proj);
      gl.uniformMatrix4fv(prog.u.uView, false, mv);
      gl.uniform1i(prog.u.uCellColours, opts.cellColours ? 1 : 0);
      gl.uniform1i(prog.u.uTexture, opts.texture ? 1 : 0);
      gl.uniform1i(prog.u.uMask, opts.mask ? 1 : 0);
      gl.uniform1f(prog.u.uChecks, 4.0);
    };
    // The placement and the hyperplane, for the programs that work in 4D.
    const place = (u) => {
      const pl = opts.placement;
      gl.uniformMatrix4fv(u.uLinear, false, pl.subarray(0, 16));
      gl.uniform4fv(u.uTranslation, pl.subarray(16, 20));
      gl.uniform4fv(u.uPlaneNormal, opts.normal);
      gl.uniform1f(u.uPlaneOffset, opts.offset);
      const b = opts.basis, basis = new Float32Array(16);
      for (let c = 0; c < 3; ++c) for (let r = 0; r < 4; ++r) basis[4 * c + r] = b[4 * c + r] ?? 0;
      gl.uniformMatrix4fv(u.uBasis, false, basis);
      if (u.uModelNormal) {
        // L^T n and d - n . t: the plane in model space.
        const m = [0, 1, 2, 3].map((j) => [0, 1, 2, 3].reduce((sum, i) => sum + pl[4 * j + i] * opts.normal[i], 0));
        gl.uniform4fv(u.uModelNormal, m);
        gl.uniform1f(u.uModelOffset, opts.offset - [0, 1, 2, 3].reduce((sum, i) => sum + opts.normal[i] * pl[16 + i], 0));
      }
    };
    if (opts.gpu) {
      if (this.tets) {
        shade(this.tet);
        place(this.tet.u);
        gl.activeTexture(gl.TEXTURE0);
        gl.bindTexture(gl.TEXTURE_2D, this.tets.texture);
        gl.uniform1i(this.tet.u.uTets, 0);
        gl.bindVertexArray(this.emptyVao);
        gl.drawArrays(gl.TRIANGLES, 0, 6 * this.tets.count);
        gl.bindTexture(gl.TEXTURE_2D, null);
      }
    } else if (this.mesh) {
      shade(this.cpu);
      gl.bindVertexArray(this.mesh.vao);
      gl.drawElements(gl.TRIANGLES, this.mesh.count, gl.UNSIGNED_INT, 0);
    }
    if (opts.edges && this.mesh && !opts.mask && !opts.gpu) {  // (the GPU path has no outline)
      gl.useProgram(this.line.p);
      gl.uniformMatrix4fv(this.line.u.uProjection, false, proj);
      gl.uniformMatrix4fv(this.line.u.uView, false, mv);
      gl.uniform4fv(this.line.u.uColour, [0.05, 0.05, 0.06, 1]);
      gl.bindVertexArray(this.mesh.lineVao);
      gl.drawArrays(gl.LINES, 0, this.mesh.lines);
    }
    // The whole polytope: blended over the section, hidden behind it, writing no depth.
    if (opts.whole && opts.whole !== 'off' && this.wires && !opts.mask) {
      const u = this.wire.u;
      gl.useProgram(this.wire.p);
      gl.uniformMatrix4fv(u.uProjection, false, proj);
      gl.uniformMatrix4fv(u.uView, false, mv);
      place(u);
      gl.uniform1i(u.uMode, opts.whole === 'persp' ? 1 : 0);
      gl.uniform1f(u.uEye, 3 * view.radius);
      gl.uniform1f(u.uFade, view.radius);
      gl.uniform1f(u.uSlab, opts.slab > 0 ? opts.slab : 0);
      gl.enable(gl.BLEND);
      gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
      gl.depthMask(false);
      gl.bindVertexArray(this.wires.vao);
      gl.drawArraysInstanced(gl.LINES, 0, 2, this.wires.count);
      gl.depthMask(true);
      gl.disable(gl.BLEND);
    }
    gl.bindVertexArray(null);
  }

  // An offscreen RGBA8 target of w x h pixels with a depth buffer.
  target(w, h) {
    const gl = this.gl;
    const fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    const colour = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, colour);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.RGBA8, w, h);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.RENDERBUFFER, colour);
    const depth = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, w, h);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return { fb, width: w, height: h, colour, depth };
  }

  // The covered pixels (any non-black) of a target, as a byte mask.
  coverage(t) {
    const gl = this.gl;
    const px = new Uint8Array(t.width * t.height * 4);
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.fb);
    gl.readPixels(0, 0, t.width, t.height, gl.RGBA, gl.UNSIGNED_BYTE, px);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    const mask = new Uint8Array(t.width * t.height);
    for (let i = 0; i < mask.length; ++i) mask[i] = px[4 * i] > 127 ? 1 : 0;
    return mask;
  }
}

// The tetrahedra of a `cw4d tetrahedralize MODEL -o NAME.bin` GPU buffer (NAME.json header,
// NAME.bin: per corner position vec4, normal vec4, uvw vec4 with the cell id in w; little
// endian float32) in the layout of the core's tets(). palette: Float32Array of r, g, b per cell.
export function tetsFromBuffer(header, bytes, palette) {
  if (header.format !== 'cw4d-tet-gpu' || header.version !== 1)
    throw new Error('not a cw4d-tet-gpu version 1 header');
  const n = header.tetrahedra, stride = header.stride_bytes;
  if (stride !== 48 || header.corners_per_tetrahedron !== 4 || bytes.byteLength !== n * 4 * stride)
    throw new Error(`buffer of ${bytes.byteLength} bytes does not hold ${n} tetrahedra of 4 x 48 bytes`);
  const f = new Float32Array(bytes.slice(0));
  if (new Uint8Array(new Float32Array([1]).buffer)[3] !== 0x3f) throw new Error('big-endian host');
  const corners = new Float32Array(16 * n), uvw = new Float32Array(12 * n);
  const normals = new Float32Array(4 * n), colours = new Float32Array(3 * n);
  const cells = new Float32Array(n);
  for (let t = 0; t < n; ++t) {
    for (let k = 0; k < 4; ++k) {
      const c = 12 * (4 * t + k);
      for (let j = 0; j < 4; ++j) corners[16 * t + 4 * k + j] = f[c + j];
      for (let j = 0; j < 3; ++j) uvw[12 * t + 3 * k + j] = f[c + 8 + j];
    }
    for (let j = 0; j < 4; ++j) normals[4 * t + j] = f[48 * t + 4 + j];
    const cell = f[48 * t + 11];
    cells[t] = cell;
    for (let j = 0; j < 3; ++j) colours[3 * t + j] = palette[3 * cell + j] ?? 0.8;
  }
  return { count: n, corners, uvw, normals, colours, cells, skippedCells: 0 };
}

// Intersection over union of two coverage masks.
export function iou(a, b) {
  let inter = 0, union = 0, na = 0, nb = 0;
  for (let i = 0; i < a.length; ++i) {
    inter += a[i] & b[i];
    union += a[i] | b[i];
    na += a[i];
    nb += b[i];
  }
  return { iou: union ? inter / union : 1, a: na, b: nb };
}
