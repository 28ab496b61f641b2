#include "cw4d/tetrahedralize/tet_slice.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <type_traits>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/tolerances.hpp"

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

// The cut when no vertex is on the plane (every crossing is interior to its edge, no triangle
// degenerates, no face lies in the plane): one pass over the corners' side bits lists the cut
// tetrahedra (all on one side: skipped at once) and counts their triangles, the output is sized
// once, and each cut tetrahedron is written straight into its final columns through the 16-case
// table. Vertices are projected into the section frame once each (y = W p + offset), a crossing
// interpolates the two projections. The same triangles, in the same order and orientation, as
// the general loop of slice_tets.
void cut_generic(const TetMesh& mesh, const double* s, const Side* side,
                 const Eigen::Matrix<double, 3, 4>& W, const Eigen::Vector3d& offset,
                 const Eigen::Matrix<double, 3, 4>& NB, TetSection& out) {
  const std::size_t T = mesh.size();
  const std::size_t nv = static_cast<std::size_t>(mesh.positions.cols());
  thread_local std::vector<std::uint8_t> up_store;
  thread_local std::vector<std::uint32_t> cut_store;
  thread_local std::vector<double> proj_store;
  up_store.resize(nv);
  cut_store.resize(T);
  proj_store.resize(3 * nv);
  std::uint8_t* up = up_store.data();
  for (std::size_t v = 0; v < nv; ++v) up[v] = side[v] > Side::On;
  // Triangles per sign mask: none for 0 and 15, two for the quads (two corners each side).
  static constexpr std::uint8_t kTris[16] = {0, 1, 1, 2, 1, 2, 2, 1, 1, 2, 2, 1, 2, 1, 1, 0};
  std::uint32_t* cut = cut_store.data();  // (t << 4) | mask of each cut tetrahedron
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
  if (out.uvw.cols() != n) out.uvw.conservativeResize(3, n);
  out.corners.resize(3 * tris);
  out.tet.resize(tris);
  out.cell.resize(tris);
  if (tris == 0) return;
  // The vertices in section coordinates, each once.
  const double* P = mesh.positions.data();
  double* Y = proj_store.data();
  for (std::size_t v = 0; v < nv; ++v) {
    const double* x = P + 4 * v;
    for (int r = 0; r < 3; ++r)
      Y[3 * v + r] = W(r, 0) * x[0] + W(r, 1) * x[1] + W(r, 2) * x[2] + W(r, 3) * x[3] + offset[r];
  }
  const double* UVW = mesh.corner_uvw.data();
  const double* CN = mesh.cell_normals.data();
  const std::uint32_t* tet_cell = mesh.tet_cell.data();
  thread_local std::vector<std::uint32_t> cell_stamp;
  thread_local std::vector<double> cell_n3;
  thread_local std::uint32_t stamp = 0;
  if (cell_stamp.size() < mesh.cell_count())
    cell_stamp.resize(mesh.cell_count(), 0), cell_n3.resize(3 * mesh.cell_count());
  if (++stamp == 0) {  // wrapped: forget every stamp
    std::fill(cell_stamp.begin(), cell_stamp.end(), 0u);
    stamp = 1;
  }
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
    double* n3 = &cell_n3[3 * cell];
    if (cell_stamp[cell] != stamp) {
      cell_stamp[cell] = stamp;
      const Eigen::Vector3d nn =
          (NB * Eigen::Map<const Eigen::Vector4d>(CN + 4 * std::size_t{cell})).normalized();
      n3[0] = nn[0], n3[1] = nn[1], n3[2] = nn[2];
    }
    // The body compiled once for triangles and once for quads (fixed trip counts).
    auto cut_one = [&](auto count_tag) {
      constexpr int count = decltype(count_tag)::value;
      double pos[4][3], uvw[4][3];
      TetCutPoint cp[4];
      for (int e = 0; e < count; ++e) {
        const auto [ka, kb, a, b] = crossing_edge(cc, e, tv);
        const double u = s[a] / (s[a] - s[b]);
        cp[e] = {a, b, u};
        const double* ya = Y + 3 * a;
        const double* yb = Y + 3 * b;
        const double* ua = UVW + 3 * (4 * std::size_t{t} + static_cast<std::size_t>(ka));
        const double* ub = UVW + 3 * (4 * std::size_t{t} + static_cast<std::size_t>(kb));
        for (int r = 0; r < 3; ++r) {
          pos[e][r] = (1.0 - u) * ya[r] + u * yb[r];
          uvw[e][r] = (1.0 - u) * ua[r] + u * ub[r];
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
            out_uvw[3 * col + r] = uvw[c[k]][r];
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
    if (cc.count == 4)
      cut_one(std::integral_constant<int, 4>{});
    else
      cut_one(std::integral_constant<int, 3>{});
  }
}

}  // namespace

TetSection slice_tets(const TetMesh& mesh, const Hyperplane& plane) {
  return slice_tets(mesh, plane, AffineTransform::identity(4));
}

TetSection slice_tets(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& xf) {
  TetSection out;
  slice_tets(mesh, plane, xf, out);
  return out;
}

void slice_tets(const TetMesh& mesh, const Hyperplane& plane, TetSection& out) {
  slice_tets(mesh, plane, AffineTransform::identity(4), out);
}

void slice_tets(const TetMesh& mesh, const Hyperplane& plane, const AffineTransform& xf,
                TetSection& out) {
  if (plane.dim() != 4)
    throw InputError("slice_tets: hyperplane in R^" + std::to_string(plane.dim()) + ", not R^4");
  if (xf.dim() != 4)
    throw InputError("slice_tets: transform of R^" + std::to_string(xf.dim()) + ", not R^4");
  out.frame = HyperplaneFrame(plane);
  out.corners.clear();
  out.tet.clear();
  out.cell.clear();
  // The plane in model space: (A^T n).x = d - n.t (as cw4d::section does).
  const Eigen::Vector4d nm = xf.linear().transpose() * plane.normal;
  const double dm = plane.offset - plane.normal.dot(xf.translation());
  const auto& p = mesh.positions;
  const auto nv = static_cast<std::size_t>(p.cols());
  // Per-thread scratch, kept between slices.
  thread_local std::vector<double> s;
  thread_local std::vector<Side> side;
  thread_local std::vector<Eigen::Vector3d> pos_buf, nrm_buf, uvw_buf, all_pos, all_nrm, all_uvw;
  thread_local std::vector<TetCutPoint> cut_buf;
  s.resize(nv);
  side.resize(nv);
  all_pos.clear();
  all_nrm.clear();
  all_uvw.clear();
  double max_norm2 = 0.0;
  for (std::size_t v = 0; v < nv; ++v) {
    const auto x = p.col(static_cast<Eigen::Index>(v));
    s[v] = nm.dot(x) - dm;
    max_norm2 = std::max(max_norm2, x.squaredNorm());
  }
  const double tolerance = on_plane_tolerance(nm.norm(), std::sqrt(max_norm2), dm);
  bool any_neg = false, any_pos = false, any_on = false;
  for (std::size_t v = 0; v < nv; ++v) {
    side[v] = classify_side(s[v], tolerance);
    any_neg |= side[v] == Side::Negative;
    any_pos |= side[v] == Side::Positive;
    any_on |= side[v] == Side::On;
  }
  const auto finish = [&] {
    const auto n = static_cast<Eigen::Index>(all_pos.size());
    if (out.positions.cols() != n) out.positions.resize(3, n);
    if (out.normals.cols() != n) out.normals.resize(3, n);
    if (out.uvw.cols() != n) out.uvw.resize(3, n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto j = static_cast<std::size_t>(i);
      out.positions.col(i) = all_pos[j];
      out.normals.col(i) = all_nrm[j];
      out.uvw.col(i) = all_uvw[j];
    }
  };
  if (!any_pos && !any_neg) {  // everything on the plane: a flat model
    finish();
    return;
  }

  // World-space frame: y = B^T (A x + t - origin); normals transform by A^{-T}.
  const Eigen::Matrix4d lin = xf.linear();
  const Eigen::Matrix4d normal_map = lin.inverse().transpose();
  const Eigen::MatrixXd& basis = out.frame.basis;
  const Eigen::Matrix<double, 3, 4> bt = basis.transpose();
  const Eigen::Vector3d offset = bt * (xf.translation() - out.frame.origin());

  // One pass of the cut; on-plane vertices count as positive or negative.
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
  if (!any_on) {
    cut_generic(mesh, s.data(), side.data(), bt * lin, offset, bt * normal_map, out);
    return;
  }
  run(true);
  if (out.tet.empty() && any_on) run(false);
  finish();
}

Section to_section(const TetSection& slice, const Complex& model) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> model_edge;
  for (std::uint32_t e = 0; e < model.count(1); ++e) {
    const auto ends = model.edge(e);
    model_edge.emplace(std::minmax(ends[0], ends[1]), e);
  }
  Section sec;
  sec.frame = slice.frame;
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
