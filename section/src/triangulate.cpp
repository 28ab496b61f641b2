#include "cw4d/section/triangulate.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>

#include "cw4d/section/section.hpp"

namespace cw4d {

std::vector<Triangle> fan_triangulate(const Complex& complex) {
  std::vector<Triangle> out;
  if (complex.top_rank() < 2) return out;
  for (std::uint32_t f = 0; f < complex.count(2); ++f) {
    auto cyc = complex.face_cycle(f);
    for (std::size_t k = 1; k + 1 < cyc.size(); ++k)
      out.push_back({{cyc[0], cyc[k], cyc[k + 1]}, f});
  }
  return out;
}

namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

Vec3 position3(const Complex& c, std::uint32_t v) {
  Vec3 p = Vec3::Zero();
  const auto col = c.positions().col(v);
  for (Eigen::Index i = 0; i < std::min<Eigen::Index>(3, col.size()); ++i) p[i] = col[i];
  return p;
}

// Newell's area vector of a closed loop (twice the area, along the loop's normal).
Vec3 area_vector(const Complex& c, const std::vector<std::uint32_t>& loop) {
  Vec3 a = Vec3::Zero();
  for (std::size_t i = 0; i < loop.size(); ++i)
    a += position3(c, loop[i]).cross(position3(c, loop[(i + 1) % loop.size()]));
  return a;
}

// Coordinates in the plane orthogonal to `normal`, dropping its largest component and
// ordering the other two so that loops counter-clockwise about `normal` stay counter-clockwise.
struct Projection {
  int u = 0, v = 1;
  explicit Projection(const Vec3& normal) {
    int a = 0;
    normal.cwiseAbs().maxCoeff(&a);
    u = (a + 1) % 3;
    v = (a + 2) % 3;
    if (normal[a] < 0) std::swap(u, v);
  }
  Vec2 operator()(const Vec3& p) const { return {p[u], p[v]}; }
};

double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

// Closed segments ab and cd meet (touching counts).
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
               o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
         (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
}

// p in the closed triangle abc (counter-clockwise).
bool in_triangle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& p) {
  return orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0;
}

bool loop_is_simple(const std::vector<Vec2>& pts, const std::vector<std::uint32_t>& ids) {
  const std::size_t n = pts.size();
  if (n < 3) return false;
  std::vector<std::uint32_t> sorted = ids;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 &a = pts[i], &b = pts[(i + 1) % n], &c = pts[(i + 2) % n];
    // A spike: the boundary turns back on itself.
    if (orient(a, b, c) == 0 && (b - a).dot(c - b) < 0) return false;
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      if (segments_meet(a, b, pts[j], pts[(j + 1) % n])) return false;
    }
  }
  return true;
}

bool loop_is_convex(const std::vector<Vec2>& pts) {
  const std::size_t n = pts.size();
  for (std::size_t i = 0; i < n; ++i)
    if (orient(pts[i], pts[(i + 1) % n], pts[(i + 2) % n]) < 0) return false;
  return true;
}

