#include "cw4d/tetrahedralize/tet_slice.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/section/provenance.hpp"

namespace cw4d {

namespace {

constexpr TetCutCase make_case(int mask) {
  TetCutCase c{0, {}};
  int pos[4] = {}, neg[4] = {};
  int np = 0, nn = 0;
  for (int k = 0; k < 4; ++k) {
    if (mask & (1 << k))
      pos[np++] = k;
    else
      neg[nn++] = k;
  }
  if (np == 1 || nn == 1) {
    const int lone = np == 1 ? pos[0] : neg[0];
    const int* others = np == 1 ? neg : pos;
    c.count = 3;
    for (int i = 0; i < 3; ++i) c.edges[static_cast<std::size_t>(i)] = {lone, others[i]};
  } else if (np == 2) {
    // Around the quad: each corner shares one end with the next.
    c.count = 4;
    c.edges[0] = {pos[0], neg[0]};
    c.edges[1] = {pos[0], neg[1]};
    c.edges[2] = {pos[1], neg[1]};
    c.edges[3] = {pos[1], neg[0]};
  }
  return c;
}

constexpr std::array<TetCutCase, 16> make_table() {
  std::array<TetCutCase, 16> t{};
  for (int m = 0; m < 16; ++m) t[static_cast<std::size_t>(m)] = make_case(m);
  return t;
}

}  // namespace

const std::array<TetCutCase, 16> kTetCutTable = make_table();

namespace tet_slice_detail {
// A cut tetrahedron as the triangle pass reads it.
struct CutRecord {
  std::uint32_t cut;    // (t << 4) | mask
  std::uint32_t first;  // its first output triangle
  std::uint32_t cell;
  std::uint32_t i;  // its position in the cut list (corner slots 4 i .. 4 i + 3)
};

}  // namespace tet_slice_detail

struct TetSlicer::Scratch {
  std::vector<double> s;
  std::vector<Side> side;
  std::vector<std::uint8_t> up;    // 4 per vertex: byte k is 1 << k when it is positive, else 0
  std::vector<std::uint32_t> cut;  // (t << 4) | mask of each cut tetrahedron
  std::vector<std::uint32_t> corner_vid;  // 4 per cut tetrahedron: vertex of each cycle corner
  std::vector<std::uint32_t> crossing;    // the edge of each output vertex
  std::vector<double> u;                  // the parameter of each output vertex
  std::vector<std::uint32_t> edge_owner;  // the last corner slot naming the edge
  std::vector<std::uint32_t> slot_edge;   // the edge of each corner slot
  std::vector<std::uint32_t> cell_owner;  // the last cut tetrahedron of the cell
  std::vector<std::uint32_t> cut_cells;   // each cut cell once
  std::vector<tet_slice_detail::CutRecord> list3;  // the cut tetrahedra giving one triangle
  std::vector<tet_slice_detail::CutRecord> list4;  // those giving a quad
  std::vector<double> cell_n3;
  std::vector<double> cell_y;  // the projected normals before scaling, with their squared norms
  // An edge index for meshes whose tets were changed after tetrahedralize.
  TetMesh edge_mesh;
  // The general loop's soup, welded for the indexed form.
  TetSection soup;
  std::vector<Eigen::Vector3d> pos_buf, nrm_buf, uvw_buf, all_pos, all_nrm, all_uvw;
  std::vector<TetCutPoint> cut_buf;
  // The soup's cut: sides as bits, the cut tetrahedra, each cell's projected normal with the
  // stamp of the slice that computed it.
  std::vector<std::uint8_t> soup_up;
  std::vector<std::uint32_t> soup_cut;
  std::vector<std::uint32_t> cell_stamp;
  std::vector<double> soup_cell_n3;
  std::uint32_t stamp = 0;
  // The last placement's linear map and what is derived from it alone (A^{-T}, det A < 0):
  // slices under one placement compute them once.
  bool have_lin = false;
  Eigen::Matrix4d last_lin, last_normal_map;
  bool last_flip = false;
};

double TetSection::volume() const {
  double v = 0.0;
  for (std::size_t i = 0; i < triangle_count(); ++i) {
    const auto c = static_cast<Eigen::Index>(3 * i);
    v += positions.col(c).dot(positions.col(c + 1).cross(positions.col(c + 2)));
  }
  return v / 6.0;
}

double TetSection::area() const {
  double a = 0.0;
  for (std::size_t i = 0; i < triangle_count(); ++i) {
    const auto c = static_cast<Eigen::Index>(3 * i);
    a += (positions.col(c + 1) - positions.col(c))
             .cross(positions.col(c + 2) - positions.col(c))
             .norm();
  }
  return a / 2.0;
}

namespace {

// Crossing edge e of a sign case: its corners (ka, kb) in the tetrahedron and their vertices
// (a, b), ordered so that a < b, which makes the crossing point the same from every tetrahedron
// sharing the edge.
struct CrossingEdge {
  int ka, kb;
  std::uint32_t a, b;
};
inline CrossingEdge crossing_edge(const TetCutCase& cc, int e,
                                  const std::array<std::uint32_t, 4>& tv) {
  const auto& k = cc.edges[static_cast<std::size_t>(e)];
  CrossingEdge c{k[0], k[1], tv[static_cast<std::size_t>(k[0])],
                 tv[static_cast<std::size_t>(k[1])]};
  if (c.a > c.b) {
    std::swap(c.a, c.b);
    std::swap(c.ka, c.kb);
  }
  return c;
}

// The position of a sign case's cut edges in TetMesh::kTetEdgeCorners (0..5), in cycle order;
// a triangle repeats its third edge in the fourth slot.
constexpr int local_edge(int a, int b) {
  const int lo = a < b ? a : b, hi = a < b ? b : a;
  for (int k = 0; k < 6; ++k)
    if (TetMesh::kTetEdgeCorners[static_cast<std::size_t>(k)][0] == lo &&
        TetMesh::kTetEdgeCorners[static_cast<std::size_t>(k)][1] == hi)
      return k;
  return -1;
}

// Whether the table's corner cycle of a sign case has to be reversed to be outward, for a
// tetrahedron positively oriented with its cell's normal N (det(N, p1 - p0, p2 - p0, p3 - p0) > 0)
// and a frame basis B with (B, n) right-handed. In the cell's 3-space, oriented by N first, the
// outward polygon (m . projected N > 0, m its frame-space normal) is the one with
// det(N, e1, e2, g) > 0, e1 = c1 - c0, e2 = c2 - c0, g the gradient of n.x - d along the cell:
// (m . N_H > 0 iff det(n, e1, e2, N) det(n, B) > 0, det(n, B) = -1, and
// det(n, e1, e2, N) = -det(N, e1, e2, g)). The sign only depends on which corners are positive
// while no corner is on the plane, so it is evaluated once on a model tetrahedron, the corners
// p0 = 0, p1 = e_y, p2 = e_x, p3 = e_z with N = e_w (det(e_w, v1, v2, v3) = -det3(v1, v2, v3) = 1),
// under the affine function that is +1 at positive and -1 at negative corners (cut at the edge
// midpoints): there det(N, e1, e2, g) = -det3(e1, e2, g).
constexpr bool reverse_case(int mask) {
  const TetCutCase c = make_case(mask);
  if (c.count == 0) return false;
  const double P[4][3] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
  double sv[4] = {};
  for (int k = 0; k < 4; ++k) sv[k] = (mask >> k) & 1 ? 1.0 : -1.0;
  const double g[3] = {sv[2] - sv[0], sv[1] - sv[0], sv[3] - sv[0]};
  double cpt[3][3] = {};
  for (int e = 0; e < 3; ++e)
    for (int r = 0; r < 3; ++r)
      cpt[e][r] = 0.5 * (P[c.edges[static_cast<std::size_t>(e)][0]][r] +
                         P[c.edges[static_cast<std::size_t>(e)][1]][r]);
  const double e1[3] = {cpt[1][0] - cpt[0][0], cpt[1][1] - cpt[0][1], cpt[1][2] - cpt[0][2]};
  const double e2[3] = {cpt[2][0] - cpt[0][0], cpt[2][1] - cpt[0][1], cpt[2][2] - cpt[0][2]};
  const double m[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
  const double det3 = m[0] * g[0] + m[1] * g[1] + m[2] * g[2];
  return !(-det3 > 0.0);
}

// What the indexed cut reads per sign case: the cut edges as local edge ids in outward cycle
// order (the table's cycle, reversed after its first corner where reverse_case says so, and
// again for a placement that reverses orientation), the corner pairs of those edges and the
// triangle count. A triangle repeats its third corner in the fourth slot.
struct IndexedCase {
  std::uint8_t local[4];
  std::uint8_t ka[4], kb[4];
  std::uint8_t tris;
  std::uint8_t swap;  // a turned quad writes its fan's second triangle first (the soup's order)
};
constexpr std::array<IndexedCase, 16> make_indexed_table(bool flip) {
  std::array<IndexedCase, 16> t{};
  for (int m = 0; m < 16; ++m) {
    const TetCutCase c = make_case(m);
    IndexedCase& ic = t[static_cast<std::size_t>(m)];
    ic.tris = static_cast<std::uint8_t>(c.count == 4 ? 2 : c.count == 3 ? 1 : 0);
    const bool reverse = reverse_case(m) != flip;
    ic.swap = reverse && c.count == 4 ? 1 : 0;
    for (int e = 0; e < 4; ++e) {
      int src = 0;
      if (c.count > 0) {
        const int slot = e < c.count ? e : c.count - 1;
        src = reverse && slot > 0 ? c.count - slot : slot;
      }
      const auto& k = c.edges[static_cast<std::size_t>(src)];
      ic.local[e] = static_cast<std::uint8_t>(c.count == 0 ? 0 : local_edge(k[0], k[1]));
      ic.ka[e] = static_cast<std::uint8_t>(k[0]);
      ic.kb[e] = static_cast<std::uint8_t>(k[1]);
    }
  }
  return t;
}
constexpr std::array<std::array<IndexedCase, 16>, 2> kIndexedTable = {make_indexed_table(false),
                                                                      make_indexed_table(true)};

// Everything a slice needs before the cut: the plane's values at the mesh vertices, their sides,
// the section frame and the maps into it.
struct Prepared {
  bool any_pos = false, any_neg = false, any_on = false;
  bool flip = false;  // the placement reverses orientation (det A < 0)
  Eigen::Matrix4d lin;
  Eigen::Matrix4d normal_map;
  Eigen::Matrix<double, 3, 4> bt;
  Eigen::Matrix<double, 3, 4> W;   // bt * lin: model point -> section coordinates (+ offset)
  Eigen::Matrix<double, 3, 4> NB;  // bt * normal_map: model normal -> section direction
  Eigen::Vector3d offset;
};

using Scratch = TetSlicer::Scratch;
using tet_slice_detail::CutRecord;

// Scratch arrays only grow (their contents are written before they are read).
template <class T>
void grow(std::vector<T>& v, std::size_t n) {
  if (v.size() < n) v.resize(n);
}

void set_frame(HyperplaneFrame& f, const Hyperplane& p) {
  f.plane.normal = p.normal;
  f.plane.offset = p.offset;
  if (f.basis.rows() != 4 || f.basis.cols() != 3) f.basis.resize(4, 3);
  hyperplane_basis(p.normal.data(), 4, f.basis.data());
}

// The four bytes 1, 2, 4, 8 in memory order, as one word (the up bytes of a positive vertex).
constexpr std::uint32_t kUpBytes =
    std::endian::native == std::endian::little ? 0x08040201u : 0x01020408u;

Prepared prepare(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& xf,
                 const HyperplaneFrame& frame, Scratch& sc) {
  if (plane.dim() != 4)
    throw InputError("slice_tets: hyperplane in R^" + std::to_string(plane.dim()) + ", not R^4");
  if (xf.dim() != 4)
    throw InputError("slice_tets: transform of R^" + std::to_string(xf.dim()) + ", not R^4");
  Prepared pr;
  // The plane in model space: (A^T n).x = d - n.t (as cw4d::section does).
  pr.lin = xf.linear();
  const Eigen::Vector4d n4 = plane.normal;
  const Eigen::Vector4d t4 = xf.translation();
  const Eigen::Vector4d nm = pr.lin.transpose() * n4;
  const double dm = plane.offset - n4.dot(t4);
  const auto nv = static_cast<std::size_t>(mesh.positions.cols());
  sc.s.resize(nv);
  sc.side.resize(nv);
  const double* P = mesh.positions.data();
  double max_norm2 = 0.0;
  for (std::size_t v = 0; v < nv; ++v) {
    const Eigen::Map<const Eigen::Vector4d> x(P + 4 * v);
    sc.s[v] = nm.dot(x) - dm;
    max_norm2 = std::max(max_norm2, x.squaredNorm());
  }
  const double tolerance = on_plane_tolerance(nm.norm(), std::sqrt(max_norm2), dm);
  // classify_side's decisions as arithmetic (the sides of a generic plane are not predictable).
  unsigned any_neg = 0, any_pos = 0, any_on = 0;
  sc.up.resize(4 * nv);
  const double* sv = sc.s.data();
  Side* __restrict sd = sc.side.data();
  std::uint8_t* __restrict up = sc.up.data();
  for (std::size_t v = 0; v < nv; ++v) {
    const unsigned pos = sv[v] > tolerance, neg = sv[v] < -tolerance;
    assert(static_cast<int>(classify_side(sv[v], tolerance)) ==
           static_cast<int>(pos) - static_cast<int>(neg));
    sd[v] = static_cast<Side>(static_cast<int>(pos) - static_cast<int>(neg));
    // (byte k: the positive bit shifted to corner k's place in a sign mask; one store)
    const std::uint32_t word = pos * kUpBytes;
    std::memcpy(up + 4 * v, &word, sizeof word);
    any_neg |= neg;
    any_pos |= pos;
    any_on |= (pos | neg) ^ 1u;
  }
  pr.any_neg = any_neg != 0, pr.any_pos = any_pos != 0, pr.any_on = any_on != 0;
  // World-space frame: y = B^T (A x + t - origin); normals transform by A^{-T}.
  // (Compared bit for bit: the same inputs give the same inverse and determinant sign.)
  if (!sc.have_lin || std::memcmp(sc.last_lin.data(), pr.lin.data(), sizeof(double) * 16) != 0) {
    sc.last_lin = pr.lin;
    sc.last_normal_map = pr.lin.inverse().transpose();
    sc.last_flip = pr.lin.determinant() < 0.0;
    sc.have_lin = true;
  }
  pr.normal_map = sc.last_normal_map;
  pr.flip = sc.last_flip;
  pr.bt = frame.basis.transpose();
  pr.offset = pr.bt * (t4 - plane.offset * n4);
  pr.W = pr.bt * pr.lin;
  pr.NB = pr.bt * pr.normal_map;
  return pr;
}

// The section-frame position of the crossing at parameter u of the model edge from xa to xb
// (4 doubles each): y = W ((1 - u) xa + u xb) + offset. The one formula of every crossing, in
// the indexed cut and the soup alike, so both give the same bits.
class CrossingProjector {
 public:
  CrossingProjector(const Eigen::Matrix<double, 3, 4>& W, const Eigen::Vector3d& offset)
      : W_(W), offset_(offset) {
#if defined(__SSE2__)
    for (int c = 0; c < 4; ++c) w01_[c] = _mm_set_pd(W(1, c), W(0, c));
    off01_ = _mm_set_pd(offset[1], offset[0]);
#endif
  }
  void operator()(const double* xa, const double* xb, double u, double* y) const {
#if defined(__SSE2__)
    // Rows 0 and 1 of the projection as lane pairs, row 2 alone: per lane the same operations
    // in the same order as the scalar form below.
    const __m128d uu = _mm_set1_pd(u), om = _mm_set1_pd(1.0 - u);
    const __m128d x01 =
        _mm_add_pd(_mm_mul_pd(om, _mm_loadu_pd(xa)), _mm_mul_pd(uu, _mm_loadu_pd(xb)));
    const __m128d x23 =
        _mm_add_pd(_mm_mul_pd(om, _mm_loadu_pd(xa + 2)), _mm_mul_pd(uu, _mm_loadu_pd(xb + 2)));
    const __m128d x0 = _mm_unpacklo_pd(x01, x01), x1 = _mm_unpackhi_pd(x01, x01);
    const __m128d x2 = _mm_unpacklo_pd(x23, x23), x3 = _mm_unpackhi_pd(x23, x23);
    __m128d y01 = _mm_add_pd(_mm_mul_pd(w01_[0], x0), _mm_mul_pd(w01_[1], x1));
    y01 = _mm_add_pd(y01, _mm_mul_pd(w01_[2], x2));
    y01 = _mm_add_pd(y01, _mm_mul_pd(w01_[3], x3));
    _mm_storeu_pd(y, _mm_add_pd(y01, off01_));
    y[2] = W_(2, 0) * _mm_cvtsd_f64(x0) + W_(2, 1) * _mm_cvtsd_f64(x1) +
           W_(2, 2) * _mm_cvtsd_f64(x2) + W_(2, 3) * _mm_cvtsd_f64(x3) + offset_[2];
#else
    double x[4];
    for (int r = 0; r < 4; ++r) x[r] = (1.0 - u) * xa[r] + u * xb[r];
    for (int r = 0; r < 3; ++r)
      y[r] = W_(r, 0) * x[0] + W_(r, 1) * x[1] + W_(r, 2) * x[2] + W_(r, 3) * x[3] + offset_[r];
#endif
  }

 private:
  const Eigen::Matrix<double, 3, 4>& W_;
  const Eigen::Vector3d& offset_;
#if defined(__SSE2__)
  __m128d w01_[4], off01_;
#endif
};

// A cell's outward normal n (4 doubles) as a unit direction of the section frame: y = NB n
// scaled by 1 / |y| (0 when y is 0). The one formula of the indexed cut and the soup.
inline double projected_normal(const Eigen::Matrix<double, 3, 4>& NB, const double* n, double* y) {
  for (int r = 0; r < 3; ++r)
    y[r] = NB(r, 0) * n[0] + NB(r, 1) * n[1] + NB(r, 2) * n[2] + NB(r, 3) * n[3];
  return y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
}

// The indexed cut when no vertex is on the plane (every crossing is interior to its edge, no
// triangle degenerates, no face lies in the plane). One pass over the corners' side bits lists
// the cut tetrahedra (all on one side: skipped at once; for cells of many tetrahedra, a block
// whose vertices are all on one side is skipped whole) and counts their triangles; three short
// passes over the cut tetrahedra's corner slots give each crossing edge one output vertex
// (claims, numbering, look-up: no branch, no store-to-load chain); one pass over the vertices
// computes each crossing once (one division per crossing edge, not per tetrahedron around it);
// one pass writes the triangles through the 16-case table, turned by the table's combinatorial
// orientation (the tetrahedra are positively oriented with their cell's normal, so no geometric
// test is needed).
// False (nothing written that is kept) when the index cannot be the tets' (an edge id, an edge's
// end, a block's range or a block vertex out of range): checks that keep a stale index from
// reading or writing out of bounds.
// An index whose entries are in range but stale (tets edited in place with their count kept) is
// the caller's error (documented at slice_tets).
bool cut_indexed(const TetMesh& mesh, const TetMesh& index, const Prepared& pr, Scratch& sc,
                 bool want_uvw, TetSliceMesh& out) {
  const std::array<std::uint32_t, 2>* edges = index.edges.data();
  const std::size_t ne = index.edges.size();
  const std::array<std::uint32_t, 6>* tet_edges = index.tet_edges.data();
  const IndexedCase* table = kIndexedTable[pr.flip ? 1 : 0].data();
  const std::size_t T = mesh.size();
  grow(sc.cut, T);
  const std::uint8_t* up = sc.up.data();
  std::uint32_t* __restrict cut = sc.cut.data();
  std::size_t ncut = 0;
  const std::array<std::uint32_t, 4>* tets = mesh.tets.data();
  // 1 for the masks of cut tetrahedra (0 and 15: all on one side).
  static constexpr std::uint8_t kCut[16] = {0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0};
  auto test_tets = [&](std::size_t t0, std::size_t t1) {
    for (std::size_t t = t0; t < t1; ++t) {
      const auto& tv = tets[t];
      const unsigned mask = up[4 * std::size_t{tv[0]}] | up[4 * std::size_t{tv[1]} + 1] |
                            up[4 * std::size_t{tv[2]} + 2] | up[4 * std::size_t{tv[3]} + 3];
      cut[ncut] = static_cast<std::uint32_t>(t << 4) | mask;
      ncut += kCut[mask];
    }
  };
  const auto nvtx = static_cast<std::uint32_t>(sc.up.size() / 4);  // the mesh's vertices
  const std::size_t nblocks = index.block_first.size() - 1;
  if (4 * nblocks <= T) {
    // Blocks of four or more tetrahedra on average (cells of many tetrahedra): a block whose
    // distinct vertices are all on one side is skipped whole.
    const std::uint32_t* bf = index.block_first.data();
    const std::uint32_t* bvf = index.block_vertex_first.data();
    const std::uint32_t* bv = index.block_vertices.data();
    const std::size_t nbv = index.block_vertices.size();
    for (std::size_t b = 0; b < nblocks; ++b) {
      unsigned any = 0, all = 1;
      // (Blocks in order within the tets: disjoint, so that no more than T are listed.)
      if (bf[b] > bf[b + 1] || bf[b + 1] > T) return false;
      if (bvf[b] > bvf[b + 1] || bvf[b + 1] > nbv) return false;
      for (std::uint32_t j = bvf[b]; j < bvf[b + 1]; ++j) {
        if (bv[j] >= nvtx) return false;
        any |= up[4 * std::size_t{bv[j]}];
        all &= up[4 * std::size_t{bv[j]}];
      }
      if (any & ~all) test_tets(bf[b], bf[b + 1]);
    }
  } else {
    test_tets(0, T);
  }
  if (ncut == 0) {
    out.clear();
    return true;
  }
  if (ne == 0) return false;
  // Output vertices, one per crossing edge, without a load that waits for a store of the
  // previous tetrahedron (neighbours share edges, and a first-sight test would chain them through
  // store forwarding): every corner slot j = 4 i + k claims its edge (owner[e] = j, the last
  // claim stays), the owning slots number the vertices in slot order, and every slot reads its
  // owner's number. The same for the cut cells (their normals are computed together below).
  // (Scratch only grows: no value-initialisation per slice.)
  grow(sc.edge_owner, ne + 1);
  grow(sc.cell_owner, mesh.cell_count());
  grow(sc.cell_n3, 3 * mesh.cell_count());
  const std::size_t nslot = 4 * ncut;
  grow(sc.slot_edge, nslot);
  grow(sc.corner_vid, nslot);
  grow(sc.crossing, nslot);
  grow(sc.cut_cells, ncut);
  grow(sc.list3, ncut);
  grow(sc.list4, ncut);
  std::uint32_t* __restrict owner = sc.edge_owner.data();
  std::uint32_t* __restrict cell_owner = sc.cell_owner.data();
  std::uint32_t* __restrict slot_edge = sc.slot_edge.data();
  std::uint32_t* __restrict corner_vid = sc.corner_vid.data();
  std::uint32_t* __restrict crossing = sc.crossing.data();
  std::uint32_t* __restrict cut_cells = sc.cut_cells.data();
  CutRecord* __restrict list3 = sc.list3.data();
  CutRecord* __restrict list4 = sc.list4.data();
  const std::uint32_t* tet_cell = mesh.tet_cell.data();
  // Per cut tetrahedron: its cell's claim, a record of what its triangles read, in the list of
  // its case (one triangle or a quad), and the claims of its corner slots.
  std::size_t n3 = 0, n4 = 0;
  std::uint32_t first = 0;
  // An edge id out of range claims the spare entry owner[ne] (no branch per slot): it is
  // noticed after the pass by that entry having lost its mark.
  owner[ne] = ~0u;
  for (std::size_t i = 0; i < ncut; ++i) {
    const std::uint32_t t = cut[i] >> 4;
    const IndexedCase& ic = table[cut[i] & 15u];
    const unsigned tris = ic.tris;
    const std::uint32_t cell = tet_cell[t];
    cell_owner[cell] = static_cast<std::uint32_t>(i);
    const CutRecord rec{cut[i], first, cell, static_cast<std::uint32_t>(i)};
    list3[n3] = rec;
    list4[n4] = rec;
    first += tris;
    n3 += tris == 1;
    n4 += tris == 2;
    const auto& te = tet_edges[t];
    for (std::size_t k = 0; k < 4; ++k) {
      const std::uint32_t e = std::min(te[ic.local[k]], static_cast<std::uint32_t>(ne));
      slot_edge[4 * i + k] = e;
      owner[e] = static_cast<std::uint32_t>(4 * i + k);
    }
  }
  const std::size_t tris = first;
  if (owner[ne] != ~0u) return false;  // an edge id out of range: index a copy
  out.triangles.resize(3 * tris);
  out.normals.resize(3 * tris);
  out.uvw.resize(want_uvw ? 9 * tris : 0);
  out.tet.resize(tris);
  out.cell.resize(tris);
  // Numbering and look-up in one pass, backwards: the owning (last) slot of an edge comes first
  // and numbers it from the end (vertex nvert - 1 - r for the r-th owner met, so vertices are in
  // the owners' slot order); every other slot copies its owner's number. No branch.
  std::uint32_t nvert = 0;
  std::size_t ncells = 0;
  for (std::size_t j = nslot; j-- > 0;) {
    const std::uint32_t e = slot_edge[j];
    const std::uint32_t o = owner[e];
    const std::uint32_t own = 0u - static_cast<std::uint32_t>(o == j);
    const std::uint32_t r = (corner_vid[o] & ~own) | (nvert & own);
    corner_vid[j] = r;
    crossing[nvert] = e;
    nvert -= own;  // + 1 where owned
  }
  for (std::size_t i = 0; i < ncut; ++i) {
    const std::uint32_t c = tet_cell[cut[i] >> 4];
    cut_cells[ncells] = c;
    ncells += cell_owner[c] == i;
  }
  // The crossings, each once.
  out.positions.resize(3 * std::size_t{nvert});
  out.vertex_source.resize(nvert);
  grow(sc.u, nvert);
  const double* P = mesh.positions.data();
  const double* s = sc.s.data();
  double* __restrict U = sc.u.data();
  double* __restrict out_pos = out.positions.data();
  TetCutPoint* __restrict out_src = out.vertex_source.data();
  const CrossingProjector project(pr.W, pr.offset);
  for (std::uint32_t v = 0; v < nvert; ++v) {
    const auto& ab = edges[crossing[nvert - 1 - v]];
    const std::uint32_t a = ab[0], b = ab[1];
    if (a >= nvtx || b >= nvtx) return false;  // an index that is not the tets' (never taken)
    const double u = s[a] / (s[a] - s[b]);
    project(P + 4 * std::size_t{a}, P + 4 * std::size_t{b}, u, out_pos + 3 * std::size_t{v});
    out_src[v] = {a, b, u};
    U[v] = u;
  }
  // The projected unit normals of the cut cells: independent square roots and divisions (two
  // at a time where SSE2 has them: the same correctly rounded results), no branch.
  {
    const double* CN = mesh.cell_normals.data();
    double* __restrict n3 = sc.cell_n3.data();
    grow(sc.cell_y, 4 * ncells + 4);
    double* __restrict yz = sc.cell_y.data();  // y0, y1, y2, |y|^2 of each cut cell
    const Eigen::Matrix<double, 3, 4>& NB = pr.NB;
    for (std::size_t j = 0; j < ncells; ++j) {
      const double* n = CN + 4 * std::size_t{cut_cells[j]};
      yz[4 * j + 3] = projected_normal(NB, n, yz + 4 * j);
    }
    auto write = [&](std::size_t j, double inv) {
      const std::size_t c = cut_cells[j];
      for (std::size_t r = 0; r < 3; ++r) n3[3 * c + r] = yz[4 * j + r] * inv;
    };
    std::size_t j = 0;
#if defined(__SSE2__)
    const __m128d one = _mm_set1_pd(1.0), zero = _mm_setzero_pd();
    for (; j + 2 <= ncells; j += 2) {
      const __m128d z = _mm_set_pd(yz[4 * j + 7], yz[4 * j + 3]);
      const __m128d inv =
          _mm_and_pd(_mm_div_pd(one, _mm_sqrt_pd(z)), _mm_cmpgt_pd(z, zero));  // 0 where z <= 0
      write(j, _mm_cvtsd_f64(inv));
      write(j + 1, _mm_cvtsd_f64(_mm_unpackhi_pd(inv, inv)));
    }
#endif
    for (; j < ncells; ++j) {
      const double z = yz[4 * j + 3];
      write(j, z > 0.0 ? 1.0 / std::sqrt(z) : 0.0);
    }
  }
  // The triangles, written at their final places: the cut tetrahedra giving one triangle and
  // those giving a quad in two loops of fixed trip counts (no branch on the case, nothing
  // written twice).
  const double* cell_n3 = sc.cell_n3.data();
  const double* UVW = mesh.corner_uvw.data();
  std::uint32_t* __restrict out_tri = out.triangles.data();
  double* __restrict out_nrm = out.normals.data();
  double* __restrict out_uvw = out.uvw.data();
  std::uint32_t* __restrict out_tet = out.tet.data();
  std::uint32_t* __restrict out_cell = out.cell.data();
  // Sources first (they need no crossing): both triangles of a quad, a triangle's slot twice.
  for (std::size_t j = 0; j < n3; ++j) {
    out_tet[list3[j].first] = list3[j].cut >> 4;
    out_cell[list3[j].first] = list3[j].cell;
  }
  for (std::size_t j = 0; j < n4; ++j) {
    const std::uint32_t w = list4[j].first;
    out_tet[w] = out_tet[w + 1] = list4[j].cut >> 4;
    out_cell[w] = out_cell[w + 1] = list4[j].cell;
  }
  const std::uint32_t top = nvert - 1;  // vertex top - r is the r-th numbered from the end
  // (compiled four times: one triangle or a quad, with or without UVW)
  auto write_cases = [&](auto count_tag, auto uvw_tag, const CutRecord* list, std::size_t n) {
    constexpr int count = decltype(count_tag)::value;
    constexpr bool with_uvw = decltype(uvw_tag)::value;
    for (std::size_t j = 0; j < n; ++j) {
      const CutRecord rec = list[j];
      const std::uint32_t t = rec.cut >> 4;
      const IndexedCase ic = table[rec.cut & 15u];
      const auto& tv = tets[t];
      const double* n3 = cell_n3 + 3 * std::size_t{rec.cell};
      const std::uint32_t* vid = corner_vid + 4 * std::size_t{rec.i};
      const double* tu = UVW + 12 * std::size_t{t};
      double uvw[count][3];
      std::uint32_t id[count];
      for (int k = 0; k < count; ++k) {
        id[k] = top - vid[k];
        if constexpr (with_uvw) {
          // u runs from the lower vertex id of the edge (picked by index arithmetic: which end
          // is lower is not predictable).
          const unsigned ka = ic.ka[k], kb = ic.kb[k];
          const unsigned b_low = 0u - static_cast<unsigned>(tv[kb] < tv[ka]);
          const unsigned lo = ka ^ ((ka ^ kb) & b_low), hi = ka ^ kb ^ lo;
          const double u = U[id[k]];
          const double* ua = tu + 3 * lo;
          const double* ub = tu + 3 * hi;
          for (int r = 0; r < 3; ++r) uvw[k][r] = (1.0 - u) * ua[r] + u * ub[r];
        }
      }
      auto emit = [&](std::size_t at, int i0, int i1, int i2) {
        const int c[3] = {i0, i1, i2};
        for (int k = 0; k < 3; ++k) {
          out_tri[3 * at + static_cast<std::size_t>(k)] = id[c[k]];
          if constexpr (with_uvw)
            for (int r = 0; r < 3; ++r)
              out_uvw[9 * at + static_cast<std::size_t>(3 * k + r)] = uvw[c[k]][r];
        }
        for (int r = 0; r < 3; ++r) out_nrm[3 * at + static_cast<std::size_t>(r)] = n3[r];
      };
      const std::size_t w = rec.first;
      if constexpr (count == 3) {
        emit(w, 0, 1, 2);
      } else {
        // The fan (0, 1, 2), (0, 2, 3) of the outward cycle, the second first when turned.
        emit(w + ic.swap, 0, 1, 2);
        emit(w + 1 - ic.swap, 0, 2, 3);
      }
    }
  };
  using Tri = std::integral_constant<int, 3>;
  using Quad = std::integral_constant<int, 4>;
  if (want_uvw) {
    write_cases(Tri{}, std::true_type{}, list3, n3);
    write_cases(Quad{}, std::true_type{}, list4, n4);
  } else {
    write_cases(Tri{}, std::false_type{}, list3, n3);
    write_cases(Quad{}, std::false_type{}, list4, n4);
  }
  return true;
}

// The cut when no vertex is on the plane (every crossing is interior to its edge, no triangle
// degenerates, no face lies in the plane): one pass over the corners' side bits lists the cut
// tetrahedra (all on one side: skipped at once) and counts their triangles, the output is sized
// once, and each cut tetrahedron is written straight into its final columns through the 16-case
// table. Each corner is the crossing of its edge computed from that tetrahedron alone, by the
// formulas of the indexed cut (CrossingProjector, projected_normal): the same bits as the
// indexed cut's shared crossing. The same triangles, in the same order and orientation, as the
// general loop of slice_tets.
void cut_generic_soup(const TetMesh& mesh, const Prepared& pr, Scratch& sc, bool want_uvw,
                      TetSection& out) {
  const double* s = sc.s.data();
  const Side* side = sc.side.data();
  const std::size_t T = mesh.size();
  const std::size_t nv = static_cast<std::size_t>(mesh.positions.cols());
  grow(sc.soup_up, nv);
  grow(sc.soup_cut, T);
  std::uint8_t* up = sc.soup_up.data();
  for (std::size_t v = 0; v < nv; ++v) up[v] = side[v] > Side::On;
  // Triangles per sign mask: none for 0 and 15, two for the quads (two corners each side).
  static constexpr std::uint8_t kTris[16] = {0, 1, 1, 2, 1, 2, 2, 1, 1, 2, 2, 1, 2, 1, 1, 0};
  std::uint32_t* cut = sc.soup_cut.data();  // (t << 4) | mask of each cut tetrahedron
  std::size_t ncut = 0, tris = 0;
  const std::array<std::uint32_t, 4>* tets = mesh.tets.data();
  for (std::size_t t = 0; t < T; ++t) {
    const auto& tv = tets[t];
    const unsigned mask = up[tv[0]] | (up[tv[1]] << 1) | (up[tv[2]] << 2) | (up[tv[3]] << 3);
    cut[ncut] = static_cast<std::uint32_t>(t << 4) | mask;
    ncut += mask - 1u < 14u;  // 0 and 15 (all on one side) are not cut
    tris += kTris[mask];
  }
  // (conservativeResize: a realloc, in place when the slice shrinks, where resize frees and
  // allocates anew for every new triangle count)
  const auto n = static_cast<Eigen::Index>(3 * tris);
  if (out.positions.cols() != n) out.positions.conservativeResize(3, n);
  if (out.normals.cols() != n) out.normals.conservativeResize(3, n);
  const auto nu = want_uvw ? n : Eigen::Index{0};
  if (out.uvw.cols() != nu) out.uvw.conservativeResize(3, nu);
  out.corners.resize(3 * tris);
  out.tet.resize(tris);
  out.cell.resize(tris);
  if (tris == 0) return;
  const CrossingProjector project(pr.W, pr.offset);
  const double* P = mesh.positions.data();
  const double* UVW = mesh.corner_uvw.data();
  const double* CN = mesh.cell_normals.data();
  const std::uint32_t* tet_cell = mesh.tet_cell.data();
  if (sc.cell_stamp.size() < mesh.cell_count()) {
    sc.cell_stamp.resize(mesh.cell_count(), 0);
    sc.soup_cell_n3.resize(3 * mesh.cell_count());
  }
  if (++sc.stamp == 0) {  // wrapped: forget every stamp
    std::fill(sc.cell_stamp.begin(), sc.cell_stamp.end(), 0u);
    sc.stamp = 1;
  }
  std::uint32_t* cell_stamp = sc.cell_stamp.data();
  const std::uint32_t stamp = sc.stamp;
  double* out_pos = out.positions.data();
  double* out_nrm = out.normals.data();
  double* out_uvw = out.uvw.data();
  TetCutPoint* out_corner = out.corners.data();
  std::uint32_t* out_tet = out.tet.data();
  std::uint32_t* out_cell = out.cell.data();
  std::size_t w = 0;  // triangles written
  for (std::size_t i = 0; i < ncut; ++i) {
    const std::uint32_t t = cut[i] >> 4;
    const TetCutCase& cc = kTetCutTable[cut[i] & 15u];
    const auto& tv = tets[t];
    // The projected normal once per cell (every tetrahedron of a cell has the same one).
    const std::uint32_t cell = tet_cell[t];
    double* n3 = sc.soup_cell_n3.data() + 3 * std::size_t{cell};
    if (cell_stamp[cell] != stamp) {
      cell_stamp[cell] = stamp;
      const double z = projected_normal(pr.NB, CN + 4 * std::size_t{cell}, n3);
      const double inv = z > 0.0 ? 1.0 / std::sqrt(z) : 0.0;
      for (int r = 0; r < 3; ++r) n3[r] *= inv;
    }
    // The body compiled once for triangles and once for quads (fixed trip counts).
    auto cut_one = [&](auto count_tag, auto uvw_tag) {
      constexpr int count = decltype(count_tag)::value;
      constexpr bool with_uvw = decltype(uvw_tag)::value;
      double pos[4][3], uvw[4][3];
      TetCutPoint cp[4];
      for (int e = 0; e < count; ++e) {
        const auto [ka, kb, a, b] = crossing_edge(cc, e, tv);
        const double u = s[a] / (s[a] - s[b]);
        cp[e] = {a, b, u};
        project(P + 4 * std::size_t{a}, P + 4 * std::size_t{b}, u, pos[e]);
        if constexpr (with_uvw) {
          const double* ua = UVW + 3 * (4 * std::size_t{t} + static_cast<std::size_t>(ka));
          const double* ub = UVW + 3 * (4 * std::size_t{t} + static_cast<std::size_t>(kb));
          for (int r = 0; r < 3; ++r) uvw[e][r] = (1.0 - u) * ua[r] + u * ub[r];
        }
      }
      // Orientation: the polygon's normal must point along the projected outward normal.
      const double d1[3] = {pos[1][0] - pos[0][0], pos[1][1] - pos[0][1], pos[1][2] - pos[0][2]};
      const double d2[3] = {pos[2][0] - pos[0][0], pos[2][1] - pos[0][1], pos[2][2] - pos[0][2]};
      double m[3] = {d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
                     d1[0] * d2[1] - d1[1] * d2[0]};
      if constexpr (count == 4) {
        const double d3[3] = {pos[3][0] - pos[0][0], pos[3][1] - pos[0][1], pos[3][2] - pos[0][2]};
        m[0] += d2[1] * d3[2] - d2[2] * d3[1];
        m[1] += d2[2] * d3[0] - d2[0] * d3[2];
        m[2] += d2[0] * d3[1] - d2[1] * d3[0];
      }
      // The turn as index arithmetic, not a branch: its sign is known only after the divisions
      // and the normal's square root, and it is unpredictable (half the polygons turn).
      const int rev = m[0] * n3[0] + m[1] * n3[1] + m[2] * n3[2] < 0.0;
      auto emit = [&](int i0, int i1, int i2) {
        const int c[3] = {i0, i1, i2};
        for (int k = 0; k < 3; ++k) {
          const std::size_t col = 3 * w + static_cast<std::size_t>(k);
          for (int r = 0; r < 3; ++r) {
            out_pos[3 * col + r] = pos[c[k]][r];
            out_nrm[3 * col + r] = n3[r];
            if constexpr (with_uvw) out_uvw[3 * col + r] = uvw[c[k]][r];
          }
          out_corner[col] = cp[c[k]];
        }
        out_tet[w] = t;
        out_cell[w] = cell;
        ++w;
      };
      emit(0, 1 + rev, 2 - rev);
      if constexpr (count == 4) emit(0, 2 + rev, 3 - rev);
    };
    using Tri = std::integral_constant<int, 3>;
    using Quad = std::integral_constant<int, 4>;
    if (want_uvw) {
      if (cc.count == 4)
        cut_one(Quad{}, std::true_type{});
      else
        cut_one(Tri{}, std::true_type{});
    } else {
      if (cc.count == 4)
        cut_one(Quad{}, std::false_type{});
      else
        cut_one(Tri{}, std::false_type{});
    }
  }
}

// The general cut into a soup (vertices on the plane: degenerate triangles dropped, flat faces
// between two tetrahedra cancelled); on-plane vertices count as positive or negative.
void cut_general(const TetMesh& mesh, const Prepared& pr, Scratch& sc, bool want_uvw,
                 TetSection& out) {
  out.corners.clear();
  out.tet.clear();
  out.cell.clear();
  auto& all_pos = sc.all_pos;
  auto& all_nrm = sc.all_nrm;
  auto& all_uvw = sc.all_uvw;
  auto& pos_buf = sc.pos_buf;
  auto& nrm_buf = sc.nrm_buf;
  auto& uvw_buf = sc.uvw_buf;
  auto& cut_buf = sc.cut_buf;
  all_pos.clear();
  all_nrm.clear();
  all_uvw.clear();
  const auto& side = sc.side;
  const auto& s = sc.s;
  const auto& p = mesh.positions;
  const Eigen::Matrix4d& lin = pr.lin;
  const Eigen::Matrix4d& normal_map = pr.normal_map;
  const Eigen::Matrix<double, 3, 4>& bt = pr.bt;
  const Eigen::Vector3d& offset = pr.offset;
  const bool any_on = pr.any_on;
  const auto finish = [&] {
    const auto n = static_cast<Eigen::Index>(all_pos.size());
    if (out.positions.cols() != n) out.positions.resize(3, n);
    if (out.normals.cols() != n) out.normals.resize(3, n);
    const auto nu = want_uvw ? n : Eigen::Index{0};
    if (out.uvw.cols() != nu) out.uvw.resize(3, nu);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto j = static_cast<std::size_t>(i);
      out.positions.col(i) = all_pos[j];
      out.normals.col(i) = all_nrm[j];
      if (want_uvw) out.uvw.col(i) = all_uvw[j];
    }
  };
  if (!pr.any_pos && !pr.any_neg) {  // everything on the plane: a flat model
    finish();
    return;
  }
  auto run = [&](bool on_is_positive) {
    // Corner k counts as positive when its side is at least `floor` (Side: -1, 0, +1).
    const int floor = on_is_positive ? 0 : 1;
    const Side* sd = side.data();
    for (std::size_t t = 0; t < mesh.size(); ++t) {
      const auto& tv = mesh.tets[t];
      const int mask = (static_cast<int>(sd[tv[0]]) >= floor) |
                       ((static_cast<int>(sd[tv[1]]) >= floor) << 1) |
                       ((static_cast<int>(sd[tv[2]]) >= floor) << 2) |
                       ((static_cast<int>(sd[tv[3]]) >= floor) << 3);
      if (mask == 0 || mask == 15) continue;  // all on one side: nothing to cut
      const TetCutCase& cc = kTetCutTable[static_cast<std::size_t>(mask)];
      const Eigen::Vector4d n4 = normal_map * mesh.tet_normal(t);
      const Eigen::Vector3d n3 = (bt * n4).normalized();
      pos_buf.clear();
      nrm_buf.clear();
      uvw_buf.clear();
      cut_buf.clear();
      for (int e = 0; e < cc.count; ++e) {
        const auto [ka, kb, a, b] = crossing_edge(cc, e, tv);
        TetCutPoint cp;
        if (side[a] == Side::On) {
          cp = {a, a, 0.0};
        } else if (side[b] == Side::On) {
          cp = {b, b, 0.0};
        } else {
          cp = {a, b, s[a] / (s[a] - s[b])};
        }
        const double w = cp.a == cp.b ? (cp.a == a ? 0.0 : 1.0) : cp.t;
        const Eigen::Vector4d x = (1.0 - w) * p.col(a) + w * p.col(b);
        pos_buf.push_back(bt * (lin * x) + offset);
        uvw_buf.push_back((1.0 - w) * mesh.corner_uvw_of(t, ka) + w * mesh.corner_uvw_of(t, kb));
        nrm_buf.push_back(n3);  // both corners carry the cell's normal
        cut_buf.push_back(cp);
      }
      // Orientation: the polygon's normal must point along the projected outward normal.
      const Eigen::Vector3d m =
          (pos_buf[1] - pos_buf[0]).cross(pos_buf[2] - pos_buf[0]) +
          (cc.count == 4 ? (pos_buf[2] - pos_buf[0]).cross(pos_buf[3] - pos_buf[0])
                         : Eigen::Vector3d::Zero());
      const bool reverse = m.dot(n3) < 0.0;
      auto emit = [&](int i0, int i1, int i2) {
        std::array<int, 3> c{i0, i1, i2};
        if (reverse) std::swap(c[1], c[2]);
        if (cut_buf[static_cast<std::size_t>(c[0])] == cut_buf[static_cast<std::size_t>(c[1])] ||
            cut_buf[static_cast<std::size_t>(c[1])] == cut_buf[static_cast<std::size_t>(c[2])] ||
            cut_buf[static_cast<std::size_t>(c[0])] == cut_buf[static_cast<std::size_t>(c[2])])
          return;  // two corners at the same on-plane vertex: no area
        for (int k = 0; k < 3; ++k) {
          const auto i = static_cast<std::size_t>(c[static_cast<std::size_t>(k)]);
          all_pos.push_back(pos_buf[i]);
          all_nrm.push_back(nrm_buf[i]);
          all_uvw.push_back(uvw_buf[i]);
          out.corners.push_back(cut_buf[i]);
        }
        out.tet.push_back(static_cast<std::uint32_t>(t));
        out.cell.push_back(mesh.tet_cell[t]);
      };
      emit(0, 1, 2);
      if (cc.count == 4) emit(0, 2, 3);
    }
    // A tetrahedron face lying in the plane between two tetrahedra on the same side is emitted by
    // both, with opposite orientations: the pieces cancel as chains (as in cw4d::section).
    if (!any_on) return;  // (corners at vertices need vertices on the plane)
    std::map<std::array<std::uint32_t, 3>, std::vector<std::size_t>> flat;
    for (std::size_t i = 0; i < out.tet.size(); ++i) {
      std::array<std::uint32_t, 3> key{};
      bool on_plane = true;
      for (std::size_t k = 0; k < 3; ++k) {
        const TetCutPoint& cp = out.corners[3 * i + k];
        on_plane &= cp.a == cp.b;
        key[k] = cp.a;
      }
      if (!on_plane) continue;
      std::sort(key.begin(), key.end());
      flat[key].push_back(i);
    }
    std::vector<char> keep(out.tet.size(), 1);
    for (const auto& [key, list] : flat)
      if (list.size() == 2)
        for (auto i : list) keep[i] = 0;
    if (std::find(keep.begin(), keep.end(), 0) != keep.end()) {
      std::size_t w = 0;
      for (std::size_t i = 0; i < out.tet.size(); ++i) {
        if (!keep[i]) continue;
        for (std::size_t k = 0; k < 3; ++k) {
          all_pos[3 * w + k] = all_pos[3 * i + k];
          all_nrm[3 * w + k] = all_nrm[3 * i + k];
          all_uvw[3 * w + k] = all_uvw[3 * i + k];
          out.corners[3 * w + k] = out.corners[3 * i + k];
        }
        out.tet[w] = out.tet[i];
        out.cell[w] = out.cell[i];
        ++w;
      }
      out.tet.resize(w);
      out.cell.resize(w);
      out.corners.resize(3 * w);
      all_pos.resize(3 * w);
      all_nrm.resize(3 * w);
      all_uvw.resize(3 * w);
    }
  };
  // On counts as positive; when that leaves nothing (the plane touches the model from below),
  // as negative, so that a facet lying in the plane is returned (as cw4d::section does).
  run(true);
  if (out.tet.empty() && any_on) run(false);
  finish();
}

// The indexed form of a soup: corners with the same source become one vertex (the first
// corner's position), numbered in order of first appearance.
void weld_soup(const TetSection& soup, TetSliceMesh& out) {
  const std::size_t T = soup.triangle_count();
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> index;
  out.positions.clear();
  out.vertex_source.clear();
  out.triangles.resize(3 * T);
  out.normals.resize(3 * T);
  const bool with_uvw = soup.uvw.cols() == static_cast<Eigen::Index>(3 * T);
  out.uvw.resize(with_uvw ? 9 * T : 0);
  out.tet.assign(soup.tet.begin(), soup.tet.end());
  out.cell.assign(soup.cell.begin(), soup.cell.end());
  for (std::size_t i = 0; i < T; ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t c = 3 * i + k;
      const TetCutPoint& cp = soup.corners[c];
      const auto [it, fresh] = index.emplace(std::make_pair(cp.a, cp.b),
                                             static_cast<std::uint32_t>(out.vertex_source.size()));
      if (fresh) {
        out.vertex_source.push_back(cp);
        for (int r = 0; r < 3; ++r)
          out.positions.push_back(soup.positions(r, static_cast<Eigen::Index>(c)));
      }
      out.triangles[c] = it->second;
      if (with_uvw)
        for (int r = 0; r < 3; ++r)
          out.uvw[3 * c + static_cast<std::size_t>(r)] = soup.uvw(r, static_cast<Eigen::Index>(c));
    }
    for (int r = 0; r < 3; ++r)
      out.normals[3 * i + static_cast<std::size_t>(r)] =
          soup.normals(r, static_cast<Eigen::Index>(3 * i));
  }
}

// An edge and block index of a copy of the mesh's tets, built here and kept per thread for the
// next slice of the same tets (for meshes without an index, or with one out of range).
const TetMesh& indexed_copy(const TetMesh& mesh, Scratch& sc) {
  if (sc.edge_mesh.tets != mesh.tets || sc.edge_mesh.tet_cell != mesh.tet_cell ||
      sc.edge_mesh.block_first.empty()) {
    sc.edge_mesh.tets = mesh.tets;
    sc.edge_mesh.tet_cell = mesh.tet_cell;
    index_tet_edges(sc.edge_mesh);
  }
  return sc.edge_mesh;
}

// The mesh's edge and block index, or a copy's when its tets were changed after tetrahedralize.
const TetMesh& edge_index(const TetMesh& mesh, Scratch& sc) {
  if (mesh.tet_edges.size() == mesh.tets.size() && !mesh.block_first.empty() &&
      mesh.block_first.back() == mesh.tets.size() &&
      mesh.block_vertex_first.size() == mesh.block_first.size()) {
    // Only the sizes are checked here (the whole check costs as much as the slice); the cut
    // checks the ranges of what it reads and comes back for a copy's index when one is out of
    // range.
    return mesh;
  }
  return indexed_copy(mesh, sc);
}

// The identity placement, built once (not allocated per slice).
const AffineTransform& identity4() {
  static const AffineTransform id = AffineTransform::identity(4);
  return id;
}

}  // namespace

