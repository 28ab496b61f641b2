// GLSL ES 3.00 sources of the viewer: the CPU path draws the section's triangles as the
// WebAssembly core made them; the GPU path cuts every tetrahedron in the vertex shader.

// Shared shading: a head light on the polygon's normal, the cell colour, and a procedural 3D
// checker of the cell's UVW (each cell's own box mapping onto [0,1]^3) so the cells' texture
// coordinates are visible. uMask draws plain white for the coverage comparison.
export const FRAGMENT = `#version 300 es
precision highp float;
in vec3 vNormal;
in vec3 vColour;
in vec3 vUvw;
uniform bool uCellColours;
uniform bool uTexture;
uniform bool uMask;
uniform float uChecks;
out vec4 fragColour;
void main() {
  if (uMask) { fragColour = vec4(1.0); return; }
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 light = normalize(vec3(0.35, 0.45, 1.0));
  float diffuse = max(dot(n, light), 0.0);
  vec3 base = uCellColours ? vColour : vec3(0.78, 0.80, 0.84);
  if (uTexture) {
    // A sample within a thousandth of a check of a lattice plane counts as on its upper side,
    // as in the native renderer: a section lying exactly on a check boundary (the tesseract
    // cut at w = 0) takes one side everywhere instead of speckling with rounding noise.
    vec3 c = floor(vUvw * uChecks + 1e-3);
    float parity = mod(c.x + c.y + c.z, 2.0);
    base *= mix(0.62, 1.0, parity);
  }
  fragColour = vec4(base * (0.28 + 0.72 * diffuse), 1.0);
}`;

export const CPU_VERTEX = `#version 300 es
in vec3 aPosition;
in vec3 aNormal;
in vec3 aColour;
in vec3 aUvw;
uniform mat4 uProjection;
uniform mat4 uView;
out vec3 vNormal;
out vec3 vColour;
out vec3 vUvw;
void main() {
  vNormal = mat3(uView) * aNormal;
  vColour = aColour;
  vUvw = aUvw;
  gl_Position = uProjection * uView * vec4(aPosition, 1.0);
}`;

export const LINE_VERTEX = `#version 300 es
in vec3 aPosition;
uniform mat4 uProjection;
uniform mat4 uView;
void main() {
  vec4 p = uProjection * uView * vec4(aPosition, 1.0);
  p.z -= 0.0005 * p.w;  // drawn just in front of the polygons they bound
  gl_Position = p;
}`;

export const LINE_FRAGMENT = `#version 300 es
precision highp float;
uniform vec4 uColour;
out vec4 fragColour;
void main() { fragColour = uColour; }`;

