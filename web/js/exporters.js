// The section on screen as a file: Wavefront OBJ (text), binary STL and binary glTF 2.0 (GLB),
// written from the arrays the WebAssembly core returns for a slice (corners with positions,
// normals and colours; three corner ids per triangle), in the section's 3D coordinates.

const exportFmt = (x) => (Math.abs(x) < 1e-12 ? '0' : Number(x.toPrecision(9)).toString());

// OBJ: one vertex and normal per corner, faces as v//vn triples (ids from 1).
export function sectionObj(s, title) {
  const lines = [`# ${title}`, `# ${s.indices.length / 3} triangles, written by the cw4d viewer`];
  for (let i = 0; i < s.positions.length; i += 3)
    lines.push(`v ${exportFmt(s.positions[i])} ${exportFmt(s.positions[i + 1])} ${exportFmt(s.positions[i + 2])}`);
  for (let i = 0; i < s.normals.length; i += 3)
    lines.push(`vn ${exportFmt(s.normals[i])} ${exportFmt(s.normals[i + 1])} ${exportFmt(s.normals[i + 2])}`);
  for (let t = 0; t < s.indices.length; t += 3) {
    const [a, b, c] = [s.indices[t] + 1, s.indices[t + 1] + 1, s.indices[t + 2] + 1];
    lines.push(`f ${a}//${a} ${b}//${b} ${c}//${c}`);
  }
  return new Blob([lines.join('\n') + '\n'], { type: 'model/obj' });
}

// Binary STL: an 80-byte header, the triangle count, then per triangle its unit normal (from
// the corners' winding) and three corners, little endian float32.
export function sectionStl(s) {
  const n = s.indices.length / 3;
  const bytes = new ArrayBuffer(84 + 50 * n);
  const view = new DataView(bytes);
  const header = 'cw4d viewer section';
  for (let i = 0; i < header.length; ++i) view.setUint8(i, header.charCodeAt(i));
  view.setUint32(80, n, true);
  const p = (k, j) => s.positions[3 * s.indices[k] + j];
  for (let t = 0; t < n; ++t) {
    const at = 84 + 50 * t;
    const e1 = [0, 1, 2].map((j) => p(3 * t + 1, j) - p(3 * t, j));
    const e2 = [0, 1, 2].map((j) => p(3 * t + 2, j) - p(3 * t, j));
    const c = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
      e1[0] * e2[1] - e1[1] * e2[0]];
    const len = Math.hypot(...c) || 1;
    for (let j = 0; j < 3; ++j) view.setFloat32(at + 4 * j, c[j] / len, true);
    for (let k = 0; k < 3; ++k)
      for (let j = 0; j < 3; ++j) view.setFloat32(at + 12 + 12 * k + 4 * j, p(3 * t + k, j), true);
    view.setUint16(at + 48, 0, true);
  }
  return new Blob([bytes], { type: 'model/stl' });
}

// GLB: one mesh of one primitive (POSITION, NORMAL, COLOR_0, uint32 indices) in one buffer,
// chunks padded to four bytes (the JSON with spaces, the binary with zeros).
export function sectionGlb(s, title) {
  const parts = [s.positions, s.normals, s.colours, s.indices];
  let offset = 0;
  const views = parts.map((a) => {
    const v = { buffer: 0, byteOffset: offset, byteLength: a.byteLength };
    offset += a.byteLength;
    return v;
  });
  views[3].target = 34963;  // ELEMENT_ARRAY_BUFFER
  for (let i = 0; i < 3; ++i) views[i].target = 34962;  // ARRAY_BUFFER
  const count = s.positions.length / 3;
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < s.positions.length; ++i) {
    min[i % 3] = Math.min(min[i % 3], s.positions[i]);
    max[i % 3] = Math.max(max[i % 3], s.positions[i]);
  }
  // Unit normals as float32 (the validator checks their length).
  const normals = new Float32Array(s.normals.length);
  for (let i = 0; i < s.normals.length; i += 3) {
    const l = Math.hypot(s.normals[i], s.normals[i + 1], s.normals[i + 2]) || 1;
    for (let j = 0; j < 3; ++j) normals[i + j] = l > 0 ? s.normals[i + j] / l : 0;
  }
  parts[1] = normals;
  const gltf = {
    asset: { version: '2.0', generator: 'cw4d viewer' },
    scene: 0, scenes: [{ nodes: [0] }], nodes: [{ mesh: 0, name: title }],
    meshes: [{ name: title, primitives: [{ attributes: { POSITION: 0, NORMAL: 1, COLOR_0: 2 },
      indices: 3, material: 0 }] }],
    materials: [{ pbrMetallicRoughness: { baseColorFactor: [1, 1, 1, 1], metallicFactor: 0,
      roughnessFactor: 0.8 }, doubleSided: true }],
    buffers: [{ byteLength: offset }],
    bufferViews: views,
    accessors: [
      { bufferView: 0, componentType: 5126, count, type: 'VEC3', min, max },
      { bufferView: 1, componentType: 5126, count, type: 'VEC3' },
      { bufferView: 2, componentType: 5126, count, type: 'VEC3' },
      { bufferView: 3, componentType: 5125, count: s.indices.length, type: 'SCALAR' },
    ],
  };
  let json = new TextEncoder().encode(JSON.stringify(gltf));
  const jsonPad = (4 - (json.length % 4)) % 4;
  const binPad = (4 - (offset % 4)) % 4;
  const total = 12 + 8 + json.length + jsonPad + 8 + offset + binPad;
  const out = new Uint8Array(total);
  const view = new DataView(out.buffer);
  view.setUint32(0, 0x46546c67, true);  // 'glTF'
  view.setUint32(4, 2, true);
  view.setUint32(8, total, true);
  view.setUint32(12, json.length + jsonPad, true);
  view.setUint32(16, 0x4e4f534a, true);  // 'JSON'
  out.set(json, 20);
  out.fill(0x20, 20 + json.length, 20 + json.length + jsonPad);
  let at = 20 + json.length + jsonPad;
  view.setUint32(at, offset + binPad, true);
  view.setUint32(at + 4, 0x004e4942, true);  // 'BIN\0'
  at += 8;
  for (const a of parts) {
    out.set(new Uint8Array(a.buffer, a.byteOffset, a.byteLength), at);
    at += a.byteLength;
  }
  return new Blob([out], { type: 'model/gltf-binary' });
}

// Saves a Blob under a file name through a temporary link (the browser's download).
export function saveBlob(blob, name) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}