// Ear clipping of a counter-clockwise, weakly simple polygon (bridged holes repeat vertices).
// Appends triangles of vertex ids; returns false, with the unclipped rest left in `poly`, when no
// ear can be found (the caller fans the rest).
bool clip_ears(std::vector<Vec2>& pts, std::vector<std::uint32_t>& ids, std::uint32_t face,
               std::vector<Triangle>& out) {
  assert(pts.size() == ids.size());
  [[maybe_unused]] const std::size_t corners = pts.size(), before = out.size();
  while (pts.size() > 3) {
    const std::size_t n = pts.size();
    std::vector<std::size_t> reflex;
    for (std::size_t i = 0; i < n; ++i)
      if (orient(pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]) <= 0) reflex.push_back(i);
    std::size_t ear = n;
    for (std::size_t pass = 0; pass < 2 && ear == n; ++pass) {
      for (std::size_t i = 0; i < n && ear == n; ++i) {
        const std::size_t ip = (i + n - 1) % n, in = (i + 1) % n;
        const double o = orient(pts[ip], pts[i], pts[in]);
        // First pass: proper ears. Second: straight angles (a zero-area triangle keeps the
        // vertex, so the mesh stays watertight with the neighbouring faces).
        if (pass == 0 ? o <= 0 : !(o == 0 && (pts[i] - pts[ip]).dot(pts[in] - pts[i]) > 0))
          continue;
        bool blocked = false;
        if (pass == 0)
          for (std::size_t j : reflex) {
            if (j == ip || j == i || j == in) continue;
            const Vec2& p = pts[j];
            if (p == pts[ip] || p == pts[i] || p == pts[in]) continue;  // a bridge's copy
            if (in_triangle(pts[ip], pts[i], pts[in], p)) {
              blocked = true;
              break;
            }
          }
        if (!blocked) ear = i;
      }
    }
    if (ear == n) return false;
    const std::size_t ip = (ear + n - 1) % n, in = (ear + 1) % n;
    out.push_back({{ids[ip], ids[ear], ids[in]}, face});
    pts.erase(pts.begin() + static_cast<std::ptrdiff_t>(ear));
    ids.erase(ids.begin() + static_cast<std::ptrdiff_t>(ear));
  }
  if (pts.size() == 3) out.push_back({{ids[0], ids[1], ids[2]}, face});
  assert(corners < 3 || out.size() - before == corners - 2);  // a k-gon gives k - 2 triangles
  pts.clear();
  ids.clear();
  return true;
}

// Splices a clockwise hole into a counter-clockwise polygon through a bridge from the hole's
// rightmost vertex to the nearest polygon vertex it can see. Returns false when none is visible.
bool bridge_hole(std::vector<Vec2>& pts, std::vector<std::uint32_t>& ids,
                 const std::vector<Vec2>& hpts, const std::vector<std::uint32_t>& hids,
                 const std::vector<std::vector<Vec2>>& others) {
  std::size_t m = 0;
  for (std::size_t i = 1; i < hpts.size(); ++i)
    if (hpts[i].x() > hpts[m].x() || (hpts[i].x() == hpts[m].x() && hpts[i].y() < hpts[m].y()))
      m = i;
  const Vec2 M = hpts[m];
  auto blocked = [&](const Vec2& P, const std::vector<Vec2>& loop) {
    for (std::size_t j = 0; j < loop.size(); ++j) {
      const Vec2 &a = loop[j], &b = loop[(j + 1) % loop.size()];
      if (a == M || b == M || a == P || b == P) continue;
      if (segments_meet(M, P, a, b)) return true;
    }
    return false;
  };
  std::size_t best = pts.size();
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double d = (pts[i] - M).squaredNorm();
    if (d >= best_d) continue;
    // The bridge must leave the polygon's vertex into its interior (inside the vertex's angle).
    const std::size_t n = pts.size();
    const Vec2 &a = pts[(i + n - 1) % n], &p = pts[i], &b = pts[(i + 1) % n];
    const bool convex = orient(a, p, b) > 0;
    const bool inside = convex ? orient(a, p, M) > 0 && orient(p, b, M) > 0
                               : !(orient(a, p, M) <= 0 && orient(p, b, M) <= 0);
    if (!inside) continue;
    if (blocked(p, pts) || blocked(p, hpts)) continue;
    bool hidden = false;
    for (const auto& o : others) hidden = hidden || blocked(p, o);
    if (hidden) continue;
    best = i;
    best_d = d;
  }
  if (best == pts.size()) return false;
  std::vector<Vec2> np(pts.begin(), pts.begin() + static_cast<std::ptrdiff_t>(best) + 1);
  std::vector<std::uint32_t> ni(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(best) + 1);
  for (std::size_t k = 0; k <= hpts.size(); ++k) {
    np.push_back(hpts[(m + k) % hpts.size()]);
    ni.push_back(hids[(m + k) % hids.size()]);
  }
  np.insert(np.end(), pts.begin() + static_cast<std::ptrdiff_t>(best), pts.end());
  ni.insert(ni.end(), ids.begin() + static_cast<std::ptrdiff_t>(best), ids.end());
  assert(np.size() == pts.size() + hpts.size() + 2 && ni.size() == np.size());
  pts = std::move(np);
  ids = std::move(ni);
  return true;
}