// The GPU tetrahedral path: six vertices per tetrahedron (two triangles), drawn without
// instancing: vertex k belongs to tetrahedron k / 6, whose data it reads from a float texture
// (nine RGBA texels per tetrahedron, TETS_PER_ROW to a row: its four corners in model space,
// their UVW packed into three texels, the cell's outward normal, the cell's colour). Software
// GL (SwiftShader) runs instanced draws one instance at a time; one plain draw lets it shade
// vertices in wide batches. Every vertex of a tetrahedron takes the corners' signed distances
// to the plane n.x = d (a corner on the plane counts as positive, as in the CPU section); on
// one side, all six collapse to one point (zero area, nothing drawn). Otherwise it places the
// corners in the world (x = L p + t) and picks its point of the sign case: one corner apart ->
// the triangle on its three edges (the second triangle collapses to a point); two and two ->
// the quadrilateral on the four crossing edges. Points are written in the plane's basis
// (section coordinates, like the CPU path), and each triangle is wound so that its normal agrees
// with the cell's outward normal projected into the plane.
export const TETS_PER_ROW = 455;  // 9 texels each: 4095 texels per row
export const TET_VERTEX = `#version 300 es
precision highp float;
precision highp sampler2D;
uniform sampler2D uTets;
uniform mat4 uLinear;      // placement: x_world = uLinear * x_model + uTranslation
uniform vec4 uTranslation;
uniform vec4 uPlaneNormal;  // unit
uniform float uPlaneOffset;
uniform vec4 uModelNormal;  // the plane in model space: uLinear^T n . x = d - n . uTranslation
uniform float uModelOffset;
uniform mat4 uBasis;        // columns 0..2: the plane's orthonormal basis, column 3: zero
uniform mat4 uProjection;
uniform mat4 uView;
out vec3 vNormal;
out vec3 vColour;
out vec3 vUvw;

vec4 P[4];
vec3 T[4];
float S[4];

vec3 toPlane(vec4 x) { return (transpose(uBasis) * (x - uPlaneOffset * uPlaneNormal)).xyz; }

void crossing(int i, int j, out vec3 y, out vec3 uvw) {
  float w = S[i] / (S[i] - S[j]);
  y = toPlane(mix(P[i], P[j], w));
  uvw = mix(T[i], T[j], w);
}

void main() {
  int tet = gl_VertexID / 6;
  int v = gl_VertexID - 6 * tet;
  ivec2 at = ivec2(9 * (tet % ${TETS_PER_ROW}), tet / ${TETS_PER_ROW});
  vec4 c0 = texelFetch(uTets, at, 0);
  vec4 c1 = texelFetch(uTets, at + ivec2(1, 0), 0);
  vec4 c2 = texelFetch(uTets, at + ivec2(2, 0), 0);
  vec4 c3 = texelFetch(uTets, at + ivec2(3, 0), 0);
  // The signed distances with the plane taken into model space (four dot products, no
  // transform): most tetrahedra lie on one side and stop here, before any other work.
  S[0] = dot(uModelNormal, c0) - uModelOffset;
  S[1] = dot(uModelNormal, c1) - uModelOffset;
  S[2] = dot(uModelNormal, c2) - uModelOffset;
  S[3] = dot(uModelNormal, c3) - uModelOffset;
  int nUp = int(S[0] >= 0.0) + int(S[1] >= 0.0) + int(S[2] >= 0.0) + int(S[3] >= 0.0);
  if (nUp == 0 || nUp == 4) {
    vNormal = vec3(0.0, 0.0, 1.0);
    vColour = vec3(0.0);
    vUvw = vec3(0.0);
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // every vertex here: a zero-area triangle
    return;
  }
  P[0] = uLinear * c0 + uTranslation;
  P[1] = uLinear * c1 + uTranslation;
  P[2] = uLinear * c2 + uTranslation;
  P[3] = uLinear * c3 + uTranslation;
  vec4 t0 = texelFetch(uTets, at + ivec2(4, 0), 0);
  vec4 t1 = texelFetch(uTets, at + ivec2(5, 0), 0);
  vec4 t2 = texelFetch(uTets, at + ivec2(6, 0), 0);
  vec4 cellNormal4 = texelFetch(uTets, at + ivec2(7, 0), 0);
  vec3 colour = texelFetch(uTets, at + ivec2(8, 0), 0).rgb;
  T[0] = t0.xyz; T[1] = vec3(t0.w, t1.xy); T[2] = vec3(t1.zw, t2.x); T[3] = t2.yzw;
  int up[4];
  int down[4];
  nUp = 0;
  int nDown = 0;
  for (int i = 0; i < 4; ++i) {
    if (S[i] >= 0.0) up[nUp++] = i; else down[nDown++] = i;
  }
  vec3 q[4];
  vec3 t[4];
  if (nUp == 1 || nUp == 3) {
    int lone = nUp == 1 ? up[0] : down[0];
    int k = 0;
    for (int i = 0; i < 4; ++i)
      if (i != lone) { crossing(lone, i, q[k], t[k]); ++k; }
    q[3] = q[2]; t[3] = t[2];
  } else {
    crossing(up[0], down[0], q[0], t[0]);
    crossing(up[0], down[1], q[1], t[1]);
    crossing(up[1], down[1], q[2], t[2]);
    crossing(up[1], down[0], q[3], t[3]);
  }
  // The cell's normal (a direction: no translation) projected into the plane's basis.
  vec3 cellNormal = (transpose(uBasis) * (uLinear * cellNormal4)).xyz;
  vColour = colour;
  vNormal = mat3(uView) * normalize(cellNormal);
  // Triangles (0,1,2) and (0,2,3); for a triangle case the second one is (q0,q2,q2).
  int order[6] = int[6](0, 1, 2, 0, 2, 3);
  // The winding from the diagonals' cross product (the quadrilateral's area vector, and the
  // triangle's when q3 = q2), which stays right when a corner on the plane makes two of the
  // points one (q0 = q1 through a vertex on the plane): the first triangle's edges would not.
  bool flip = dot(cross(q[2] - q[0], q[3] - q[1]), cellNormal) < 0.0;
  if (flip) v = v == 1 ? 2 : (v == 2 ? 1 : (v == 4 ? 5 : (v == 5 ? 4 : v)));
  int c = order[v];
  vUvw = t[c];
  gl_Position = uProjection * uView * vec4(q[c], 1.0);
}`;


