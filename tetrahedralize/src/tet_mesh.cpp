// Tetrahedralization of the 3-cells of a 4D complex: one global face triangulation, coning of
// convex cells, the 5-tetrahedron cube split, the caller's mesher for the rest (TetGen, in
// cw4d_tetrahedralize: tetgen_cell.cpp), UVW. Eigen only (cw4d_tetra).
#include "cw4d/tetrahedralize/tet_mesh.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <unordered_map>

#include "cw4d/complex/text.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/section/triangulate.hpp"
#include "cw4d/section/uvw.hpp"

namespace cw4d {

namespace {

using Tri = std::array<std::uint32_t, 3>;
using Tet = std::array<std::uint32_t, 4>;

double det4(const Eigen::Vector4d& n, const Eigen::Vector4d& a, const Eigen::Vector4d& b,
            const Eigen::Vector4d& c) {
  Eigen::Matrix4d m;
  m << n, a, b, c;
  return m.determinant();
}

// Orientation of the chain [v0 v1 v2 v3] relative to the outward geometric orientation:
// for the boundary convention of complex.hpp, a chain-positive tetrahedron of an outward cell
// has det(N, p1 - p0, p2 - p0, p3 - p0) of this sign (checked by the tests on every model).
constexpr int kChainToGeometric = 1;

// A global order of the vertices: one colour class of a 2-colouring of the edge graph first
// (when the graph is bipartite), then by id. key[v] is v's position.
std::vector<std::uint32_t> vertex_order(const Complex& c) {
  const std::size_t nv = c.count(0);
  std::vector<std::vector<std::uint32_t>> adj(nv);
  for (std::uint32_t e = 0; e < c.count(1); ++e) {
    const auto ends = c.edge(e);
    adj[ends[0]].push_back(ends[1]);
    adj[ends[1]].push_back(ends[0]);
  }
  std::vector<int> color(nv, -1);
  bool bipartite = true;
  for (std::uint32_t s = 0; s < nv && bipartite; ++s) {
    if (color[s] >= 0) continue;
    color[s] = 0;
    std::queue<std::uint32_t> q;
    q.push(s);
    while (!q.empty() && bipartite) {
      const auto v = q.front();
      q.pop();
      for (auto w : adj[v]) {
        if (color[w] < 0) {
          color[w] = 1 - color[v];
          q.push(w);
        } else if (color[w] == color[v]) {
          bipartite = false;
          break;
        }
      }
    }
  }
  std::vector<std::uint32_t> ids(nv);
  for (std::uint32_t v = 0; v < nv; ++v) ids[v] = v;
  if (bipartite)
    std::stable_sort(ids.begin(), ids.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return color[a] < color[b]; });
  std::vector<std::uint32_t> key(nv);
  for (std::uint32_t i = 0; i < nv; ++i) key[ids[i]] = i;
  return key;
}

// 2D coordinates of a planar polygon in R^n (an orthonormal frame of its plane).
std::vector<Eigen::Vector2d> polygon_2d(const Complex& c, const std::vector<std::uint32_t>& cyc) {
  const auto& p = c.positions();
  Eigen::VectorXd centre = Eigen::VectorXd::Zero(p.rows());
  for (auto v : cyc) centre += p.col(v);
  centre /= static_cast<double>(cyc.size());
  // First axis: towards the farthest vertex; second: the largest residual of the others.
  Eigen::VectorXd u = Eigen::VectorXd::Zero(p.rows()), w = u;
  for (auto v : cyc)
    if ((p.col(v) - centre).squaredNorm() > u.squaredNorm()) u = p.col(v) - centre;
  u.normalize();
  for (auto v : cyc) {
    Eigen::VectorXd r = p.col(v) - centre;
    r -= r.dot(u) * u;
    if (r.squaredNorm() > w.squaredNorm()) w = r;
  }
  w.normalize();
  std::vector<Eigen::Vector2d> out;
  out.reserve(cyc.size());
  for (auto v : cyc) out.emplace_back((p.col(v) - centre).dot(u), (p.col(v) - centre).dot(w));
  return out;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

bool is_convex_polygon(const std::vector<Eigen::Vector2d>& q, double& orientation) {
  double area = 0.0, scale = 0.0;
  const std::size_t n = q.size();
  for (std::size_t i = 0; i < n; ++i) {
    area += cross2(q[i], q[(i + 1) % n]);
    scale = std::max(scale, q[i].squaredNorm());
  }
  orientation = area >= 0.0 ? 1.0 : -1.0;
  const double tol = tol::degenerate_rel * scale;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = q[(i + n - 1) % n];
    const auto& b = q[i];
    const auto& d = q[(i + 1) % n];
    if (orientation * cross2(b - a, d - b) < -tol) return false;
  }
  return true;
}

// Ear clipping of a simple polygon (section/triangulate.hpp); triangles keep the cycle's
// orientation. A face that cannot be clipped is not a simple planar polygon.
std::vector<Tri> ear_clip(const std::vector<std::uint32_t>& cyc,
                          const std::vector<Eigen::Vector2d>& q, std::uint32_t face) {
  std::vector<Triangle> tris;
  if (!ear_clip_polygon(q, cyc, face, tris))
    throw TopologyError(
        2, {face},
        "face " + std::to_string(face) + " cannot be triangulated (not a simple planar polygon)");
  std::vector<Tri> out;
  out.reserve(tris.size());
  for (const Triangle& t : tris) out.push_back(t.v);
  return out;
}

struct FaceTriangulation {
  std::vector<std::vector<Tri>> triangles;
  std::vector<char> convex;
};

FaceTriangulation triangulate_all(const Complex& c, const std::vector<std::uint32_t>& key) {
  FaceTriangulation out;
  const std::size_t nf = c.count(2);
  out.triangles.resize(nf);
  out.convex.resize(nf);
  for (std::uint32_t f = 0; f < nf; ++f) {
    auto cyc = c.face_cycle(f);
    if (cyc.size() == 3) {
      out.triangles[f].push_back({cyc[0], cyc[1], cyc[2]});
      out.convex[f] = 1;
      continue;
    }
    const auto q = polygon_2d(c, cyc);
    double orientation = 1.0;
    if (is_convex_polygon(q, orientation)) {
      out.convex[f] = 1;
      // Fan from the first vertex in the global order.
      const auto first = std::min_element(cyc.begin(), cyc.end(),
                                          [&](auto a, auto b) { return key[a] < key[b]; }) -
                         cyc.begin();
      std::rotate(cyc.begin(), cyc.begin() + first, cyc.end());
      for (std::size_t k = 1; k + 1 < cyc.size(); ++k)
        out.triangles[f].push_back({cyc[0], cyc[k], cyc[k + 1]});
    } else {
      out.convex[f] = 0;
      out.triangles[f] = ear_clip(cyc, q, f);
    }
  }
  return out;
}

// A chain-positive tetrahedron made geometrically positive (outward).
Tet outward(Tet t, int chain_sign) {
  if (chain_sign * kChainToGeometric < 0) std::swap(t[2], t[3]);
  return t;
}

// Face of a chain-positive tetrahedron opposite its corner i, as a chain-positive triangle.
Tri opposite_face(const Tet& t, int i) {
  Tri f{};
  int k = 0;
  for (int j = 0; j < 4; ++j)
    if (j != i) f[static_cast<std::size_t>(k++)] = t[static_cast<std::size_t>(j)];
  if (i % 2 == 1) std::swap(f[1], f[2]);
  return f;
}

struct CellContext {
  const Complex& c;
  const FaceTriangulation& ft;
  const std::vector<std::uint32_t>& key;
};

// The faces of a cell with their signs.
struct CellFaces {
  std::vector<std::uint32_t> faces;
  std::vector<int> signs;
  std::vector<std::uint32_t> vertices;  // sorted, unique
};

CellFaces cell_faces(const Complex& c, std::uint32_t cell) {
  CellFaces out;
  const auto ids = c.boundary(3).ids(cell);
  const auto signs = c.boundary(3).signs(cell);
  out.faces.assign(ids.begin(), ids.end());
  out.signs.assign(signs.begin(), signs.end());
  out.vertices = c.vertices_of(3, cell);
  return out;
}

bool face_has(const Complex& c, std::uint32_t f, std::uint32_t v) {
  for (auto e : c.boundary(2).ids(f)) {
    const auto ends = c.edge(e);
    if (ends[0] == v || ends[1] == v) return true;
  }
  return false;
}

// Chain-positive tetrahedra of a cell (before kChainToGeometric), or nothing when coning from
// its first vertex does not give positive tetrahedra.
std::optional<std::vector<Tet>> cone_cell(const CellContext& ctx, const CellFaces& cf,
                                          const Eigen::Vector4d& normal, double min_volume) {
  const auto& p = ctx.c.positions();
  const std::uint32_t apex =
      *std::min_element(cf.vertices.begin(), cf.vertices.end(),
                        [&](auto a, auto b) { return ctx.key[a] < ctx.key[b]; });
  std::vector<Tet> tets;
  for (std::size_t j = 0; j < cf.faces.size(); ++j) {
    const auto f = cf.faces[j];
    if (face_has(ctx.c, f, apex)) {
      if (!ctx.ft.convex[f]) return std::nullopt;  // its ear clipping is not the fan from apex
      continue;
    }
    for (const auto& t : ctx.ft.triangles[f]) {
      Tet tet{apex, t[0], t[1], t[2]};
      tet = outward(tet, cf.signs[j]);
      const Eigen::Vector4d a = p.col(tet[0]);
      const double v = det4(normal, p.col(tet[1]) - a, p.col(tet[2]) - a, p.col(tet[3]) - a) / 6.0;
      if (!(v > min_volume)) return std::nullopt;
      tets.push_back(tet);
    }
  }
  return tets;
}

// The 5-tetrahedron split of a combinatorial cube whose face diagonals all join vertices of one
// colour class of the cube's own 2-colouring; nothing otherwise.
std::optional<std::vector<Tet>> split_cube(const CellContext& ctx, const CellFaces& cf) {
  if (cf.faces.size() != 6 || cf.vertices.size() != 8) return std::nullopt;
  for (auto f : cf.faces)
    if (ctx.c.boundary(2).row_size(f) != 4) return std::nullopt;
  // Neighbours within the cell.
  auto local = [&](std::uint32_t v) {
    return static_cast<int>(std::lower_bound(cf.vertices.begin(), cf.vertices.end(), v) -
                            cf.vertices.begin());
  };
  std::array<std::vector<int>, 8> nbr;
  for (auto f : cf.faces) {
    const auto cyc = ctx.c.face_cycle(f);
    for (std::size_t k = 0; k < 4; ++k) {
      const int a = local(cyc[k]), b = local(cyc[(k + 1) % 4]);
      if (std::find(nbr[a].begin(), nbr[a].end(), b) == nbr[a].end()) nbr[a].push_back(b);
      if (std::find(nbr[b].begin(), nbr[b].end(), a) == nbr[b].end()) nbr[b].push_back(a);
    }
  }
  for (const auto& nb : nbr)
    if (nb.size() != 3) return std::nullopt;
  std::array<int, 8> color;
  color.fill(-1);
  color[0] = 0;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    for (int w : nbr[v]) {
      if (color[w] < 0) {
        color[w] = 1 - color[v];
        stack.push_back(w);
      } else if (color[w] == color[v]) {
        return std::nullopt;
      }
    }
  }
  // The diagonal of each face: the vertex pair shared by its two triangles.
  int central = -1;
  for (auto f : cf.faces) {
    const auto& tris = ctx.ft.triangles[f];
    if (tris.size() != 2) return std::nullopt;
    int shared_color = -1, shared = 0;
    for (auto a : tris[0])
      for (auto b : tris[1])
        if (a == b) {
          ++shared;
          const int col = color[local(a)];
          if (shared_color >= 0 && shared_color != col) return std::nullopt;
          shared_color = col;
        }
    if (shared != 2) return std::nullopt;
    if (central >= 0 && central != shared_color) return std::nullopt;
    central = shared_color;
  }
  // Corner tetrahedra: each vertex y of the other class with its three neighbours. Orient them by
  // a boundary triangle at y (a face triangle containing y, coned from the fourth vertex).
  std::vector<Tet> tets;
  Tri central_face{};
  std::uint32_t central_apex = 0;
  for (int y = 0; y < 8; ++y) {
    if (color[y] == central) continue;
    const std::uint32_t vy = cf.vertices[static_cast<std::size_t>(y)];
    bool done = false;
    for (std::size_t j = 0; j < cf.faces.size() && !done; ++j) {
      for (const auto& t : ctx.ft.triangles[cf.faces[j]]) {
        if (std::find(t.begin(), t.end(), vy) == t.end()) continue;
        // The fourth vertex: the neighbour of y not on this triangle.
        std::uint32_t fourth = 0;
        for (int w : nbr[y]) {
          const auto vw = cf.vertices[static_cast<std::size_t>(w)];
          if (std::find(t.begin(), t.end(), vw) == t.end()) fourth = vw;
        }
        Tet tet{fourth, t[0], t[1], t[2]};
        if (cf.signs[j] < 0) std::swap(tet[2], tet[3]);  // now chain-positive
        if (tets.empty()) {
          // The face opposite y is a face of the central tetrahedron, with opposite orientation.
          const int iy = static_cast<int>(std::find(tet.begin(), tet.end(), vy) - tet.begin());
          central_face = opposite_face(tet, iy);
          std::swap(central_face[1], central_face[2]);
          for (int w = 0; w < 8; ++w) {
            const auto vw = cf.vertices[static_cast<std::size_t>(w)];
            if (color[w] == central &&
                std::find(central_face.begin(), central_face.end(), vw) == central_face.end())
              central_apex = vw;
          }
        }
        tets.push_back(outward(tet, 1));
        done = true;
        break;
      }
    }
    if (!done) return std::nullopt;
  }
  tets.push_back(outward({central_apex, central_face[0], central_face[1], central_face[2]}, 1));
  return tets;
}

