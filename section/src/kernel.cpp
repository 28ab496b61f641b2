#include "cw4d/section/slicer.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <thread>
#include <unordered_map>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/fork_join.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "general.hpp"
#include "slicer_detail.hpp"

namespace cw4d {

// --- the R^4 kernel -----------------------------------------------------------------------

namespace {

// Lists every nonzero byte counts[x] of [b, e) as (x << 8) | counts[x] in increasing x, zeroing
// those bytes (eight at a time); returns the new end of the list (the entry at the end may be
// written: the list needs room for one more). The work on the listed
// elements is then a plain loop whose pointers and counters stay in registers (its byte stores
// would otherwise make the compiler reload everything a visiting callback captures).
inline std::uint64_t* list_counts(std::uint8_t* counts, std::uint32_t b, std::uint32_t e,
                                  std::uint64_t* list) {
  std::uint32_t x = b;
  for (; x < e && (x & 7u); ++x)
    if (counts[x]) *list++ = (std::uint64_t{x} << 8) | counts[x], counts[x] = 0;
  for (; x + 8 <= e; x += 8) {
    std::uint64_t w;
    std::memcpy(&w, counts + x, 8);
    if (!w) continue;
    std::memset(counts + x, 0, 8);
    // Every byte of the word written, the list advanced past the nonzero ones: no branch per
    // byte (whether a face or cell is cut is unpredictable).
    for (std::uint32_t i = 0; i < 8; ++i) {
      const std::uint64_t byte = (w >> (8 * i)) & 0xffu;
      *list = (std::uint64_t{x + i} << 8) | byte;
      list += byte != 0;
    }
  }
  for (; x < e; ++x)
    if (counts[x]) *list++ = (std::uint64_t{x} << 8) | counts[x], counts[x] = 0;
  return list;
}

// The polygon of a cut cell of at most W faces (faces[i] with sign signs[i] in the cell), in
// registers at a fixed width: each cut face (face_edge[f], its section edge, or no_index) is a
// step, forward (edge_row's tail to head) when the face's sign in the cell is -1; the loop is
// followed from the smallest tail and written to ids/signs (up to W entries; *added of them
// are the polygon's). False when the steps are not one loop through every step of at least
// three (a pinch, an open chain, several loops): the generic gathering decides those.
template <int W>
inline bool chain_fixed(const std::uint32_t* faces, const std::int8_t* signs, std::uint32_t nfaces,
                        const std::uint32_t* face_edge, const std::uint32_t* edge_row,
                        std::uint32_t* ids, std::int8_t* out_signs, std::uint32_t* added) {
  constexpr std::uint32_t kFlip = 0x80000000u, kIndex = 0x7fffffffu;
  constexpr std::uint32_t kNoTail = 0xffffffffu, kNoHead = 0xfffffffeu;  // (no vertex ids)
  std::uint32_t tails[W], heads[W], edge[W];
  std::uint32_t ns = 0;
  for (std::uint32_t i = 0; i < nfaces; ++i) {
    // Masks, not branches (which way a face goes, and whether it is cut, are unpredictable).
    const std::uint32_t se = face_edge[faces[i]];
    const std::uint32_t cut = se != no_index;
    const std::uint32_t r = se & (0u - cut);  // (written to the next slot, kept only when cut)
    const std::uint32_t fwd = static_cast<std::uint32_t>(static_cast<std::int32_t>(signs[i]) >> 31);
    const std::uint32_t a = edge_row[2 * r], b = edge_row[2 * r + 1];
    const std::uint32_t tail = b ^ ((a ^ b) & fwd);
    tails[ns] = tail;
    heads[ns] = a ^ b ^ tail;
    edge[ns] = r | (kFlip & ~fwd);
    ns += cut;
  }
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(W); ++i) {
    tails[i] = i < ns ? tails[i] : kNoTail;
    heads[i] = i < ns ? heads[i] : kNoHead;
    edge[i] = i < ns ? edge[i] : 0;
  }
  std::uint32_t lo = 0;
  bool bad = ns < 3;
  for (std::uint32_t i = 1; i < static_cast<std::uint32_t>(W); ++i) {
    lo = tails[i] < tails[lo] ? i : lo;
    for (std::uint32_t j = 0; j < i; ++j) bad |= tails[i] == tails[j] && i < ns;  // a pinch
  }
  std::uint32_t next[W];
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(W); ++i) {
    std::uint32_t n = W;
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(W); ++j)
      n = tails[j] == heads[i] ? j : n;
    next[i] = n;
  }
  // Walk W steps from lo (those past the ns-th are written and dropped); one loop through
  // every step returns to lo first after exactly ns steps, each step having a successor.
  std::uint32_t cur = lo, closed = 0;
  for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(W); ++k) {
    ids[k] = edge[cur] & kIndex;
    out_signs[k] = (edge[cur] & kFlip) ? -1 : 1;
    const std::uint32_t n = next[cur];
    const bool live = k < ns;
    bad |= live && n == static_cast<std::uint32_t>(W);  // the chain does not close
    closed = live && closed == 0 && n == lo ? k + 1 : closed;
    cur = n < static_cast<std::uint32_t>(W) ? n : 0;
  }
  *added = ns;
  return !bad && closed == ns;
}
}  // namespace

