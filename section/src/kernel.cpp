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
// those bytes (eight at a time); returns the new end of the list. The work on the listed
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
    while (w) {
      const int bit = __builtin_ctzll(w) & ~7;
      *list++ =
          (std::uint64_t{x + static_cast<std::uint32_t>(bit >> 3)} << 8) | ((w >> bit) & 0xffu);
      w &= ~(std::uint64_t{0xff} << bit);
    }
  }
  for (; x < e; ++x)
    if (counts[x]) *list++ = (std::uint64_t{x} << 8) | counts[x], counts[x] = 0;
  return list;
}

}  // namespace

int Slicer::kernel_slice(const SliceModel& m, const Placement& pl, SliceBuffers& out,
                         bool marked_edges) {
  // A section vertex per crossing edge, a section edge per face with exactly two crossings, a
  // polygon per cell whose section edges form one loop: the buffers the generic gathering
  // writes for such a slice (tested element for element), in the same order, written once.
  // Nothing is gathered by reading boundaries: each crossing edge hands its section vertex to
  // the faces above it (coface lists carrying the edge's sign in the face), each cut face its
  // section edge, as the step it makes, to the cells above it; a face or a cell then reads only
  // what it was handed, from one place. The per-element counts double as the marks of the
  // faces and cells to visit (zero between slices: cleared when listed, or wholly when the
  // kernel stops half way).
  if (!m.unit_signs_) return -1;  // multiplicities: the generic gathering decides
  start_buffers(m, pl, out);
  constexpr std::uint32_t kFlip = 0x80000000u, kIndex = 0x7fffffffu;
  const SliceModel::Rank& E = m.ranks_[1];
  const SliceModel::Rank& F = m.ranks_[2];
  const SliceModel::Rank& C = m.ranks_[3];
  const std::uint32_t* const edge_ends = E.ids.data();
  const std::int8_t* const side = side_.data();
  const double* const s = s_.data();
  const double* const edge_length = m.edge_length_.data();
  const double weld = m.weld_;
  const double near_parallel = near_parallel_;
  const std::uint32_t* const edge_model = E.model_id.empty() ? nullptr : E.model_id.data();
  const std::uint32_t* const face_model = F.model_id.empty() ? nullptr : F.model_id.data();
  const std::uint32_t* const cell_model = C.model_id.empty() ? nullptr : C.model_id.data();
  const std::size_t nf = F.offsets.size() - 1, nc = C.offsets.size() - 1;
  if (face_mark_.size() < nf) face_mark_.resize(nf, 0);
  if (cell_mark_.size() < nc) cell_mark_.resize(nc, 0);
  if (face_ends_.size() < 2 * nf) face_ends_.resize(2 * nf);
  if (cell_base_.size() < nc) cell_base_.resize(nc);
  std::uint8_t* const face_count = face_mark_.data();
  std::uint8_t* const cell_count = cell_mark_.data();
  std::uint32_t* const face_ends = face_ends_.data();
  std::uint32_t* const cell_base = cell_base_.data();
  auto stop = [this](int result) {
    std::fill(face_mark_.begin(), face_mark_.end(), 0);
    std::fill(cell_mark_.begin(), cell_mark_.end(), 0);
    return result;
  };
  const std::uint32_t* const edge_up = m.up_offsets_[1].data();
  const std::uint32_t* const edge_up_ids = m.up_ids_[1].data();
  const std::uint32_t* const face_up = m.up_offsets_[2].data();
  const std::uint32_t* const face_up_ids = m.up_ids_[2].data();
  // Rank 1: the crossings, in id order cluster by cluster, each handed to its faces with its
  // coefficient in the face's cut (the kFlip bit: +1).
  std::uint32_t cut_faces_bound = 0;
  for (auto c : touched_) {
    // The crossing edges first: listed without a branch (the sides are unpredictable), or
    // those a sweep marked.
    const std::uint32_t e0 = m.begin_[0][c], e1 = m.begin_[0][c + 1];
    if (crossing_ids_.size() < e1 - e0) crossing_ids_.resize(e1 - e0);
    std::uint32_t* const list = crossing_ids_.data();
    std::uint32_t count = 0;
    if (marked_edges) {
      std::uint32_t* w = list;
      visit_marked(mark_[1], e0, e1, [&w](std::uint32_t e) {
        *w++ = e;
        return true;
      });
      count = static_cast<std::uint32_t>(w - list);
    } else {
      for (std::uint32_t e = e0; e < e1; ++e) {
        list[count] = e;
        count += side[edge_ends[2 * e]] != side[edge_ends[2 * e + 1]];
      }
    }
    const std::uint32_t v0 = static_cast<std::uint32_t>(out.vertex_source.size());
    out.vertex_source.resize(v0 + count);
    section_edge_.resize(v0 + count);
    VertexSource* const vs = out.vertex_source.data();
    std::uint32_t* const vertex_edge = section_edge_.data();
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint32_t e = list[i];
      const std::uint32_t a = edge_ends[2 * e], b = edge_ends[2 * e + 1];
      const double t = s[a] / (s[a] - s[b]);
      const double len = edge_length[e];
      if (needs_general(s[a], s[b], t, len, near_parallel, weld)) {  // as crossing()
        reason_ = FallbackReason::Weld;
        return stop(0);
      }
      const std::uint32_t v = v0 + i;
      vs[v] = {edge_model ? edge_model[e] : e, 1, t};
      vertex_edge[v] = e;
      // The crossing's coefficient in the edge's cut is +1 when the tail is below; in a face's
      // cut that times the edge's sign there (the coface's top bit: -1).
      const std::uint32_t tail_above = side[a] < 0 ? 0u : kFlip;
      const std::uint32_t j0 = edge_up[e], j1 = edge_up[e + 1];
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
  if (out.vertex_source.empty()) {
    clear_to_empty(out, m.dim_ - 1);
    return 1;
  }
  // Rank 2: a face handed two crossings of opposite coefficients gives the section edge from
  // the one with -1 to the one with +1, and hands it to its cells as the step their cut makes.
  Incidence::Storage edges = out.boundary[0].storage();
  edges.ids.resize(2 * std::size_t{cut_faces_bound});
  out.source[1].resize(cut_faces_bound);
  std::uint32_t nse = 0, cut_cells_bound = 0;
  {
    std::uint32_t* const edge_row = edges.ids.data();
    std::uint32_t* const src = out.source[1].data();
    bool bad = false;
    CellPush* push = cell_push_.data();
    std::size_t push_room = cell_push_.size();
    for (auto c : touched_) {
      const std::uint32_t b = m.begin_[1][c], e = m.begin_[1][c + 1];
      if (visit_list_.size() < e - b) visit_list_.resize(e - b);
      std::uint64_t* const visit = visit_list_.data();
      const std::uint64_t* const end = list_counts(face_count, b, e, visit);
      for (const std::uint64_t* it = visit; it != end; ++it) {
        const std::uint32_t x = static_cast<std::uint32_t>(*it >> 8);
        const std::uint32_t p = face_ends[2 * x], q = face_ends[2 * x + 1];
        // Two crossings (no more, no fewer), distinct, of opposite coefficients.
        bad |= (*it & 0xffu) != 2 || ((p ^ q) & kFlip) == 0 || ((p ^ q) & kIndex) == 0;
        const std::uint32_t tail = ((p & kFlip) ? q : p) & kIndex;
        const std::uint32_t head = ((p & kFlip) ? p : q) & kIndex;
        const std::uint32_t se = nse++;
        edge_row[2 * se] = tail;
        edge_row[2 * se + 1] = head;
        src[se] = face_model ? face_model[x] : x;
        const std::uint32_t j0 = face_up[x], j1 = face_up[x + 1];
        if (cut_cells_bound + (j1 - j0) > push_room) {  // (rare once the scratch has grown)
          cell_push_.resize(2 * (std::size_t{cut_cells_bound} + (j1 - j0)));
          push = cell_push_.data();
          push_room = cell_push_.size();
        }
        for (std::uint32_t j = j0; j < j1; ++j) {
          const std::uint32_t up = face_up_ids[j];
          const std::uint32_t y = up & kIndex;
          const std::uint32_t k = cell_count[y];
          // The step's sign is minus the face's sign in the cell: forward when that is -1.
          push[cut_cells_bound++] = {
              y, (up & kFlip) ? CellStep{tail, head, se} : CellStep{head, tail, se | kFlip}};
          bad |= k == 255;
          cell_count[y] = static_cast<std::uint8_t>(k + 1);
        }
      }
      if (bad) return stop(-1);
    }
  }
  out.source[1].resize(nse);
  edges.ids.resize(2 * std::size_t{nse});
  edges.signs.resize(2 * std::size_t{nse});
  edges.offsets.resize(std::size_t{nse} + 1);
  for (std::uint32_t i = 0; i <= nse; ++i) edges.offsets[i] = 2 * i;
  for (std::uint32_t i = 0; i < nse; ++i) edges.signs[2 * i] = -1, edges.signs[2 * i + 1] = 1;
  // Rank 3 (the facets): the steps a cell was handed, one leaving each section vertex, followed
  // from the smallest tail; one loop through every step is the polygon the generic gathering
  // chains (loops start at the smallest tail, steps follow heads). A pinch, an open chain or
  // several loops: the generic gathering. A cut of up to kSmall steps (a tetrahedron's, a
  // dodecahedron's) is chained in registers, the step after each found by comparing tails; a
  // larger one through a per-section-vertex step map (stamped per cell). Both decide alike.
  const std::size_t nsv = out.vertex_source.size();
  if (loop_step_.size() < nsv) loop_step_.resize(nsv, LoopStep{0, 0, 0});
  Incidence::Storage polys = out.boundary[1].storage();
  polys.ids.resize(cut_cells_bound);
  polys.signs.resize(cut_cells_bound);
  polys.offsets.resize(std::size_t{cut_cells_bound} + 1);
  out.source[2].resize(cut_cells_bound);
  facet_internal_.resize(cut_cells_bound);
  std::uint32_t npoly = 0;
  {
    const bool above = m.top_ > 3;
    const bool chains_above = above && !m.single_solid_;
    std::uint32_t* const poly_ids = polys.ids.data();
    std::int8_t* const poly_signs = polys.signs.data();
    std::uint32_t* const poly_off = polys.offsets.data();
    std::uint32_t* const src = out.source[2].data();
    std::uint32_t* const facet = facet_internal_.data();
    LoopStep* const step = loop_step_.data();
    const std::uint32_t* const solid_up = above ? m.up_offsets_[3].data() : nullptr;
    const std::uint32_t* const solid_up_ids = above ? m.up_ids_[3].data() : nullptr;
    std::uint64_t* const solid_bits = above ? mark_[4].data() : nullptr;
    constexpr std::uint32_t kSmall = 12;
    std::uint32_t entries = 0;
    // The cut cells, cluster by cluster, with their counts; their steps grouped by cell (each
    // cell's in the order they were handed) in one pass over what the faces handed.
    if (visit_list_.size() < cut_cells_bound) visit_list_.resize(cut_cells_bound);
    std::uint64_t* const visit = visit_list_.data();
    std::uint64_t* end = visit;
    for (auto c : touched_) end = list_counts(cell_count, m.begin_[2][c], m.begin_[2][c + 1], end);
    std::uint32_t sum = 0;
    for (const std::uint64_t* it = visit; it != end; ++it) {
      cell_base[*it >> 8] = sum;
      sum += static_cast<std::uint32_t>(*it & 0xffu);
    }
    if (cell_steps_.size() < sum) cell_steps_.resize(sum);
    CellStep* const grouped = cell_steps_.data();
    const CellPush* const push = cell_push_.data();
    for (std::uint32_t i = 0; i < cut_cells_bound; ++i)
      grouped[cell_base[push[i].cell]++] = push[i].step;
    {
      bool ok = true;
      for (const std::uint64_t* it = visit; it != end && ok; ++it) {
        const std::uint32_t x = static_cast<std::uint32_t>(*it >> 8);
        const std::uint32_t ns = static_cast<std::uint32_t>(*it & 0xffu);
        const CellStep* const steps = grouped + (cell_base[x] - ns);  // (bases moved past)
        if (ns < 3) {
          ok = false;
        } else if (ns <= kSmall) {
          std::uint32_t tails[kSmall], heads[kSmall], ids[kSmall];
          std::uint32_t lo = 0;
          for (std::uint32_t i = 0; i < ns; ++i) {
            tails[i] = steps[i].tail, heads[i] = steps[i].head, ids[i] = steps[i].edge;
            for (std::uint32_t j = 0; j < i; ++j) ok &= tails[j] != tails[i];  // a pinch
            lo = tails[i] < tails[lo] ? i : lo;
          }
          const std::uint32_t first = tails[lo];
          std::uint32_t cur = lo;
          for (std::uint32_t k = 0; ok;) {
            poly_ids[entries] = ids[cur] & kIndex;
            poly_signs[entries] = (ids[cur] & kFlip) ? -1 : 1;
            ++entries;
            ++k;
            const std::uint32_t h = heads[cur];
            if (h == first) {
              ok = k == ns;  // one loop through every step (or several loops)
              break;
            }
            std::uint32_t next = kSmall;
            for (std::uint32_t j = 0; j < ns; ++j) next = tails[j] == h ? j : next;
            ok = k < ns && next != kSmall;  // (else the chain does not close)
            cur = next;
          }
        } else {
          if (++stamp_ == 0) {  // wrapped: forget every stamp
            for (std::size_t i = 0; i < loop_step_.size(); ++i) loop_step_[i].stamp = 0;
            stamp_ = 1;
          }
          const std::uint32_t st = stamp_;
          std::uint32_t lo = 0xffffffffu;
          for (std::uint32_t i = 0; i < ns && ok; ++i) {
            const CellStep cs = steps[i];
            ok = step[cs.tail].stamp != st;  // else a pinch (or a face listed twice)
            step[cs.tail] = {st, cs.head, cs.edge};
            lo = std::min(lo, cs.tail);
          }
          std::uint32_t cur = lo;
          for (std::uint32_t k = 0; ok;) {
            const LoopStep sp = step[cur];
            if (sp.stamp != st) {
              ok = false;  // the chain does not close
              break;
            }
            poly_ids[entries] = sp.edge & kIndex;
            poly_signs[entries] = (sp.edge & kFlip) ? -1 : 1;
            ++entries;
            ++k;
            cur = sp.head;
            if (cur == lo) {
              ok = k == ns;  // else several loops
              break;
            }
            ok = k < ns;
          }
        }
        if (!ok) break;
        const std::uint32_t poly = npoly++;
        poly_off[npoly] = entries;
        src[poly] = cell_model ? cell_model[x] : x;
        facet[poly] = x;
        if (above) {
          if (chains_above) {
            images_[3][x] = {gen_, static_cast<std::uint32_t>(terms_[3].size()), 1};
            terms_[3].push_back({poly, 1});
          }
          for (std::uint32_t j = solid_up[x]; j < solid_up[x + 1]; ++j) {  // mark_parents
            const std::uint32_t y = solid_up_ids[j] & kIndex;
            solid_bits[y >> 6] |= std::uint64_t{1} << (y & 63);
          }
        }
      }
      if (!ok) return stop(-1);
    }
    polys.ids.resize(entries);
    polys.signs.resize(entries);
  }
  out.source[2].resize(npoly);
  facet_internal_.resize(npoly);
  polys.offsets.resize(std::size_t{npoly} + 1);
  kernel_count_ += nse + npoly;
  return cut_upper(m, pl, out, 4) ? 1 : 0;  // (the rank-4 marks are the generic path's bits)
}

}  // namespace cw4d