std::string lower(std::string s) {
  for (auto& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

double turn(double angle) {
  double t = angle / (2.0 * std::numbers::pi);
  if (t < 0.0) t += 1.0;
  return t;
}

}  // namespace

double TetMesh::tet_volume(std::size_t t) const {
  return std::abs(tet_signed_volume(t));
}

double TetMesh::tet_signed_volume(std::size_t t) const {
  const Eigen::Vector4d a = corner_position(t, 0);
  return det4(tet_normal(t), corner_position(t, 1) - a, corner_position(t, 2) - a,
              corner_position(t, 3) - a) /
         6.0;
}

std::optional<UvwMapping> uvw_mapping_for_spec(const std::string& spec) {
  const std::string s = lower(spec);
  const auto colon = s.find(':');
  if (colon == std::string::npos) return std::nullopt;
  const std::string head = s.substr(0, colon);
  UvwMapping m;
  if (head == "glome")
    m.kind = UvwMapping::Kind::Glome;
  else if (head == "spherinder")
    m.kind = UvwMapping::Kind::Spherinder;
  else if (head == "duocylinder")
    m.kind = UvwMapping::Kind::Duocylinder;
  else
    return std::nullopt;
  const std::string args = s.substr(colon + 1);
  try {
    std::size_t used = 0;
    m.radius = std::stod(args, &used);
    if (used >= args.size() || args[used] != ',') throw InputError("");
  } catch (const std::exception&) {
    throw InputError("model spec " + quote_user_text(spec) + ": expected " + head + ":R,N");
  }
  if (!(m.radius > 0.0) || !std::isfinite(m.radius))
    throw InputError("model spec " + quote_user_text(spec) + ": the radius must be positive");
  return m;
}

std::optional<Eigen::Vector3d> parametric_uvw(const UvwMapping& m, const Eigen::Vector4d& x,
                                              const Eigen::Vector4d& n,
                                              std::array<bool, 3>& periodic) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double r = m.radius;
  const double tiny = tol::uvw_axis_rel * r;  // an angle about an axis is undefined on the axis
  switch (m.kind) {
    case UvwMapping::Kind::CellBox:
      return std::nullopt;
    case UvwMapping::Kind::Glome: {
      periodic = {true, true, false};
      const double rxy = std::hypot(x(0), x(1)), rzw = std::hypot(x(2), x(3));
      const double a = std::atan2(rzw, rxy);
      return Eigen::Vector3d(rxy > tiny ? turn(std::atan2(x(1), x(0))) : nan,
                             rzw > tiny ? turn(std::atan2(x(3), x(2))) : nan,
                             a / (std::numbers::pi / 2.0));
    }
    case UvwMapping::Kind::Spherinder: {
      if (std::abs(n(3)) > 0.5) return std::nullopt;  // the caps have no sphere parameters
      periodic = {true, false, false};
      const double rxy = std::hypot(x(0), x(1));
      const double polar = std::atan2(rxy, x(2));
      return Eigen::Vector3d(rxy > tiny ? turn(std::atan2(x(1), x(0))) : nan,
                             polar / std::numbers::pi, (x(3) / r + 1.0) / 2.0);
    }
    case UvwMapping::Kind::Duocylinder: {
      periodic = {true, false, false};
      if (std::hypot(n(0), n(1)) >= std::hypot(n(2), n(3)))
        return Eigen::Vector3d(turn(std::atan2(x(1), x(0))), (x(2) / r + 1.0) / 2.0,
                               (x(3) / r + 1.0) / 2.0);
      return Eigen::Vector3d(turn(std::atan2(x(3), x(2))), (x(0) / r + 1.0) / 2.0,
                             (x(1) / r + 1.0) / 2.0);
    }
  }
  return std::nullopt;
}