int Slicer::kernel_slice(const SliceModel& m, const Placement& pl, SliceBuffers& out,
                         bool marked_edges) {
  // A section vertex per crossing edge, a section edge per face with exactly two crossings, a
  // polygon per cell whose section edges form one loop: the buffers the generic gathering
  // writes for such a slice (tested element for element), in the same order, written once.
  // No face gathers its crossings by reading its boundary: each crossing edge hands its section
  // vertex to the faces above it (coface lists carrying the edge's sign in the face), and a face
  // reads its two from one place. Each cut face keeps its section edge's id (face_edge_, reset
  // after the slice) and marks the cells above it; a cut cell reads its own faces' ids (a
  // tetrahedron only those its table names). The per-element counts double as the marks of the
  // faces and cells to visit (zero between slices: cleared when listed, or wholly when the
  // kernel stops half way).
  if (!m.unit_signs_) return -1;  // multiplicities: the generic gathering decides
  start_kernel_buffers(m, pl, out);
  constexpr std::uint32_t kFlip = 0x80000000u, kIndex = 0x7fffffffu;
  const SliceModel::Rank& E = m.ranks_[1];
  const SliceModel::Rank& F = m.ranks_[2];
  const SliceModel::Rank& C = m.ranks_[3];
  const std::uint32_t* const edge_ends = E.ids.data();
  const std::int8_t* const side = side_.data();
  const double* const s = s_.data();
  const SliceModel::CrossingTest needs_general = m.crossing_test(near_parallel_);
  const std::uint32_t* const edge_model = E.model_id.empty() ? nullptr : E.model_id.data();
  const std::uint32_t* const face_model = F.model_id.empty() ? nullptr : F.model_id.data();
  const std::uint32_t* const cell_model = C.model_id.empty() ? nullptr : C.model_id.data();
  const std::size_t nf = F.offsets.size() - 1, nc = C.offsets.size() - 1;
  if (face_mark_.size() < nf) face_mark_.resize(nf, 0);
  if (cell_mark_.size() < nc) cell_mark_.resize(nc, 0);
  if (face_ends_.size() < 2 * nf) face_ends_.resize(2 * nf);
  if (face_edge_.size() < nf) face_edge_.resize(nf, no_index);
  std::uint8_t* const face_count = face_mark_.data();
  std::uint8_t* const cell_count = cell_mark_.data();
  std::uint32_t* const face_ends = face_ends_.data();
  // Cells that are not the tetrahedra of a table each collect their steps (one per cut face,
  // written by the face) in a bucket, so that a cut cell reads only its cut faces' steps, not
  // its whole row. A cell's first cut face places its bucket, with room for its whole row,
  // after the last one placed: the buckets take the cut cells' rows, not the model's.
  const bool buckets = m.tet_vertices_.empty();
  if (buckets && cell_fill_.size() < nc) {
    cell_fill_.resize(nc);
    cell_start_.resize(nc);
  }
  auto stop = [this](int result) {
    std::fill(face_mark_.begin(), face_mark_.end(), 0);
    std::fill(cell_mark_.begin(), cell_mark_.end(), 0);
    std::fill(face_edge_.begin(), face_edge_.end(), no_index);
    return result;
  };
  const SliceModel::Up edge_up = m.up(1), face_up = m.up(2);
  const std::uint32_t* const edge_up_ids = edge_up.ids;
  const std::uint32_t* const face_up_ids = face_up.ids;
  // Rank 1: the crossings, in id order cluster by cluster, each handed to its faces with its
  // coefficient in the face's cut (the kFlip bit: +1). The crossing edges of every touched
  // cluster are listed first, without a branch (the sides are unpredictable), or those a sweep
  // marked; then the outputs are sized once.
  const std::size_t ne = E.count;
  if (crossing_ids_.size() < ne) crossing_ids_.resize(ne);
  std::uint32_t* const list = crossing_ids_.data();
  std::uint32_t count = 0;
  for (auto c : touched_) {
    const std::uint32_t e0 = m.begin_[0][c], e1 = m.begin_[0][c + 1];
    if (marked_edges) {
      visit_marked(mark_[1], e0, e1, [list, &count](std::uint32_t e) {
        list[count++] = e;
        return true;
      });
    } else {
      for (std::uint32_t e = e0; e < e1; ++e) {
        list[count] = e;
        count += side[edge_ends[2 * e]] != side[edge_ends[2 * e + 1]];
      }
    }
  }
  if (count == 0) {
    clear_to_empty(out, m.dim_ - 1);
    section_edge_.clear();
    facet_internal_.clear();
    return 1;
  }
  out.vertex_source.resize(count);
  section_edge_.resize(count);
  std::uint32_t cut_faces_bound = 0;
  {
    VertexSource* const vs = out.vertex_source.data();
    std::uint32_t* const vertex_edge = section_edge_.data();
    for (std::uint32_t v = 0; v < count; ++v) {
      const std::uint32_t e = list[v];
      const std::uint32_t a = edge_ends[2 * e], b = edge_ends[2 * e + 1];
      const double t = s[a] / (s[a] - s[b]);
      if (needs_general(a, b, s[a], s[b], t)) {  // as crossing()
        reason_ = FallbackReason::Weld;
        return stop(0);
      }
      vs[v] = {edge_model ? edge_model[e] : e, 1, t};
      vertex_edge[v] = e;
      // The crossing's coefficient in the edge's cut is +1 when the tail is below; in a face's
      // cut that times the edge's sign there (the coface's top bit: -1).
      const std::uint32_t tail_above = side[a] < 0 ? 0u : kFlip;
      const std::uint32_t j0 = edge_up.begin(e), j1 = edge_up.end(e);
      for (std::uint32_t j = j0; j < j1; ++j) {
        const std::uint32_t up = edge_up_ids[j];
        const std::uint32_t f = up & kIndex;
        const std::uint32_t k = face_count[f];
        face_ends[2 * f + (k & 1u)] = v | ((up & kFlip) ^ tail_above);  // (k >= 2: fails below)
        face_count[f] = static_cast<std::uint8_t>(k < 3 ? k + 1 : 3);
      }
      cut_faces_bound += j1 - j0;
    }
  }
  // Rank 2: a face handed two crossings of opposite coefficients gives the section edge from
  // the one with -1 to the one with +1; it keeps that edge's id for its cells and marks them.
  // (list_counts may write one entry past the listed ones)
  if (face_list_.size() < cut_faces_bound + 1) face_list_.resize(cut_faces_bound + 1);
  std::uint64_t* const faces = face_list_.data();
  std::uint64_t* faces_end = faces;
  for (auto c : touched_)
    faces_end = list_counts(face_count, m.begin_[1][c], m.begin_[1][c + 1], faces_end);
  const std::uint32_t nse = static_cast<std::uint32_t>(faces_end - faces);
  Incidence::Storage edges = out.boundary[0].storage();
  edges.ids.resize(2 * std::size_t{nse});
  edges.signs.resize(2 * std::size_t{nse});
  edges.offsets.resize(std::size_t{nse} + 1);
  out.source[1].resize(nse);
  std::uint32_t cut_cells_bound = 0;  // (cut face, cell) pairs: the polygons' entries
  {
    std::uint32_t* const edge_row = edges.ids.data();
    std::uint32_t* const src = out.source[1].data();
    std::uint32_t* const face_edge = face_edge_.data();
    std::uint32_t* const fill = cell_fill_.data();
    std::uint32_t* const start = cell_start_.data();
    const std::uint32_t* const cell_row = C.offsets.data();
    CellStep* bucket = cell_steps_.data();
    std::size_t room = cell_steps_.size(), placed = 0;
    bool bad = false;
    for (std::uint32_t se = 0; se < nse; ++se) {
      const std::uint64_t item = faces[se];
      const std::uint32_t x = static_cast<std::uint32_t>(item >> 8);
      const std::uint32_t p = face_ends[2 * x], q = face_ends[2 * x + 1];
      // Two crossings (no more, no fewer), distinct, of opposite coefficients.
      bad |= (item & 0xffu) != 2 || ((p ^ q) & kFlip) == 0 || ((p ^ q) & kIndex) == 0;
      const std::uint32_t tail = p ^ ((p ^ q) & (0u - (p >> 31)));  // (p's flip: q is the tail)
      const std::uint32_t ta = tail & kIndex, hd = (p ^ q ^ tail) & kIndex;
      edge_row[2 * se] = ta;
      edge_row[2 * se + 1] = hd;
      src[se] = face_model ? face_model[x] : x;
      face_edge[x] = se;
      const std::uint32_t j0 = face_up.begin(x), j1 = face_up.end(x);
      if (buckets) {
        for (std::uint32_t j = j0; j < j1; ++j) {
          const std::uint32_t up = face_up_ids[j];
          const std::uint32_t y = up & kIndex;
          const bool first = cell_count[y] == 0;  // (selects, not branches)
          const std::uint32_t at = first ? static_cast<std::uint32_t>(placed) : fill[y];
          start[y] = first ? at : start[y];
          placed += first ? cell_row[y + 1] - cell_row[y] : 0u;
          if (placed > room) {  // (rare: the buckets keep their storage between slices)
            cell_steps_.resize(std::max(2 * room, placed + 64));
            room = cell_steps_.size();
            bucket = cell_steps_.data();
          }
          cell_count[y] = 1;
          fill[y] = at + 1;
          // The step's sign is minus the face's sign in the cell: forward when that is -1.
          const std::uint32_t fwd = static_cast<std::uint32_t>(static_cast<std::int32_t>(up) >> 31);
          const std::uint32_t t = hd ^ ((ta ^ hd) & fwd);
          bucket[at] = {t, ta ^ hd ^ t, se | (kFlip & ~fwd)};
        }
      } else {
        for (std::uint32_t j = j0; j < j1; ++j) cell_count[face_up_ids[j] & kIndex] = 1;
      }
      cut_cells_bound += j1 - j0;
    }
    if (bad) return stop(-1);
  }
  {
    std::uint32_t* const off = edges.offsets.data();
    std::int8_t* const sg = edges.signs.data();
    for (std::uint32_t i = 0; i <= nse; ++i) off[i] = 2 * i;
    for (std::uint32_t i = 0; i < nse; ++i) sg[2 * i] = -1, sg[2 * i + 1] = 1;
  }
  // Rank 3 (the facets): a cut cell reads its faces' section edges (one step each, its
  // direction the opposite of the face's sign in the cell); one loop through every step,
  // followed from the smallest tail, is the polygon the generic gathering chains (loops start
  // at the smallest tail, steps follow heads). A pinch, an open chain or several loops: the
  // generic gathering. A tetrahedron's polygon is read from the model's table for the sides
  // of its vertices; another cell of up to 4 faces is chained in registers at a fixed width
  // (no branch on the cut's length), a larger one from the steps its cut faces left in its
  // bucket through a per-section-vertex step map (stamped per cell). All decide alike.
  if (loop_step_.size() < count) loop_step_.resize(count, LoopStep{0, 0, 0});
  Incidence::Storage polys = out.boundary[1].storage();
  constexpr std::uint32_t kSlack = 4;  // (a fixed-width chain writes up to 4 entries)
  polys.ids.resize(cut_cells_bound + kSlack);
  polys.signs.resize(cut_cells_bound + kSlack);
  std::uint32_t npoly = 0;
  {
    if (visit_list_.size() < cut_cells_bound + 1) visit_list_.resize(cut_cells_bound + 1);
    std::uint64_t* const visit = visit_list_.data();
    std::uint64_t* end = visit;
    for (auto c : touched_) end = list_counts(cell_count, m.begin_[2][c], m.begin_[2][c + 1], end);
    const std::uint32_t ncut = static_cast<std::uint32_t>(end - visit);
    polys.offsets.resize(std::size_t{ncut} + 1);
    out.source[2].resize(ncut);
    facet_internal_.resize(ncut);
    const bool above = m.top_ > 3;
    const bool chains_above = above && !m.single_solid_;
    std::uint32_t* const poly_ids = polys.ids.data();
    std::int8_t* const poly_signs = polys.signs.data();
    std::uint32_t* const poly_off = polys.offsets.data();
    poly_off[0] = 0;
    std::uint32_t* const src = out.source[2].data();
    std::uint32_t* const facet = facet_internal_.data();
    LoopStep* const step = loop_step_.data();
    const SliceModel::Up solid_up = above ? m.up(3) : SliceModel::Up{nullptr, nullptr, 0};
    const std::uint32_t* const solid_up_ids = solid_up.ids;
    std::uint64_t* const solid_bits = above ? mark_[4].data() : nullptr;
    const std::uint32_t* const cell_off = C.offsets.data();
    const std::uint32_t* const fill = cell_fill_.data();
    const std::uint32_t* const start = cell_start_.data();
    const CellStep* const bucket = cell_steps_.data();
    const std::uint32_t* const cell_faces = C.ids.data();
    const std::int8_t* const cell_signs = C.signs.data();
    const std::uint32_t* const face_edge = face_edge_.data();
    const std::uint32_t* const edge_row = edges.ids.data();
    const std::uint32_t* const tet_vertex =
        m.tet_vertices_.empty() ? nullptr : m.tet_vertices_.data();
    const std::uint16_t* const tet_case = m.tet_cases_.data();
    std::uint32_t entries = 0;
    bool ok = true;
    for (const std::uint64_t* it = visit; it != end && ok; ++it) {
      const std::uint32_t x = static_cast<std::uint32_t>(*it >> 8);
      const std::uint32_t b = cell_off[x], nfaces = cell_off[x + 1] - b;
      std::uint32_t added = 0;
      if (tet_vertex) {
        // A tetrahedron: its polygon for the sides of its four vertices, decided when the
        // model was compiled; only the faces' section edges are read.
        const std::uint32_t* const tv = tet_vertex + 4 * x;
        const std::uint32_t pattern = static_cast<std::uint32_t>(side[tv[0]] > 0) |
                                      static_cast<std::uint32_t>(side[tv[1]] > 0) << 1 |
                                      static_cast<std::uint32_t>(side[tv[2]] > 0) << 2 |
                                      static_cast<std::uint32_t>(side[tv[3]] > 0) << 3;
        const std::uint32_t code = tet_case[16 * x + pattern];
        for (std::uint32_t k = 0; k < 4; ++k) {  // (a triangle's fourth entry is dropped)
          const std::uint32_t entry = code >> (3 + 3 * k);
          poly_ids[entries + k] = face_edge[cell_faces[b + (entry & 3u)]];
          poly_signs[entries + k] = static_cast<std::int8_t>(1 - static_cast<int>(entry & 4u) / 2);
        }
        added = code & 7u;
        ok = added != 7;
      } else if (nfaces <= 4) {
        ok = chain_fixed<4>(cell_faces + b, cell_signs + b, nfaces, face_edge, edge_row,
                            poly_ids + entries, poly_signs + entries, &added);
      } else {
        if (++stamp_ == 0) forget_stamps();  // wrapped
        const std::uint32_t st = stamp_;
        const std::uint32_t ns = fill[x] - start[x];
        const CellStep* const cs = bucket + start[x];
        std::uint32_t lo = 0xffffffffu;
        bool pinch = false;
        for (std::uint32_t k = 0; k < ns; ++k) {
          const CellStep c = cs[k];
          pinch |= step[c.tail].stamp == st;  // a pinch (or a face listed twice)
          step[c.tail] = {st, c.head, c.edge};
          lo = std::min(lo, c.tail);
        }
        ok = !pinch;
        ok = ok && ns >= 3;
        std::uint32_t cur = lo;
        for (std::uint32_t k = 0; ok;) {
          const LoopStep sp = step[cur];
          if (sp.stamp != st) {
            ok = false;  // the chain does not close
            break;
          }
          poly_ids[entries + k] = sp.edge & kIndex;
          poly_signs[entries + k] = (sp.edge & kFlip) ? -1 : 1;
          ++k;
          cur = sp.head;
          if (cur == lo) {
            ok = k == ns;  // else several loops
            added = k;
            break;
          }
          ok = k < ns;
        }
      }
      if (!ok) break;
      entries += added;
      const std::uint32_t poly = npoly++;
      poly_off[npoly] = entries;
      src[poly] = cell_model ? cell_model[x] : x;
      facet[poly] = x;
      if (above && !m.single_solid_) {
        if (chains_above) {
          images_[3][x] = {gen_, static_cast<std::uint32_t>(terms_[3].size()), 1};
          terms_[3].push_back({poly, 1});
        }
        for (std::uint32_t j = solid_up.begin(x); j < solid_up.end(x); ++j) {  // mark_parents
          const std::uint32_t y = solid_up_ids[j] & kIndex;
          solid_bits[y >> 6] |= std::uint64_t{1} << (y & 63);
        }
      }
    }
    if (!ok) return stop(-1);
    if (above && m.single_solid_ && npoly > 0) solid_bits[0] |= 1u;  // (every cell's one solid)
    polys.ids.resize(entries);
    polys.signs.resize(entries);
  }
  for (const std::uint64_t* it = faces; it != faces_end; ++it)
    face_edge_[static_cast<std::uint32_t>(*it >> 8)] = no_index;
  out.source[2].resize(npoly);
  facet_internal_.resize(npoly);
  polys.offsets.resize(std::size_t{npoly} + 1);
  kernel_count_ += nse + npoly;
  return cut_upper(m, pl, out, 4) ? 1 : 0;  // (the rank-4 marks are the generic path's bits)
}

}  // namespace cw4d