void to_soup(const TetSliceMesh& slice, TetSection& out) {
  out.frame = slice.frame;
  const std::size_t T = slice.triangle_count();
  const auto n = static_cast<Eigen::Index>(3 * T);
  if (out.positions.cols() != n) out.positions.resize(3, n);
  if (out.normals.cols() != n) out.normals.resize(3, n);
  const bool with_uvw = slice.uvw.size() == 9 * T;
  const auto nu = with_uvw ? n : Eigen::Index{0};
  if (out.uvw.cols() != nu) out.uvw.resize(3, nu);
  out.corners.resize(3 * T);
  out.tet.assign(slice.tet.begin(), slice.tet.end());
  out.cell.assign(slice.cell.begin(), slice.cell.end());
  if (T == 0) return;
  if (with_uvw) std::copy(slice.uvw.begin(), slice.uvw.end(), out.uvw.data());  // the same layout
  const std::uint32_t* tri = slice.triangles.data();
  const double* P = slice.positions.data();
  const double* N = slice.normals.data();
  const TetCutPoint* src = slice.vertex_source.data();
  double* op = out.positions.data();
  double* on = out.normals.data();
  TetCutPoint* oc = out.corners.data();
  for (std::size_t i = 0; i < T; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t c = 3 * i + k;
      const std::size_t v = tri[c];
      for (std::size_t r = 0; r < 3; ++r) {
        op[3 * c + r] = P[3 * v + r];
        on[3 * c + r] = N[3 * i + r];
      }
      oc[c] = src[v];
    }
}