std::vector<std::vector<std::array<std::uint32_t, 3>>> triangulate_faces(const Complex& complex) {
  if (complex.top_rank() < 2) return {};
  return triangulate_all(complex, vertex_order(complex)).triangles;
}

bool TetMesh::has_edge_index() const {
  if (tet_edges.size() != tets.size()) return false;
  for (std::size_t t = 0; t < tets.size(); ++t)
    for (std::size_t k = 0; k < 6; ++k) {
      const std::uint32_t e = tet_edges[t][k];
      if (e >= edges.size()) return false;
      const std::uint32_t a = tets[t][static_cast<std::size_t>(kTetEdgeCorners[k][0])];
      const std::uint32_t b = tets[t][static_cast<std::size_t>(kTetEdgeCorners[k][1])];
      if (edges[e][0] != std::min(a, b) || edges[e][1] != std::max(a, b)) return false;
    }
  if (block_first.empty() || block_first.front() != 0 || block_first.back() != tets.size() ||
      block_vertex_first.size() != block_first.size() || tet_cell.size() != tets.size())
    return false;
  for (std::size_t b = 0; b + 1 < block_first.size(); ++b) {
    std::vector<std::uint32_t> want, have;
    for (std::uint32_t t = block_first[b]; t < block_first[b + 1]; ++t) {
      if (tet_cell[t] != tet_cell[block_first[b]]) return false;
      want.insert(want.end(), tets[t].begin(), tets[t].end());
    }
    std::sort(want.begin(), want.end());
    want.erase(std::unique(want.begin(), want.end()), want.end());
    have.assign(block_vertices.begin() + block_vertex_first[b],
                block_vertices.begin() + block_vertex_first[b + 1]);
    std::sort(have.begin(), have.end());
    if (want != have) return false;
  }
  return true;
}