void fan(const std::vector<std::uint32_t>& cyc, std::uint32_t face, std::vector<Triangle>& out) {
  for (std::size_t k = 1; k + 1 < cyc.size(); ++k)
    out.push_back({{cyc[0], cyc[k], cyc[k + 1]}, face});
}

// Point-in-polygon by the crossing rule (p strictly inside; boundary points count as outside).
bool inside_loop(const std::vector<Vec2>& loop, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
    const Vec2 &a = loop[i], &b = loop[j];
    if (orient(a, b, p) == 0 && on_segment(a, b, p)) return false;
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

double signed_area(const std::vector<Vec2>& pts) {
  double a = 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec2 &p = pts[i], &q = pts[(i + 1) % pts.size()];
    a += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * a;
}

}  // namespace

bool ear_clip_polygon(std::vector<Vec2> points, std::vector<std::uint32_t> ids, std::uint32_t face,
                      std::vector<Triangle>& out) {
  if (points.size() != ids.size() || points.size() < 3) return false;
  // The clipper wants a counter-clockwise loop: mirror a clockwise one. Its triangles list the
  // ids in loop order, so they keep the loop's orientation either way.
  if (signed_area(points) < 0.0)
    for (Vec2& p : points) p.y() = -p.y();
  const std::size_t before = out.size();
  if (!clip_ears(points, ids, face, out)) {
    out.resize(before);
    return false;
  }
  return true;
}

bool is_simple_face(const Complex& complex, std::uint32_t f) {
  const auto cyc = complex.face_cycle(f);
  const Vec3 a = area_vector(complex, cyc);
  if (!(a.norm() > 0.0)) return false;
  const Projection proj(a);
  std::vector<Vec2> pts;
  for (auto v : cyc) pts.push_back(proj(position3(complex, v)));
  return loop_is_simple(pts, cyc);
}