TetSlicer::TetSlicer() : scratch_(std::make_unique<Scratch>()) {}
TetSlicer::TetSlicer(TetSliceOptions options)
    : scratch_(std::make_unique<Scratch>()), options_(options) {}
TetSlicer::~TetSlicer() = default;
TetSlicer::TetSlicer(TetSlicer&&) noexcept = default;
TetSlicer& TetSlicer::operator=(TetSlicer&&) noexcept = default;

TetSection TetSlicer::slice(const TetMesh& mesh, const Hyperplane& plane) {
  return slice(mesh, plane, identity4());
}

TetSection TetSlicer::slice(const TetMesh& mesh, const Hyperplane& plane,
                            const AffineTransform& xf) {
  TetSection out;
  slice(mesh, plane, xf, out);
  return out;
}

void TetSlicer::slice(const TetMesh& mesh, const Hyperplane& plane, TetSection& out) {
  slice(mesh, plane, identity4(), out);
}

void TetSlicer::slice(const TetMesh& mesh, const Hyperplane& plane, TetSliceMesh& out) {
  slice(mesh, plane, identity4(), out);
}

void TetSlicer::slice(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& xf,
                      TetSection& out) {
  if (!scratch_) scratch_ = std::make_unique<Scratch>();  // (a moved-from slicer)
  Scratch& sc = *scratch_;
  if (plane.dim() == 4) set_frame(out.frame, plane);
  const Prepared pr = prepare(mesh, plane, xf, out.frame, sc);
  if (!pr.any_on && (!pr.any_pos || !pr.any_neg)) {  // the plane misses the model
    out.positions.resize(3, 0);
    out.normals.resize(3, 0);
    out.uvw.resize(3, 0);
    out.corners.clear();
    out.tet.clear();
    out.cell.clear();
    return;
  }
  if (pr.any_on) {
    cut_general(mesh, pr, sc, options_.uvw, out);
    return;
  }
  // The soup's own cut (the triangles of the indexed one, corner by corner, the same bits).
  cut_generic_soup(mesh, pr, sc, options_.uvw, out);
}