void index_tet_edges(TetMesh& mesh) {
  mesh.edges.clear();
  mesh.tet_edges.resize(mesh.tets.size());
  std::unordered_map<std::uint64_t, std::uint32_t> id;
  id.reserve(2 * mesh.tets.size() + 16);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (std::size_t k = 0; k < 6; ++k) {
      const std::uint32_t a =
          mesh.tets[t][static_cast<std::size_t>(TetMesh::kTetEdgeCorners[k][0])];
      const std::uint32_t b =
          mesh.tets[t][static_cast<std::size_t>(TetMesh::kTetEdgeCorners[k][1])];
      const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
      const auto [it, fresh] =
          id.emplace((std::uint64_t{lo} << 32) | hi, static_cast<std::uint32_t>(mesh.edges.size()));
      if (fresh) mesh.edges.push_back({lo, hi});
      mesh.tet_edges[t][k] = it->second;
    }
  mesh.block_first.assign(1, 0);
  mesh.block_vertex_first.assign(1, 0);
  mesh.block_vertices.clear();
  // (without a cell per tetrahedron, every tetrahedron is a block)
  const bool cells = mesh.tet_cell.size() == mesh.tets.size();
  std::size_t t0 = 0;
  while (t0 < mesh.tets.size()) {
    std::size_t t1 = t0 + 1;
    while (cells && t1 < mesh.tets.size() && mesh.tet_cell[t1] == mesh.tet_cell[t0]) ++t1;
    const std::size_t v0 = mesh.block_vertices.size();
    for (std::size_t t = t0; t < t1; ++t)
      mesh.block_vertices.insert(mesh.block_vertices.end(), mesh.tets[t].begin(),
                                 mesh.tets[t].end());
    std::sort(mesh.block_vertices.begin() + static_cast<std::ptrdiff_t>(v0),
              mesh.block_vertices.end());
    mesh.block_vertices.erase(
        std::unique(mesh.block_vertices.begin() + static_cast<std::ptrdiff_t>(v0),
                    mesh.block_vertices.end()),
        mesh.block_vertices.end());
    mesh.block_first.push_back(static_cast<std::uint32_t>(t1));
    mesh.block_vertex_first.push_back(static_cast<std::uint32_t>(mesh.block_vertices.size()));
    t0 = t1;
  }
}