// The whole polytope around its section: every edge of the placed model, one instance per edge
// (its two model-space ends), drawn in the section's 3D coordinates. A point x of the world
// has the signed distance s = n.x - d to the hyperplane and the plane coordinates
// y = B^T (x - d n); "shadow" draws it at y (the projection along the normal, as 4D Golf shows
// what lies off the slice), "perspective" at y e / (e - s), seen from an eye on the normal at
// distance e (nearer parts larger). Either way the section (s = 0) sits exactly inside the
// wireframe. Colours: warm on the positive side, cool on the negative side, bright where an
// edge crosses the hyperplane, faded with the distance |s|; a slab |s| <= uSlab (when > 0)
// keeps only the parts near the hyperplane (a thick slice).
export const WIRE_VERTEX = `#version 300 es
in vec4 aP0;
in vec4 aP1;
uniform mat4 uLinear;
uniform vec4 uTranslation;
uniform vec4 uPlaneNormal;
uniform float uPlaneOffset;
uniform mat4 uBasis;
uniform mat4 uProjection;
uniform mat4 uView;
uniform int uMode;     // 0: shadow, 1: 4D perspective
uniform float uEye;    // perspective: the eye's distance from the hyperplane
out float vS;
out float vCrossing;
void main() {
  vec4 x0 = uLinear * aP0 + uTranslation;
  vec4 x1 = uLinear * aP1 + uTranslation;
  float s0 = dot(uPlaneNormal, x0) - uPlaneOffset;
  float s1 = dot(uPlaneNormal, x1) - uPlaneOffset;
  vec4 x = gl_VertexID == 0 ? x0 : x1;
  float s = gl_VertexID == 0 ? s0 : s1;
  vec3 y = (transpose(uBasis) * (x - uPlaneOffset * uPlaneNormal)).xyz;
  if (uMode == 1) y *= uEye / max(uEye - s, 1e-3 * uEye);
  vS = s;
  vCrossing = (s0 < 0.0) != (s1 < 0.0) ? 1.0 : 0.0;
  vec4 p = uProjection * uView * vec4(y, 1.0);
  p.z -= 0.0002 * p.w;
  gl_Position = p;
}`;

export const WIRE_FRAGMENT = `#version 300 es
precision highp float;
in float vS;
in float vCrossing;
uniform float uFade;   // the distance over which an edge fades to its faintest
uniform float uSlab;   // > 0: only |s| <= uSlab is drawn
out vec4 fragColour;
void main() {
  float a = abs(vS);
  if (uSlab > 0.0 && a > uSlab) discard;
  vec3 warm = vec3(1.0, 0.62, 0.32), cool = vec3(0.42, 0.66, 1.0);
  vec3 colour = vS >= 0.0 ? warm : cool;
  float alpha = mix(0.85, 0.12, clamp(a / uFade, 0.0, 1.0));
  if (vCrossing > 0.5) {
    colour = mix(vec3(1.0, 0.95, 0.6), colour, clamp(a / (0.25 * uFade), 0.0, 1.0));
    alpha = max(alpha, 0.9 - 0.6 * clamp(a / uFade, 0.0, 1.0));
  }
  fragColour = vec4(colour * alpha, alpha);
}`;