void TetSlicer::slice(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& xf,
                      TetSliceMesh& out) {
  if (!scratch_) scratch_ = std::make_unique<Scratch>();  // (a moved-from slicer)
  Scratch& sc = *scratch_;
  if (plane.dim() == 4) set_frame(out.frame, plane);
  const Prepared pr = prepare(mesh, plane, xf, out.frame, sc);
  if (!pr.any_on && (!pr.any_pos || !pr.any_neg)) {  // the plane misses the model
    out.clear();
    return;
  }
  if (pr.any_on) {
    set_frame(sc.soup.frame, plane);
    cut_general(mesh, pr, sc, options_.uvw, sc.soup);
    weld_soup(sc.soup, out);
    return;
  }
  if (cut_indexed(mesh, edge_index(mesh, sc), pr, sc, options_.uvw, out)) return;
  // The mesh's index no longer describes its tets (edited in place without index_tet_edges):
  // a copy's, as for a mesh without one.
  const bool ok = cut_indexed(mesh, indexed_copy(mesh, sc), pr, sc, options_.uvw, out);
  assert(ok);
  static_cast<void>(ok);
}

namespace {

// The slicer of the free functions: one per thread, so that they keep their scratch between
// calls as a caller's TetSlicer does.
TetSlicer& thread_slicer() {
  thread_local TetSlicer slicer;
  return slicer;
}

}  // namespace