TetMesh tetrahedralize_cells(const Complex& complex, const TetOptions& options,
                             const NonConvexCellMesher& nonconvex, TetStats* stats) {
  if (complex.ambient_dim() != 4)
    throw InputError("tetrahedralize: the model lives in R^" +
                     std::to_string(complex.ambient_dim()) +
                     "; only 4D models have tetrahedral cells");
  if (complex.top_rank() < 3 || complex.count(3) == 0)
    throw InputError("tetrahedralize: the model has no 3-cells");
  if (!complex.has_facet_normals())
    throw InputError("tetrahedralize: the model has no outward facet normals (build it oriented)");
  check_tables(complex);
  TetStats local_stats;
  TetStats& st = stats ? *stats : local_stats;
  st = {};

  const auto key = vertex_order(complex);
  const FaceTriangulation ft = triangulate_all(complex, key);
  const CellContext ctx{complex, ft, key};
  const auto& p = complex.positions();

  TetMesh mesh;
  const std::size_t nc = complex.count(3);
  mesh.cell_normals = complex.facet_normals();
  std::vector<Eigen::Vector4d> extra_points;  // Steiner points
  const auto nv = static_cast<std::uint32_t>(complex.count(0));

  for (std::uint32_t cell = 0; cell < nc; ++cell) {
    const CellFaces cf = cell_faces(complex, cell);
    const Eigen::Vector4d normal = mesh.cell_normals.col(cell);
    double diam2 = 0.0;
    for (auto v : cf.vertices)
      diam2 = std::max(diam2, (p.col(v) - p.col(cf.vertices[0])).squaredNorm());
    const double min_volume = tol::degenerate_rel * std::pow(diam2, 1.5);

    std::optional<std::vector<Tet>> tets;
    if (options.five_tet_cubes) {
      tets = split_cube(ctx, cf);
      if (tets) {
        // Geometric check: a warped hexahedron may not split this way.
        for (const auto& t : *tets) {
          const Eigen::Vector4d a = p.col(t[0]);
          if (!(det4(normal, p.col(t[1]) - a, p.col(t[2]) - a, p.col(t[3]) - a) / 6.0 >
                min_volume)) {
            tets.reset();
            break;
          }
        }
        if (tets) ++st.cube_split_cells;
      }
    }
    if (!tets) {
      tets = cone_cell(ctx, cf, normal, min_volume);
      if (tets) ++st.coned_cells;
    }
    if (!tets && !nonconvex) {
      ++st.skipped_cells;  // non-convex, and no mesher for it
      continue;
    }
    if (!tets) {
      // Non-convex: the mesher (TetGen in tetrahedralize) on the cell's boundary triangles.
      std::vector<Tri> boundary;
      for (std::size_t j = 0; j < cf.faces.size(); ++j)
        for (auto t : ft.triangles[cf.faces[j]]) {
          if (cf.signs[j] < 0) std::swap(t[1], t[2]);
          boundary.push_back(t);
        }
      const CellTets result = nonconvex(complex, cell, cf.vertices, boundary, normal);
      std::vector<std::uint32_t> ids = cf.vertices;
      for (const auto& sp : result.steiner) {
        ids.push_back(nv + static_cast<std::uint32_t>(extra_points.size()));
        extra_points.push_back(sp);
      }
      auto pos = [&](std::uint32_t id) -> Eigen::Vector4d {
        return id < nv ? Eigen::Vector4d(p.col(id)) : extra_points[id - nv];
      };
      tets.emplace();
      for (const auto& lt : result.tets) {
        Tet t{ids[lt[0]], ids[lt[1]], ids[lt[2]], ids[lt[3]]};
        const Eigen::Vector4d a = pos(t[0]);
        if (det4(normal, pos(t[1]) - a, pos(t[2]) - a, pos(t[3]) - a) < 0.0) std::swap(t[2], t[3]);
        tets->push_back(t);
      }
      ++st.tetgen_cells;
      st.steiner_points += result.steiner.size();
    }
    for (const auto& t : *tets) {
      mesh.tets.push_back(t);
      mesh.tet_cell.push_back(cell);
    }
  }

  mesh.positions.resize(4, static_cast<Eigen::Index>(nv + extra_points.size()));
  mesh.positions.leftCols(nv) = p;
  for (std::size_t i = 0; i < extra_points.size(); ++i)
    mesh.positions.col(static_cast<Eigen::Index>(nv + i)) = extra_points[i];

  // UVW: the parametric mapping where every corner of the cell has parameters, else the cell
  // box. Tetrahedra are stored grouped by cell, in cell order.
  mesh.corner_uvw.resize(3, static_cast<Eigen::Index>(4 * mesh.tets.size()));
  std::vector<FacetTextureMap> box_maps;
  std::size_t t0 = 0;
  while (t0 < mesh.tets.size()) {
    const std::uint32_t cell = mesh.tet_cell[t0];
    std::size_t t1 = t0;
    while (t1 < mesh.tets.size() && mesh.tet_cell[t1] == cell) ++t1;
    const Eigen::Vector4d normal = mesh.cell_normals.col(cell);
    bool parametric = options.uvw.kind != UvwMapping::Kind::CellBox;
    std::array<bool, 3> periodic{false, false, false};
    if (parametric) {
      for (std::size_t t = t0; t < t1 && parametric; ++t)
        for (int k = 0; k < 4; ++k) {
          const auto uvw =
              parametric_uvw(options.uvw, mesh.corner_position(t, k), normal, periodic);
          if (!uvw) {
            parametric = false;
            break;
          }
          mesh.corner_uvw.col(static_cast<Eigen::Index>(4 * t + k)) = *uvw;
        }
    }
    if (parametric) {
      // Per tetrahedron: undefined angles (on an axis) take the mean of the others, periodic
      // components are unwrapped to within half a turn of the first defined corner.
      for (std::size_t t = t0; t < t1; ++t) {
        auto block = mesh.corner_uvw.middleCols(static_cast<Eigen::Index>(4 * t), 4);
        for (int comp = 0; comp < 3; ++comp) {
          double ref = std::numeric_limits<double>::quiet_NaN();
          for (int k = 0; k < 4; ++k)
            if (!std::isnan(block(comp, k))) {
              ref = block(comp, k);
              break;
            }
          if (std::isnan(ref)) ref = 0.0;
          double sum = 0.0;
          int defined = 0;
          for (int k = 0; k < 4; ++k) {
            double& u = block(comp, k);
            if (std::isnan(u)) continue;
            if (periodic[static_cast<std::size_t>(comp)]) u -= std::round(u - ref);
            sum += u;
            ++defined;
          }
          for (int k = 0; k < 4; ++k)
            if (std::isnan(block(comp, k))) block(comp, k) = defined ? sum / defined : ref;
        }
      }
    } else {
      // The same box map the CW section's exporters use (section/uvw.hpp).
      if (box_maps.empty()) box_maps = facet_texture_maps(complex);
      const Eigen::Matrix<double, 3, 4> to_uvw =
          box_maps[cell].to_uvw;  // fixed size: no allocation
      const Eigen::Vector4d origin = box_maps[cell].origin;
      for (std::size_t t = t0; t < t1; ++t)
        for (int k = 0; k < 4; ++k)
          mesh.corner_uvw.col(static_cast<Eigen::Index>(4 * t + k)) =
              to_uvw * (mesh.corner_position(t, k) - origin);
    }
    t0 = t1;
  }
  index_tet_edges(mesh);
  return mesh;
}

}  // namespace cw4d