std::vector<Triangle> ear_clip_triangulate(const Complex& complex,
                                           const std::vector<std::vector<std::uint32_t>>& holes) {
  std::vector<Triangle> out;
  if (complex.top_rank() < 2) return out;
  const std::uint32_t nf = static_cast<std::uint32_t>(complex.count(2));
  assert(holes.empty() || holes.size() == nf);
  std::vector<char> is_hole(nf, 0);
  for (const auto& list : holes)
    for (auto h : list) {
      assert(h < nf);
      is_hole[h] = 1;
    }
  for (std::uint32_t f = 0; f < nf; ++f) {
    if (is_hole[f]) continue;
    std::vector<std::uint32_t> ids = complex.face_cycle(f);
    const Vec3 a = area_vector(complex, ids);
    const auto& my_holes = holes.empty() ? std::vector<std::uint32_t>{} : holes[f];
    if (!(a.norm() > 0.0)) {
      fan(ids, f, out);
      continue;
    }
    const Projection proj(a);
    std::vector<Vec2> pts;
    for (auto v : ids) pts.push_back(proj(position3(complex, v)));
    const bool simple = loop_is_simple(pts, ids);
    if (my_holes.empty() && simple && loop_is_convex(pts)) {
      fan(ids, f, out);
      continue;
    }
    // Holes, each a simple loop, clockwise in this projection.
    std::vector<std::vector<Vec2>> hpts;
    std::vector<std::vector<std::uint32_t>> hids;
    bool usable = simple;
    for (auto h : my_holes) {
      hids.push_back(complex.face_cycle(h));
      auto& hp = hpts.emplace_back();
      for (auto v : hids.back()) hp.push_back(proj(position3(complex, v)));
      usable = usable && loop_is_simple(hp, hids.back());
    }
    if (usable) {
      // Bridge the holes from right to left (by their rightmost x).
      std::vector<std::size_t> order(hpts.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      auto max_x = [&](std::size_t i) {
        double m = -std::numeric_limits<double>::infinity();
        for (const auto& p : hpts[i]) m = std::max(m, p.x());
        return m;
      };
      std::stable_sort(order.begin(), order.end(),
                       [&](std::size_t x, std::size_t y) { return max_x(x) > max_x(y); });
      for (std::size_t k = 0; k < order.size() && usable; ++k) {
        std::vector<std::vector<Vec2>> rest;
        for (std::size_t j = k + 1; j < order.size(); ++j) rest.push_back(hpts[order[j]]);
        usable = bridge_hole(pts, ids, hpts[order[k]], hids[order[k]], rest);
      }
    }
    if (usable) {
      // Each bridge adds two corners (the copies of its ends): the clipper then gives
      // k + sum(k_i) + 2h - 2 triangles for a k-gon with h holes of k_i corners.
      [[maybe_unused]] std::size_t corners = complex.boundary(2).row_size(f);
      for (const auto& h : hids) corners += h.size() + 2;
      assert(pts.size() == corners && ids.size() == corners);
      const std::size_t before = out.size();
      if (clip_ears(pts, ids, f, out)) continue;
      out.resize(before);
    }
    // Not a simple polygon (or one the clipper could not finish): the signed fan of the face
    // and of each hole sums to the right region.
    fan(complex.face_cycle(f), f, out);
    for (auto h : my_holes) fan(complex.face_cycle(h), f, out);
  }
  return out;
}

std::vector<std::vector<std::uint32_t>> section_holes(const Section& section) {
  const Complex& c = section.complex;
  const std::uint32_t nf = c.top_rank() >= 2 ? static_cast<std::uint32_t>(c.count(2)) : 0;
  std::vector<std::vector<std::uint32_t>> holes(nf);
  if (section.source.size() < 3 || section.source[2].size() != nf) return holes;
  // Cell ids repeat between the objects of a scene's section: a cell is (object, cell id).
  const bool objects = section.object_of_face.size() == nf;
  std::map<std::uint64_t, std::vector<std::uint32_t>> by_cell;
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint64_t object = objects ? section.object_of_face[f] : 0u;
    by_cell[object << 32 | section.source[2][f]].push_back(f);
  }
  for (const auto& [cell, faces] : by_cell) {
    if (faces.size() < 2) continue;
    std::vector<Vec3> area;
    std::size_t largest = 0;
    for (std::size_t i = 0; i < faces.size(); ++i) {
      area.push_back(area_vector(c, c.face_cycle(faces[i])));
      if (area[i].norm() > area[largest].norm()) largest = i;
    }
    const Vec3 ref = area[largest];
    if (!(ref.norm() > 0.0)) continue;
    const Projection proj(ref);
    std::vector<std::vector<Vec2>> loops;
    for (auto f : faces) {
      auto& l = loops.emplace_back();
      for (auto v : c.face_cycle(f)) l.push_back(proj(position3(c, v)));
    }
    for (std::size_t h = 0; h < faces.size(); ++h) {
      if (!(area[h].dot(ref) < 0.0)) continue;
      std::size_t best = faces.size();
      for (std::size_t o = 0; o < faces.size(); ++o) {
        if (!(area[o].dot(ref) > 0.0)) continue;
        bool contains = true;
        for (const Vec2& p : loops[h]) contains = contains && inside_loop(loops[o], p);
        if (contains && (best == faces.size() || area[o].norm() < area[best].norm())) best = o;
      }
      if (best != faces.size()) holes[faces[best]].push_back(faces[h]);
    }
  }
  return holes;
}

std::vector<Triangle> triangulate_section(const Section& section) {
  return ear_clip_triangulate(section.complex, section_holes(section));
}

}  // namespace cw4d