TetSection slice_tets(const TetMesh& mesh, const Hyperplane& plane) {
  return thread_slicer().slice(mesh, plane);
}

TetSection slice_tets(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& xf) {
  return thread_slicer().slice(mesh, plane, xf);
}

void slice_tets(const TetMesh& mesh, const Hyperplane& plane, TetSection& out) {
  thread_slicer().slice(mesh, plane, out);
}

void slice_tets(const TetMesh& mesh, const Hyperplane& plane, TetSliceMesh& out) {
  thread_slicer().slice(mesh, plane, out);
}

void slice_tets(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& xf,
                TetSection& out) {
  thread_slicer().slice(mesh, plane, xf, out);
}

void slice_tets(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& xf,
                TetSliceMesh& out) {
  thread_slicer().slice(mesh, plane, xf, out);
}

Section to_section(const TetSection& slice, const Complex& model) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> model_edge;
  for (std::uint32_t e = 0; e < model.count(1); ++e) {
    const auto ends = model.edge(e);
    model_edge.emplace(std::minmax(ends[0], ends[1]), e);
  }
  Section sec;
  sec.frame = slice.frame;
  sec.source_fingerprint = model_fingerprint(model);
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> index;
  ComplexSoup soup;
  soup.ambient_dim = 3;
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::uint32_t> face_cell;
  for (std::size_t i = 0; i < slice.triangle_count(); ++i) {
    std::vector<std::uint32_t> f;
    for (int k = 0; k < 3; ++k) {
      const std::size_t c = 3 * i + static_cast<std::size_t>(k);
      const auto& cp = slice.corners[c];
      auto [it, fresh] =
          index.emplace(std::make_pair(cp.a, cp.b), static_cast<std::uint32_t>(pts.size()));
      if (fresh) {
        pts.push_back(slice.positions.col(static_cast<Eigen::Index>(c)));
        VertexSource vs;
        if (cp.a == cp.b) {
          vs.rank = 0;
          vs.element = cp.a;
        } else {
          vs.rank = 1;
          const auto it_edge = model_edge.find({cp.a, cp.b});
          if (it_edge == model_edge.end()) {
            vs.element = no_index;  // a diagonal of the tetrahedralization
            vs.t = cp.t;
          } else {
            vs.element = it_edge->second;
            vs.t = model.edge(vs.element)[0] == cp.a ? cp.t : 1.0 - cp.t;
          }
        }
        sec.vertex_source.push_back(vs);
      }
      f.push_back(it->second);
    }
    soup.faces.push_back(f);
    face_cell.push_back(slice.cell[i]);
  }
  soup.positions.resize(3, static_cast<Eigen::Index>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i)
    soup.positions.col(static_cast<Eigen::Index>(i)) = pts[i];
  BuildOptions opt;
  opt.orient = false;  // the triangles are oriented outward already
  sec.complex = build_complex(soup, opt);
  assert(sec.complex.count(2) == slice.triangle_count() && sec.vertex_source.size() == pts.size());
  Eigen::MatrixXd normals(3, static_cast<Eigen::Index>(slice.triangle_count()));
  for (std::size_t i = 0; i < slice.triangle_count(); ++i)
    normals.col(static_cast<Eigen::Index>(i)) = slice.normals.col(static_cast<Eigen::Index>(3 * i));
  sec.complex.set_facet_normals(std::move(normals));
  sec.source.assign(3, {});
  sec.source[1].assign(sec.complex.count(1), 0);  // edges have no single source here
  sec.source[2] = std::move(face_cell);
  return sec;
}

CornerUvw tet_section_uvw(const TetSection& slice, const Section& section) {
  const Complex& c = section.complex;
  const std::size_t faces = c.top_rank() >= 2 ? c.count(2) : 0;
  if (faces != slice.triangle_count())
    throw InputError("tet section UVW: the section has " + std::to_string(faces) +
                     " faces, the slice " + std::to_string(slice.triangle_count()) + " triangles");
  if (faces > 0 && slice.uvw.cols() != static_cast<Eigen::Index>(3 * faces))
    throw InputError("tet section UVW: the slice has no UVW (TetSliceOptions::uvw was off)");
  CornerUvw out;
  out.offset.resize(faces + 1);
  out.uvw.resize(3, static_cast<Eigen::Index>(3 * faces));
  for (std::size_t f = 0; f < faces; ++f) {
    out.offset[f] = static_cast<std::uint32_t>(3 * f);
    const auto cycle = c.face_cycle(static_cast<std::uint32_t>(f));
    if (cycle.size() != 3)
      throw InputError("tet section UVW: face " + std::to_string(f) + " is not a triangle");
    // Face f is triangle f (to_section keeps their order); its corners are matched by position,
    // which to_section copied from the slice (welded vertices: the first corner's copy, equal
    // to within rounding for the same crossing).
    for (std::size_t j = 0; j < 3; ++j) {
      const Eigen::Vector3d p = c.position(cycle[j]);
      std::size_t best = 0;
      double best_d = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < 3; ++k) {
        const double d =
            (slice.positions.col(static_cast<Eigen::Index>(3 * f + k)) - p).squaredNorm();
        if (d < best_d) {
          best_d = d;
          best = k;
        }
      }
      out.uvw.col(static_cast<Eigen::Index>(3 * f + j)) =
          slice.uvw.col(static_cast<Eigen::Index>(3 * f + best)).cast<float>();
    }
  }
  out.offset[faces] = static_cast<std::uint32_t>(3 * faces);
  return out;
}

}  // namespace cw4d
