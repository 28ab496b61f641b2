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

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/fork_join.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "general.hpp"
#include "slicer_detail.hpp"
#include "slicer_impl.hpp"

namespace cw4d {

namespace {

// The first of the n ascending values x with x > h (n when none), as std::upper_bound finds
// it, by halving without a branch on the comparisons (a sweep's vertex heights fall anywhere
// among its layers, so a branch on each would be mispredicted half the time).
std::uint32_t first_greater(const double* x, std::uint32_t n, double h) {
  if (n == 0) return 0;
  const double* base = x;
  while (n > 1) {
    const std::uint32_t half = n / 2;
    base = base[half] <= h ? base + half : base;
    n -= half;
  }
  return static_cast<std::uint32_t>(base - x) + (*base <= h ? 1u : 0u);
}

}  // namespace

// --- sweeps ---------------------------------------------------------------------------------

void Slicer::Impl::sweep(const SliceModel::Compiled& m, const Eigen::VectorXd& normal,
                         std::span<const double> offsets, const AffineTransform& xf,
                         std::vector<SliceBuffers>& out, unsigned threads) {
  if (offsets.empty()) {
    out.clear();
    return;
  }
  const Hyperplane proto = Hyperplane::from(normal, offsets[0]);
  for (double d : offsets)
    if (!std::isfinite(d)) throw InputError("hyperplane offset is not finite");
  check_section_input(m.complex(), proto, xf);
  out.resize(offsets.size());
  for (SliceBuffers& b : out) b.source_fingerprint = m.fingerprint_;
  std::vector<std::uint32_t>& order = sweep_order_;
  order.resize(offsets.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return offsets[a] < offsets[b]; });
  threads = resolve_threads(threads);
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, order.size()));
  if (threads <= 1) {
    sweep_layers(m, proto, xf, offsets, order, out);
    return;
  }
  // Consecutive groups of layers in offset order, one Slicer per extra thread (kept for the
  // next sweep); each thread writes only its own entries of out.
  if (helpers_.size() < threads - 1) helpers_.resize(threads - 1);
  std::vector<std::size_t> before(threads - 1);
  for (unsigned t = 0; t + 1 < threads; ++t) before[t] = helpers_[t].fast_count_;
  const std::size_t per = (order.size() + threads - 1) / threads;
  fork_join(threads, [&](unsigned t) {
    const std::size_t b = std::min(order.size(), t * per),
                      e = std::min(order.size(), (t + 1) * per);
    if (b < e)
      (t == 0 ? *this : helpers_[t - 1])
          .sweep_layers(m, proto, xf, offsets,
                        std::span<const std::uint32_t>(order).subspan(b, e - b), out);
  });
  for (unsigned t = 0; t + 1 < threads; ++t) fast_count_ += helpers_[t].fast_count_ - before[t];
}

void Slicer::Impl::sweep_layers(const SliceModel::Compiled& m, const Hyperplane& plane,
                                const AffineTransform& xf, std::span<const double> offsets,
                                std::span<const std::uint32_t> layers,
                                std::vector<SliceBuffers>& out) {
  const std::size_t L = layers.size();
  if (L == 0) return;
  kernel_ = true;
  auto single = [&](std::uint32_t k) {
    slice(m, Hyperplane{plane.normal, offsets[k]}, xf, out[k]);
  };
  if (!m.fast()) {
    for (auto k : layers) single(k);
    return;
  }
  const int n = m.dim_;
  const std::size_t nv = m.nv_;
  const std::size_t nc = m.cluster_count();
  Placement pl;
  pl.set(m, plane, &xf);
  near_parallel_ = tol::near_parallel_edge * pl.nm_norm;
  // Per layer (in offset order): the model-space offset and the ON band.
  layer_d_.resize(L);
  layer_tol_.resize(L);
  double max_tol = 0.0;
  for (std::size_t j = 0; j < L; ++j) {
    pl.set_offset(m, offsets[layers[j]]);
    layer_d_[j] = pl.dm;
    layer_tol_[j] = pl.tol;
    max_tol = std::max(max_tol, pl.tol);
  }
  const double* D = layer_d_.data();
  auto first_above = [&](double h) { return first_greater(D, static_cast<std::uint32_t>(L), h); };
  // Heights once per vertex. A vertex within a layer's ON band sends that layer to slice().
  const double* P = m.positions();
  height_.resize(nv);
  layer_bad_.assign(L, 0);
  const bool events = n == 4 && m.top_ >= 3;
  if (events) sweep_.vertex_layer.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    const double h = height(pl.nm, P + v * n, n);
    height_[v] = h;
    // The layers with h - delta <= d <= h + delta: those just below the first layer above h,
    // then from it on.
    const double delta = 2.0 * max_tol;
    std::uint32_t j = first_above(h);
    if (events) sweep_.vertex_layer[v] = j;  // below the plane from that layer on
    while (j > 0 && D[j - 1] >= h - delta) --j;
    for (; j < L && D[j] <= h + delta; ++j)
      if (classify_side(h - D[j], layer_tol_[j]) == Side::On) layer_bad_[j] = 1;
  }
  if (events) {
    sweep_events(m, pl, offsets, layers, out, xf, plane);
    return;
  }
  // Without ON vertices, edge (a, b) crosses layer j exactly when lo < d_j < hi for its end
  // heights lo < hi (the sign of the rounded h - d is the sign of h - d). Edges enter the
  // active set at the first layer above lo (bucketed by that layer) and leave it at the first
  // layer at or above hi (dropped before the layer is built), so each layer sees exactly its
  // crossing edges.
  const SliceModel::Compiled::Rank& E = m.ranks_[1];
  const std::uint32_t ne = static_cast<std::uint32_t>(E.count);
  bucket_offsets_.assign(L + 2, 0);
  edge_top_.resize(ne);
  edge_start_.resize(ne);
  for (std::uint32_t e = 0; e < ne; ++e) {
    const double ha = height_[E.ids[2 * e]], hb = height_[E.ids[2 * e + 1]];
    const std::uint32_t j = first_above(std::min(ha, hb));
    edge_start_[e] = j;
    edge_top_[e] = std::max(ha, hb);
    ++bucket_offsets_[j + 1];
  }
  for (std::size_t j = 0; j <= L; ++j) bucket_offsets_[j + 1] += bucket_offsets_[j];
  bucket_ids_.resize(ne);
  {
    std::vector<std::uint32_t>& fill = bucket_fill_;
    fill.assign(bucket_offsets_.begin(), bucket_offsets_.end() - 1);
    for (std::uint32_t e = 0; e < ne; ++e) bucket_ids_[fill[edge_start_[e]]++] = e;
  }
  active_.clear();
  for (std::size_t j = 0; j < L; ++j) {
    const double d = D[j];
    for (std::uint32_t i = bucket_offsets_[j]; i < bucket_offsets_[j + 1]; ++i)
      active_.push_back(bucket_ids_[i]);
    std::size_t keep = 0;
    for (std::uint32_t e : active_)
      if (edge_top_[e] > d) active_[keep++] = e;
    active_.resize(keep);
    const std::uint32_t k = layers[j];
    if (layer_bad_[j]) {
      single(k);
      continue;
    }
    SliceBuffers& o = out[k];
    pl.set_offset(m, offsets[k]);
    prepare(m);
    touched_.clear();
    for (std::size_t c = 0; c < nc; ++c)
      if (pl.meets(&m.cluster_sphere_[c * (n + 1)], m.cluster_sphere_[c * (n + 1) + n]))
        touched_.push_back(static_cast<std::uint32_t>(c));
    // The crossing edges in increasing id order (marked, then visited cluster by cluster as a
    // slice visits them).
    std::vector<std::uint64_t>& edge_bits = mark_[1];
    for (std::uint32_t e : active_) {
      const std::uint32_t a = E.ids[2 * e], b = E.ids[2 * e + 1];
      s_[a] = height_[a] - d;
      s_[b] = height_[b] - d;
      side_[a] = s_[a] < 0.0 ? Side::Negative : Side::Positive;
      side_[b] = s_[b] < 0.0 ? Side::Negative : Side::Positive;
      edge_bits[e >> 6] |= std::uint64_t{1} << (e & 63);
    }
    start_buffers(m, pl, o);
    bool ok = true;
    for (auto c : touched_)
      if (!visit_marked(edge_bits, m.begin_[0][c], m.begin_[0][c + 1],
                        [&](std::uint32_t e) { return add_crossing(m, e, o); })) {
        ok = false;
        break;
      }
    if (ok && o.vertex_source.empty()) {
      clear_to_empty(o, n - 1);
      ++fast_count_;
      continue;
    }
    if (ok && cut_upper(m, pl, o)) {
      ++fast_count_;
      continue;
    }
    clear_marks(m);
    single(k);  // a degenerate layer: exactly what slice() gives
  }
}

// --- the output-sensitive sweep in R^4 ------------------------------------------------------
//
// Between two consecutive vertex heights no vertex changes side, so the combinatorial section
// (which edges cross, which faces and cells are cut and how) is the same for every layer in
// between; only the crossing parameters t and hence the positions change (the facet normals
// depend on the normal alone). The structure is kept in model terms: the crossing edges, for
// each cut face its two crossing edges (tail, head), for each cut cell its loop of faces from
// the step with the smallest tail. A section vertex's index is the rank of its edge among the
// crossing edges (the kernel numbers them in increasing internal id), a section edge's the rank
// of its face, so a loop's first step (the smallest tail index) is the step with the smallest
// tail edge, and an element outside the star of a passed vertex keeps its description.
//
// When the plane passes vertices, only their edges that change side, the faces on those (read
// through bits over the face rows' entries marking the crossing edges, so a face reads only its
// crossings) and the cells on faces that changed (likewise reading only their cut faces) are
// recomputed, and the layer writes its buffers from the structure in the kernel's layout (the
// orientation as finish_fast turns it, each cell's facet normal computed once per sweep by the
// kernel's arithmetic); a layer that passes no vertex copies the previous layer's connectivity
// and normals. Every layer computes its crossing parameters and positions (the kernel's
// arithmetic, term for term). Elements the kernel does not decide (a face with other than two
// crossings, a pinch, an open chain, several loops) are counted; while any is, a layer goes to
// slice(), as does a layer with a vertex in its ON band, a crossing the kernel leaves to the
// general path or a facet nearly parallel to the plane, and every layer of a model with
// multiplicities.

namespace {

constexpr std::uint32_t kSweepFlip = 0x80000000u;
constexpr std::uint32_t kSweepSmall = 12;  // loops of up to this many steps chained in registers
constexpr std::uint32_t kSweepChunk = 4;   // loop entries copied at a time into a layer's table

// Renews a stamp generation; on wrap every stamp is forgotten.
std::uint32_t next_stamp(std::uint32_t& stamp,
                         std::initializer_list<std::vector<std::uint32_t>*> arrays) {
  if (++stamp == 0) {
    for (auto* a : arrays) std::fill(a->begin(), a->end(), 0u);
    stamp = 1;
  }
  return stamp;
}

// Sets or clears bit x.
inline void put_bit(std::vector<std::uint64_t>& bits, std::uint32_t x, bool on) {
  const std::uint64_t b = std::uint64_t{1} << (x & 63);
  if (on)
    bits[x >> 6] |= b;
  else
    bits[x >> 6] &= ~b;
}

inline void flip_bit(std::uint64_t* bits, std::uint32_t x) {
  bits[x >> 6] ^= std::uint64_t{1} << (x & 63);
}

// list := the set bits, increasing.
// (Inline: without a popcnt instruction in the target, __builtin_popcountll is a call.)
inline std::uint32_t bit_count(std::uint64_t x) {
  x -= (x >> 1) & 0x5555555555555555u;
  x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fu;
  return static_cast<std::uint32_t>((x * 0x0101010101010101u) >> 56);
}

// list := the set bits, increasing. Eight positions are written at a time (those past a word's
// last bit are overwritten by the next word's, or cut off), so that a word's loop ends on the
// count of its bits in eights rather than on each bit.
void list_bits(const std::vector<std::uint64_t>& bits, std::vector<std::uint32_t>& list) {
  std::size_t count = 0;
  for (std::uint64_t b : bits) count += bit_count(b);
  list.resize(count + 8);
  std::uint32_t* to = list.data();
  for (std::size_t w = 0; w < bits.size(); ++w) {
    std::uint64_t b = bits[w];
    if (b == 0) continue;
    const std::uint32_t base = static_cast<std::uint32_t>(w * 64);
    std::uint32_t* at = to;
    to += bit_count(b);
    constexpr std::uint64_t top = std::uint64_t{1} << 63;  // (no bits left: 63, not undefined)
    do {
      for (int q = 0; q < 8; ++q) {
        at[q] = base + static_cast<std::uint32_t>(__builtin_ctzll(b | top));
        b &= b - 1;
      }
      at += 8;
    } while (b != 0);
  }
  list.resize(count);
}

// list (ascending) := list with the membership of every id in `toggled` (distinct, any order)
// switched: those in it removed, the others inserted; the runs between are copied. spare:
// scratch, left with the old list's storage.
void toggle_sorted(std::vector<std::uint32_t>& list, std::vector<std::uint32_t>& toggled,
                   std::vector<std::uint32_t>& spare) {
  if (toggled.empty()) return;
  std::sort(toggled.begin(), toggled.end());
  spare.resize(list.size() + toggled.size());
  const std::uint32_t* from = list.data();
  const std::uint32_t* const end = from + list.size();
  std::uint32_t* to = spare.data();
  for (const std::uint32_t x : toggled) {
    const std::uint32_t* const at = std::lower_bound(from, end, x);
    to = std::copy(from, at, to);
    from = at;
    if (from != end && *from == x)
      ++from;  // removed
    else
      *to++ = x;  // inserted
  }
  to = std::copy(from, end, to);
  spare.resize(static_cast<std::size_t>(to - spare.data()));
  list.swap(spare);
}

// Calls f(x) for every set bit x of [b, e), in increasing order, while f returns true; false
// when f stopped it.
template <class F>
inline bool each_bit(const std::uint64_t* bits, std::uint32_t b, std::uint32_t e, F&& f) {
  if (b >= e) return true;
  std::uint32_t w = b >> 6;
  const std::uint32_t last = (e - 1) >> 6;
  std::uint64_t word = bits[w] & (~std::uint64_t{0} << (b & 63));
  for (;;) {
    if (w == last) word &= ~std::uint64_t{0} >> (63 - ((e - 1) & 63));
    for (; word; word &= word - 1)
      if (!f(w * 64 + static_cast<std::uint32_t>(__builtin_ctzll(word)))) return false;
    if (w == last) return true;
    word = bits[++w];
  }
}

// offsets := the rows of a CSR over `count` keys holding `keys` (offsets[k + 1] - offsets[k]
// entries for key k); cursor: scratch of count entries, left at each row's end.
void csr_offsets(std::span<const std::uint32_t> keys, std::size_t count,
                 std::vector<std::uint32_t>& offsets, std::vector<std::uint32_t>& cursor) {
  offsets.assign(count + 1, 0);
  for (std::uint32_t k : keys) ++offsets[k + 1];
  for (std::size_t k = 0; k < count; ++k) offsets[k + 1] += offsets[k];
  cursor.assign(offsets.begin(), offsets.end() - 1);
}

}  // namespace

void Slicer::Impl::sweep_incidences(const SliceModel::Compiled& m) {
  SweepState& w = sweep_;
  if (w.model == m.serial_) return;
  const SliceModel::Compiled::Rank& E = m.ranks_[1];
  const SliceModel::Compiled::Rank& F = m.ranks_[2];
  const SliceModel::Compiled::Rank& C = m.ranks_[3];
  const std::size_t nv = m.nv_;
  const std::uint32_t ne = static_cast<std::uint32_t>(E.count);
  const std::uint32_t nf = static_cast<std::uint32_t>(F.offsets.size() - 1);
  const std::uint32_t nc = static_cast<std::uint32_t>(C.offsets.size() - 1);
  std::vector<std::uint32_t>& cursor = w.merged;
  csr_offsets(std::span<const std::uint32_t>(E.ids).first(2 * std::size_t{ne}), nv,
              w.vertex_edge_offsets, cursor);
  w.vertex_edges.resize(2 * std::size_t{ne});
  for (std::uint32_t e = 0; e < ne; ++e) {
    const std::uint32_t a = E.ids[2 * e], b = E.ids[2 * e + 1];
    w.vertex_edges[cursor[a]++] = {e, b};
    w.vertex_edges[cursor[b]++] = {e, a};
  }
  // Each face row entry as its edge and the edge's tail (| kSweepFlip: the sign -1), each cell
  // row entry as its face (| kSweepFlip: the sign +1, the step runs backward).
  w.face_entries.resize(F.ids.size());
  for (std::size_t i = 0; i < F.ids.size(); ++i)
    w.face_entries[i] = {F.ids[i],
                         E.ids[2 * std::size_t{F.ids[i]}] | (F.signs[i] < 0 ? kSweepFlip : 0u)};
  w.cell_entries.resize(C.ids.size());
  for (std::size_t i = 0; i < C.ids.size(); ++i)
    w.cell_entries[i] = C.ids[i] | (C.signs[i] < 0 ? 0u : kSweepFlip);
  csr_offsets(F.ids, ne, w.edge_face_offsets, cursor);
  w.edge_faces.resize(F.ids.size());
  for (std::uint32_t f = 0; f < nf; ++f)
    for (std::uint32_t i = F.offsets[f]; i < F.offsets[f + 1]; ++i)
      w.edge_faces[cursor[F.ids[i]]++] = {f, i};
  csr_offsets(C.ids, nf, w.face_cell_offsets, cursor);
  w.face_cells.resize(C.ids.size());
  for (std::uint32_t c = 0; c < nc; ++c)
    for (std::uint32_t i = C.offsets[c]; i < C.offsets[c + 1]; ++i)
      w.face_cells[cursor[C.ids[i]]++] = {c, i};
  w.model = m.serial_;
}

std::uint8_t Slicer::Impl::sweep_face(const SliceModel::Compiled& m, std::uint32_t f) {
  // As the kernel's face pass: exactly two crossings of opposite coefficients (+1 when the
  // edge's tail is below) give the section edge from the -1 crossing to the +1 one.
  SweepState& w = sweep_;
  const SliceModel::Compiled::Rank& F = m.ranks_[2];
  const SweepSlot* entries = w.face_entries.data();
  const Side* side = side_.data();
  std::uint32_t e[2];
  int coef[2];
  int cnt = 0;
  if (!each_bit(w.face_row_bits.data(), F.offsets[f], F.offsets[f + 1], [&](std::uint32_t i) {
        if (cnt == 2) return false;
        const SweepSlot x = entries[i];
        // (the signs are +-1: the model has unit signs)
        coef[cnt] = (side[x.index & ~kSweepFlip] == Side::Negative) != ((x.index & kSweepFlip) != 0)
                        ? -1
                        : 1;
        e[cnt++] = x.element;
        return true;
      }))
    return 2;  // more than two crossings
  if (cnt == 0) return 0;
  if (cnt != 2 || e[0] == e[1] || coef[0] != -coef[1]) return 2;
  w.face_ends[2 * f] = coef[0] < 0 ? e[0] : e[1];
  w.face_ends[2 * f + 1] = coef[0] < 0 ? e[1] : e[0];
  return 1;
}

std::uint8_t Slicer::Impl::sweep_cell(const SliceModel::Compiled& m, std::uint32_t c) {
  // As the kernel's cell pass: one step per cut face (forward when the face's sign in the cell
  // is -1), one leaving each tail, followed from the smallest tail through every step.
  SweepState& w = sweep_;
  const SliceModel::Compiled::Rank& C = m.ranks_[3];
  const std::uint32_t* cell_entries = w.cell_entries.data();
  std::uint32_t tails[kSweepSmall], heads[kSweepSmall], entries[kSweepSmall];
  std::uint32_t ns = 0;
  bool kernel = true;
  std::vector<std::uint32_t>& more = w.steps;  // the steps beyond kSweepSmall
  more.clear();
  each_bit(w.cell_row_bits.data(), C.offsets[c], C.offsets[c + 1], [&](std::uint32_t i) {
    const std::uint32_t entry = cell_entries[i];
    const std::uint32_t f = entry & ~kSweepFlip;
    if (w.face_state[f] != 1) return kernel = false;
    const std::uint32_t back = entry >> 31;  // the step runs from the face's head
    const std::uint32_t tail = w.face_ends[2 * f + back];
    const std::uint32_t head = w.face_ends[2 * f + (back ^ 1u)];
    if (ns < kSweepSmall) {
      tails[ns] = tail, heads[ns] = head, entries[ns] = entry;
    } else {
      more.insert(more.end(), {tail, head, entry});
    }
    ++ns;
    return true;
  });
  if (!kernel) return 2;
  if (ns == 0) return 0;
  if (ns < 3) return 2;
  const std::size_t first = w.loops.size();
  // A loop entry and its sign in the polygon (-1 when the step runs backward), side by side.
  auto push = [&w](std::uint32_t entry) {
    w.loops.push_back(entry);
    w.loop_signs.push_back((entry & kSweepFlip) ? std::int8_t{-1} : std::int8_t{1});
  };
  auto drop = [&w, first] {
    w.loops.resize(first);
    w.loop_signs.resize(first);
  };
  if (ns <= kSweepSmall) {
    std::uint32_t lo = 0;
    for (std::uint32_t i = 1; i < ns; ++i) {
      for (std::uint32_t j = 0; j < i; ++j)
        if (tails[j] == tails[i]) return 2;  // a pinch (or a face listed twice)
      lo = tails[i] < tails[lo] ? i : lo;
    }
    // The step leaving each step's head, + 1 (0: none), all at once (the tails are distinct),
    // so that following the chain is a load per step.
    std::uint32_t next[kSweepSmall];
    for (std::uint32_t i = 0; i < ns; ++i) {
      std::uint32_t sum = 0;
      for (std::uint32_t j = 0; j < ns; ++j) sum += tails[j] == heads[i] ? j + 1 : 0;
      next[i] = sum;
    }
    const std::uint32_t start = tails[lo];
    std::uint32_t cur = lo;
    for (std::uint32_t k = 1;; ++k) {
      push(entries[cur]);
      if (heads[cur] == start) {
        if (k == ns) break;
        drop();  // several loops
        return 2;
      }
      if (next[cur] == 0 || k == ns) {  // the chain does not close
        drop();
        return 2;
      }
      cur = next[cur] - 1;
    }
  } else {
    const std::uint32_t st = next_stamp(w.loop_gen, {&w.loop_stamp});
    std::uint32_t lo = no_index;
    for (std::uint32_t i = 0; i < ns; ++i) {
      const std::uint32_t tail = i < kSweepSmall ? tails[i] : more[3 * (i - kSweepSmall)];
      const std::uint32_t head = i < kSweepSmall ? heads[i] : more[3 * (i - kSweepSmall) + 1];
      const std::uint32_t entry = i < kSweepSmall ? entries[i] : more[3 * (i - kSweepSmall) + 2];
      if (w.loop_stamp[tail] == st) return 2;  // a pinch (or a face listed twice)
      w.loop_stamp[tail] = st;
      w.loop_head[tail] = head;
      w.loop_entry[tail] = entry;
      lo = std::min(lo, tail);
    }
    std::uint32_t cur = lo, k = 0;
    for (;;) {
      if (w.loop_stamp[cur] != st) break;  // the chain does not close
      push(w.loop_entry[cur]);
      ++k;
      cur = w.loop_head[cur];
      if (cur == lo || k == ns) break;
    }
    if (cur != lo || k != ns) {  // open, or several loops
      drop();
      return 2;
    }
  }
  w.cell_loop[c] = static_cast<std::uint32_t>(first);
  w.cell_size[c] = ns;
  return 1;
}

void Slicer::Impl::sweep_update(const SliceModel::Compiled& m, std::span<const std::uint32_t> moved,
                                bool rebuild) {
  // The sides of `moved` (of every vertex when rebuilding) are already those of the new layer.
  SweepState& w = sweep_;
  const SliceModel::Compiled::Rank& E = m.ranks_[1];
  const std::uint32_t ne = static_cast<std::uint32_t>(E.count);
  const std::uint32_t nf = static_cast<std::uint32_t>(m.ranks_[2].offsets.size() - 1);
  const std::uint32_t nc = static_cast<std::uint32_t>(m.ranks_[3].offsets.size() - 1);
  const std::uint32_t* edge_ends = E.ids.data();
  const Side* side = side_.data();
  const std::uint32_t st = next_stamp(w.stamp, {&w.stamp_f, &w.stamp_c});
  const SweepSlot* edge_faces = w.edge_faces.data();
  const std::uint32_t* edge_face_offsets = w.edge_face_offsets.data();
  const SweepSlot* face_cells = w.face_cells.data();
  const std::uint32_t* face_cell_offsets = w.face_cell_offsets.data();
  auto cell_pass = [&](std::uint32_t c) {
    const std::uint8_t was = w.cell_state[c];
    if (was == 1) w.live -= w.cell_size[c];
    const std::uint8_t now = sweep_cell(m, c);
    if (now == 1) w.live += w.cell_size[c];
    w.bad += (now == 2) - (was == 2);
    w.cell_state[c] = now;
    if ((now == 1) != (was == 1)) {
      if (rebuild) put_bit(w.cell_bits, c, now == 1);
      return true;
    }
    return false;
  };
  if (rebuild) {
    w.edge_in.assign(ne, 0);
    w.face_state.assign(nf, 0);
    w.cell_state.assign(nc, 0);
    w.edge_bits.assign((ne + 63) / 64, 0);
    w.face_bits.assign((nf + 63) / 64, 0);
    w.cell_bits.assign((nc + 63) / 64, 0);
    w.face_row_bits.assign((m.ranks_[2].ids.size() + 63) / 64, 0);
    w.cell_row_bits.assign((m.ranks_[3].ids.size() + 63) / 64, 0);
    std::uint64_t* face_row = w.face_row_bits.data();
    w.loops.clear();
    w.loop_signs.clear();
    w.live = 0;
    w.bad = 0;
    for (std::uint32_t e = 0; e < ne; ++e)
      if (side[edge_ends[2 * e]] != side[edge_ends[2 * e + 1]]) {
        w.edge_in[e] = 1;
        put_bit(w.edge_bits, e, true);
        for (std::uint32_t i = edge_face_offsets[e]; i < edge_face_offsets[e + 1]; ++i)
          flip_bit(face_row, edge_faces[i].index);
      }
    for (std::uint32_t f = 0; f < nf; ++f) {
      const std::uint8_t now = sweep_face(m, f);
      w.face_state[f] = now;
      w.bad += now == 2;
      if (now == 1) put_bit(w.face_bits, f, true);
      if (now != 0)
        for (std::uint32_t i = face_cell_offsets[f]; i < face_cell_offsets[f + 1]; ++i)
          flip_bit(w.cell_row_bits.data(), face_cells[i].index);
    }
    for (std::uint32_t c = 0; c < nc; ++c) cell_pass(c);
    list_bits(w.edge_bits, w.edges);
    list_bits(w.face_bits, w.faces);
    list_bits(w.cell_bits, w.cells);
    return;
  }
  // Rank 1: the edges at the moved vertices that changed side; the faces on those.
  std::uint64_t* face_row = w.face_row_bits.data();
  // (The lists of cut elements are switched where their membership changed; the bits over
  // them are read only when rebuilding, which sets them anew.)
  w.near_f.clear();
  w.toggled.clear();
  for (std::uint32_t v : moved)
    for (std::uint32_t i = w.vertex_edge_offsets[v]; i < w.vertex_edge_offsets[v + 1]; ++i) {
      const std::uint32_t e = w.vertex_edges[i].element;
      const std::uint8_t in = side[v] != side[w.vertex_edges[i].index];
      if (in == w.edge_in[e]) continue;  // (both ends moved: it crosses neither time)
      w.edge_in[e] = in;
      w.toggled.push_back(e);
      for (std::uint32_t j = edge_face_offsets[e]; j < edge_face_offsets[e + 1]; ++j) {
        const SweepSlot s = edge_faces[j];
        flip_bit(face_row, s.index);
        if (w.stamp_f[s.element] != st) {
          w.stamp_f[s.element] = st;
          w.near_f.push_back(s.element);
        }
      }
    }
  toggle_sorted(w.edges, w.toggled, w.spare);
  // Rank 2: those faces; the cells on the faces that changed.
  w.near_c.clear();
  w.toggled.clear();
  for (std::uint32_t f : w.near_f) {
    const std::uint8_t was = w.face_state[f];
    const std::uint32_t tail = w.face_ends[2 * f], head = w.face_ends[2 * f + 1];
    const std::uint8_t now = sweep_face(m, f);
    if (now == was && (now != 1 || (w.face_ends[2 * f] == tail && w.face_ends[2 * f + 1] == head)))
      continue;
    w.face_state[f] = now;
    w.bad += (now == 2) - (was == 2);
    if ((now == 1) != (was == 1)) w.toggled.push_back(f);
    const bool row = (now != 0) != (was != 0);
    for (std::uint32_t j = face_cell_offsets[f]; j < face_cell_offsets[f + 1]; ++j) {
      const SweepSlot s = face_cells[j];
      if (row) flip_bit(w.cell_row_bits.data(), s.index);
      if (w.stamp_c[s.element] != st) {
        w.stamp_c[s.element] = st;
        w.near_c.push_back(s.element);
      }
    }
  }
  toggle_sorted(w.faces, w.toggled, w.spare);
  // Rank 3: those cells (after every face is renewed).
  w.toggled.clear();
  for (std::uint32_t c : w.near_c)
    if (cell_pass(c)) w.toggled.push_back(c);
  toggle_sorted(w.cells, w.toggled, w.spare);
  // Recomputed cells appended their loops: compact when the dead ones dominate.
  if (w.loops.size() > 4 * w.live + 4096) {
    w.merged.clear();
    w.merged_signs.clear();
    for (std::uint32_t c : w.cells) {
      const std::uint32_t b = w.cell_loop[c];
      w.cell_loop[c] = static_cast<std::uint32_t>(w.merged.size());
      w.merged.insert(w.merged.end(), w.loops.begin() + b, w.loops.begin() + b + w.cell_size[c]);
      w.merged_signs.insert(w.merged_signs.end(), w.loop_signs.begin() + b,
                            w.loop_signs.begin() + b + w.cell_size[c]);
    }
    w.loops.swap(w.merged);
    w.loop_signs.swap(w.merged_signs);
  }
}

void Slicer::Impl::sweep_normals(const SliceModel::Compiled& m, const Placement& pl) {
  // write_geometry's facet normal of every cell (term for term): the model facet's normal
  // through A^{-T}, projected, unit; the fourth entry 0 when nearly parallel to the plane.
  SweepState& w = sweep_;
  const std::uint32_t nc = static_cast<std::uint32_t>(m.ranks_[3].offsets.size() - 1);
  w.cell_normal.resize(4 * std::size_t{nc});
  const bool copied = !m.facet_normals_.empty() || m.ranks_[3].model_id.empty();
  const double* fn = copied ? m.facet_normals_.data() : m.model_->facet_normals().data();
  const std::uint32_t* fid = copied ? nullptr : m.ranks_[3].model_id.data();
  for (std::uint32_t c = 0; c < nc; ++c) {
    const double* nf = fn + 4 * std::size_t{fid ? fid[c] : c};
    double* y = &w.cell_normal[4 * std::size_t{c}];
    double len2 = 0.0;
    for (int r = 0; r < 3; ++r) {
      double sum = 0.0;
      for (int j = 0; j < 4; ++j) sum += pl.N[r * 4 + j] * nf[j];
      y[r] = sum;
      len2 += sum * sum;
    }
    const double len = std::sqrt(len2);
    y[3] = len < tol::near_parallel_normal ? 0.0 : 1.0;
    for (int r = 0; r < 3; ++r) y[r] = y[r] / len;
  }
}

void Slicer::Impl::sweep_events(const SliceModel::Compiled& m, Placement& pl,
                                std::span<const double> offsets,
                                std::span<const std::uint32_t> layers,
                                std::vector<SliceBuffers>& out, const AffineTransform& xf,
                                const Hyperplane& plane) {
  SweepState& w = sweep_;
  const std::size_t L = layers.size();
  bool restore = false;  // slice() wrote its own sides
  auto single = [&](std::uint32_t k) {
    slice(m, Hyperplane{plane.normal, offsets[k]}, xf, out[k]);
    restore = true;
  };
  if (!m.unit_signs_ || m.nv_ >= kSweepFlip) {
    // Multiplicities: the generic gathering decides every layer (and vertex ids must leave
    // the top bit free for the face entries' sign).
    for (auto k : layers) single(k);
    return;
  }
  const SliceModel::Compiled::Rank& E = m.ranks_[1];
  const SliceModel::Compiled::Rank& F = m.ranks_[2];
  const SliceModel::Compiled::Rank& C = m.ranks_[3];
  const std::uint32_t nv = static_cast<std::uint32_t>(m.nv_);
  const std::uint32_t ne = static_cast<std::uint32_t>(E.count);
  const std::uint32_t nf = static_cast<std::uint32_t>(F.offsets.size() - 1);
  const std::uint32_t nc = static_cast<std::uint32_t>(C.offsets.size() - 1);
  sweep_incidences(m);
  // The vertices grouped by the first layer they are below: the vertices below layer j are
  // by_layer[0, layer_vertex_offsets[j + 1]).
  {
    std::vector<std::uint32_t>& cursor = w.merged;
    csr_offsets(std::span<const std::uint32_t>(w.vertex_layer).first(nv), L + 1,
                w.layer_vertex_offsets, cursor);
    w.by_layer.resize(nv);
    for (std::uint32_t v = 0; v < nv; ++v) w.by_layer[cursor[w.vertex_layer[v]]++] = v;
  }
  for (auto* a : {&w.loop_stamp, &w.loop_head, &w.loop_entry, &w.vertex_index})
    if (a->size() < ne) a->resize(ne, 0);
  for (auto* a : {&w.stamp_f, &w.edge_index})
    if (a->size() < nf) a->resize(nf, 0);
  if (w.face_ends.size() < 2 * std::size_t{nf}) w.face_ends.resize(2 * std::size_t{nf});
  for (auto* a : {&w.stamp_c, &w.cell_loop, &w.cell_size})
    if (a->size() < nc) a->resize(nc, 0);
  sweep_normals(m, pl);  // (they depend on the normal and the placement only)
  if (s_.size() < nv) s_.resize(nv), side_.resize(nv);
  bool valid = false;       // the structure describes the sides of the last layer it built
  std::uint32_t below = 0;  // vertices by_layer[0, below) are below that layer
  constexpr std::uint32_t kNoLayer = 0xffffffffu;
  std::uint32_t last = kNoLayer;  // the last layer built from the structure as it is
  const double* H = height_.data();
  const double* D = layer_d_.data();
  const SliceModel::Compiled::CrossingTest needs_general_at = m.crossing_test(near_parallel_);
  const std::uint32_t* edge_ends = E.ids.data();
  const std::uint32_t* edge_id = E.model_id.empty() ? nullptr : E.model_id.data();
  const std::uint32_t* face_id = F.model_id.empty() ? nullptr : F.model_id.data();
  const std::uint32_t* cell_id = C.model_id.empty() ? nullptr : C.model_id.data();
  const bool above = m.top_ > 3;
  // The tables above the polygons: written here for a single solid (and none), else by
  // cut_upper from the polygons' images.
  const bool direct = !above || m.single_solid_;
  const std::size_t tables = above ? 3 : 2;
  std::vector<std::uint32_t>& moved = touched_;  // (scratch: the kernel's cluster list is unused)
  const std::uint32_t* lv = w.layer_vertex_offsets.data();
  for (std::size_t j = 0; j < L; ++j) {
    const std::uint32_t k = layers[j];
    if (layer_bad_[j]) {
      single(k);  // a vertex in the ON band: slice() decides
      continue;
    }
    const double d = D[j];
    // Without ON vertices the side of v is the sign of h_v - d (a rounded difference has the
    // exact difference's sign): below exactly from the first layer above h_v on.
    const std::uint32_t to = lv[j + 1];
    const bool rebuild = !valid || 4 * std::size_t{to - below} > nv;
    if (restore && !rebuild) {  // the structure's sides again
      for (std::uint32_t i = 0; i < nv; ++i)
        side_[w.by_layer[i]] = i < below ? Side::Negative : Side::Positive;
    }
    restore = false;
    if (rebuild) {
      for (std::uint32_t v = 0; v < nv; ++v)
        side_[v] = H[v] - d < 0.0 ? Side::Negative : Side::Positive;
    } else {
      moved.assign(w.by_layer.begin() + below, w.by_layer.begin() + to);
      for (std::uint32_t v : moved) side_[v] = Side::Negative;
    }
    if (rebuild || to != below) {
      sweep_update(m, moved, rebuild);
      last = kNoLayer;
    }
    if (j + 1 < L) {
      // The stars of the next layer's vertices, fetched while this layer is written (on a
      // large model they lie anywhere in memory).
      const std::uint32_t* vo = w.vertex_edge_offsets.data();
      const SweepSlot* ve = w.vertex_edges.data();
      const std::uint32_t* eo = w.edge_face_offsets.data();
      const SweepSlot* ef = w.edge_faces.data();
      for (std::uint32_t i = to; i < lv[j + 2]; ++i) {
        const std::uint32_t v = w.by_layer[i];
        for (std::uint32_t q = vo[v]; q < vo[v + 1]; ++q) {
          const std::uint32_t e = ve[q].element;
          __builtin_prefetch(ef + eo[e]);
          __builtin_prefetch(w.edge_in.data() + e);
        }
      }
    }
    valid = true;
    const bool same = !rebuild && to == below && last != kNoLayer;
    below = to;
    if (w.bad) {
      single(k);  // something the kernel leaves to the generic gathering
      continue;
    }
    SliceBuffers& o = out[k];
    pl.set_offset(m, offsets[k]);
    if (w.edges.empty()) {
      start_buffers(m, pl, o);
      clear_to_empty(o, 3);
      ++fast_count_;
      last = kNoLayer;
      continue;
    }
    // Rank 1: a section vertex per crossing edge, t as the kernel computes it, and its position
    // by write_geometry's vertex pass: y = M ((1 - t) a + t b) + c.
    const std::uint32_t nx = static_cast<std::uint32_t>(w.edges.size());
    o.vertex_source.resize(nx);
    {
      VertexSource* vs = o.vertex_source.data();
      const std::uint32_t* xe = w.edges.data();
      std::uint32_t* vertex_index = w.vertex_index.data();
      // Two at a time: the same divisions as the kernel's, lane by lane; a pair that the model's
      // shortest and longest edge cannot clear is decided exactly (needs_general_at).
      bool ok = true;
      std::uint32_t i = 0;
#if defined(__SSE2__)
      {
        const __m128d dd = _mm_set1_pd(d);
        const __m128d np_long =
            _mm_set1_pd(needs_general_at.near_parallel * needs_general_at.longest);
        const __m128d shortest = _mm_set1_pd(needs_general_at.shortest);
        const __m128d wl = _mm_set1_pd(needs_general_at.weld);
        const __m128d one = _mm_set1_pd(1.0);
        const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffff));
        for (; i + 2 <= nx; i += 2) {
          const std::uint32_t e0 = xe[i], e1 = xe[i + 1];
          const std::uint32_t a0 = edge_ends[2 * e0], b0 = edge_ends[2 * e0 + 1];
          const std::uint32_t a1 = edge_ends[2 * e1], b1 = edge_ends[2 * e1 + 1];
          const __m128d ha = _mm_set_pd(H[a1], H[a0]);
          const __m128d hb = _mm_set_pd(H[b1], H[b0]);
          const __m128d sa = _mm_sub_pd(ha, dd), sb = _mm_sub_pd(hb, dd);
          const __m128d diff = _mm_sub_pd(sa, sb);
          const __m128d t = _mm_div_pd(sa, diff);
          __m128d maybe = _mm_cmplt_pd(_mm_and_pd(diff, magnitude), np_long);
          maybe = _mm_or_pd(maybe, _mm_cmple_pd(_mm_mul_pd(t, shortest), wl));
          maybe = _mm_or_pd(maybe, _mm_cmple_pd(_mm_mul_pd(_mm_sub_pd(one, t), shortest), wl));
          const double t0 = _mm_cvtsd_f64(t), t1 = _mm_cvtsd_f64(_mm_unpackhi_pd(t, t));
          if (const int lanes = _mm_movemask_pd(maybe)) {
            const double sa0 = _mm_cvtsd_f64(sa), sb0 = _mm_cvtsd_f64(sb);
            const double sa1 = _mm_cvtsd_f64(_mm_unpackhi_pd(sa, sa));
            const double sb1 = _mm_cvtsd_f64(_mm_unpackhi_pd(sb, sb));
            ok = !((lanes & 1) && needs_general_at(a0, b0, sa0, sb0, t0)) &&
                 !((lanes & 2) && needs_general_at(a1, b1, sa1, sb1, t1));
            if (!ok) break;
          }
          vs[i] = {edge_id ? edge_id[e0] : e0, 1, t0};
          vs[i + 1] = {edge_id ? edge_id[e1] : e1, 1, t1};
          vertex_index[e0] = i;
          vertex_index[e1] = i + 1;
        }
      }
#endif
      for (; ok && i < nx; ++i) {
        const std::uint32_t e = xe[i];
        const std::uint32_t a = edge_ends[2 * e], b = edge_ends[2 * e + 1];
        const double sa = H[a] - d, sb = H[b] - d;
        const double t = sa / (sa - sb);
        ok = !needs_general_at(a, b, sa, sb, t);
        vs[i] = {edge_id ? edge_id[e] : e, 1, t};
        vertex_index[e] = i;
      }
      if (!ok) {
        single(k);  // a crossing within the weld distance, or nearly parallel
        continue;
      }
      // (no facets: write_geometry fails only on those; their normals are written below, into
      // the layer's array as it is, so that its storage is not zeroed anew)
      write_geometry(m, pl, o, w.edges, {}, false);
    }
    o.dim = 3;
    o.plane.normal = pl.plane->normal;
    o.plane.offset = pl.offset;
    o.general = false;
    o.fallback = FallbackReason::None;
    o.reused_topology = false;
    o.cache_valid_ = false;
    if (same) {
      // No vertex passed since layer `last`: its connectivity and its facet normals.
      const SliceBuffers& p = out[last];
      o.boundary = p.boundary;
      o.source = p.source;
      o.facet_normals = p.facet_normals;
      ++fast_count_;
      continue;
    }
    if (direct) {
      resize_keeping(o.boundary, o.spare_tables_, tables);
      resize_keeping(o.source, o.spare_sources_, tables + 1);
      o.source[0].clear();
    } else {
      prepare(m);
      o.set_ranks(3);  // as start_buffers (cut_upper appends the solids)
    }
    // Rank 2: a section edge per cut face.
    const std::uint32_t nse = static_cast<std::uint32_t>(w.faces.size());
    {
      Incidence::Storage edges = o.boundary[0].storage();
      edges.ids.resize(2 * std::size_t{nse});
      edges.signs.resize(2 * std::size_t{nse});
      edges.offsets.resize(std::size_t{nse} + 1);
      std::vector<std::uint32_t>& src_store = o.source[1];
      src_store.resize(nse);
      std::uint32_t* ids = edges.ids.data();
      std::int8_t* signs = edges.signs.data();
      std::uint32_t* offs = edges.offsets.data();
      std::uint32_t* src = src_store.data();
      const std::uint32_t* faces = w.faces.data();
      const std::uint32_t* face_ends = w.face_ends.data();
      const std::uint32_t* vertex_index = w.vertex_index.data();
      std::uint32_t* edge_index = w.edge_index.data();
      for (std::uint32_t i = 0; i < nse; ++i) {
        const std::uint32_t f = faces[i];
        ids[2 * i] = vertex_index[face_ends[2 * f]];
        ids[2 * i + 1] = vertex_index[face_ends[2 * f + 1]];
        src[i] = face_id ? face_id[f] : f;
        edge_index[f] = i;
      }
      {  // -1, +1 for every edge, sixteen bytes at a time
        static constexpr std::int8_t kPairs[16] = {-1, 1, -1, 1, -1, 1, -1, 1,
                                                   -1, 1, -1, 1, -1, 1, -1, 1};
        const std::size_t bytes = 2 * std::size_t{nse};
        std::size_t b = 0;
        for (; b + 16 <= bytes; b += 16) std::memcpy(signs + b, kPairs, 16);
        std::memcpy(signs + b, kPairs, bytes - b);
      }
      for (std::uint32_t i = 0; i <= nse; ++i) offs[i] = 2 * i;
    }
    // Rank 3: a polygon per cut cell, turned as finish_fast turns it (a reflecting placement
    // reverses each loop), with its facet normal.
    const std::uint32_t npoly = static_cast<std::uint32_t>(w.cells.size());
    bool ok = true;
    {
      const std::uint32_t* cells = w.cells.data();
      const std::uint32_t* cell_size = w.cell_size.data();
      const std::uint32_t* cell_loop = w.cell_loop.data();
      const std::size_t kept = w.loops.size();
      w.loops.resize(kept + kSweepChunk);  // (read by the last chunks; cut off below)
      w.loop_signs.resize(kept + kSweepChunk);
      const std::uint32_t* loops = w.loops.data();
      const std::int8_t* loop_signs = w.loop_signs.data();
      const std::uint32_t* edge_index = w.edge_index.data();
      std::size_t entries = 0;
      for (std::uint32_t p = 0; p < npoly; ++p) entries += cell_size[cells[p]];
      Incidence::Storage polys = o.boundary[1].storage();
      // (kSweepChunk entries beyond the end: loops are copied kSweepChunk entries at a time)
      polys.ids.resize(entries + kSweepChunk);
      polys.signs.resize(entries + kSweepChunk);
      polys.offsets.resize(std::size_t{npoly} + 1);
      std::vector<std::uint32_t>& src_store = o.source[2];
      src_store.resize(npoly);
      std::uint32_t* ids = polys.ids.data();
      std::int8_t* signs = polys.signs.data();
      std::uint32_t* offs = polys.offsets.data();
      std::uint32_t* src = src_store.data();
      const bool reverse = direct && pl.reflect;
      std::uint32_t at = 0;
      offs[0] = 0;
      for (std::uint32_t p = 0; p < npoly; ++p) {
        const std::uint32_t c = cells[p];
        const std::uint32_t* loop = loops + cell_loop[c];
        const std::int8_t* loop_sign = loop_signs + cell_loop[c];
        const std::uint32_t cnt = cell_size[c];
        if (!reverse) {
          // Whole chunks, without a branch per entry: what a chunk writes beyond the loop's
          // end is overwritten by the next loop (or lies in the slack cut off below); what it
          // reads there are other loops' entries or the slack's zeros, all faces.
          for (std::uint32_t i = 0; i < cnt; i += kSweepChunk) {
            for (std::uint32_t q = 0; q < kSweepChunk; ++q)
              ids[at + i + q] = edge_index[loop[i + q] & ~kSweepFlip];
            std::memcpy(signs + at + i, loop_sign + i, kSweepChunk);
          }
        } else {
          for (std::uint32_t i = 0; i < cnt; ++i) {
            ids[at + cnt - 1 - i] = edge_index[loop[i] & ~kSweepFlip];
            signs[at + cnt - 1 - i] = static_cast<std::int8_t>(-loop_sign[i]);
          }
        }
        at += cnt;
        offs[p + 1] = at;
        src[p] = cell_id ? cell_id[c] : c;
      }
      polys.ids.resize(entries);
      polys.signs.resize(entries);
      w.loops.resize(kept);
      w.loop_signs.resize(kept);
      if (direct) {
        o.facet_normals.resize(3 * std::size_t{npoly});
        double* normals = o.facet_normals.data();
        const double* cell_normal = w.cell_normal.data();
        double parallel = 1.0;
        for (std::uint32_t p = 0; p < npoly; ++p) {
          const double* y = cell_normal + 4 * std::size_t{cells[p]};
          normals[3 * p] = y[0];
          normals[3 * p + 1] = y[1];
          normals[3 * p + 2] = y[2];
          parallel *= y[3];
        }
        ok = parallel != 0.0;
      } else {
        section_edge_.assign(w.edges.begin(), w.edges.end());
        facet_internal_.assign(cells, cells + npoly);
        for (std::uint32_t p = 0; p < npoly; ++p) {  // several solids: their chains
          images_[3][cells[p]] = {gen_, static_cast<std::uint32_t>(terms_[3].size()), 1};
          terms_[3].push_back({p, 1});
          mark_parents(m, 3, cells[p]);
        }
      }
    }
    kernel_count_ += nse + npoly;
    if (direct) {
      if (!ok) {
        single(k);  // a facet nearly parallel to the plane: the general path
        continue;
      }
      if (above) {
        // The single solid: every polygon, with +1 (as cut_upper and finish_fast write it).
        Incidence::Storage solids = o.boundary[2].storage();
        const std::uint32_t rows = npoly > 0 ? 1 : 0;
        solids.offsets.assign({0u, npoly});
        solids.offsets.resize(rows + 1);
        solids.ids.resize(npoly);
        std::iota(solids.ids.begin(), solids.ids.end(), 0u);
        solids.signs.assign(npoly, 1);
        o.source[3].assign(rows, m.ranks_[4].model_id.empty() ? 0u : m.ranks_[4].model_id[0]);
      }
      ++fast_count_;
      last = k;
      continue;
    }
    if (cut_upper(m, pl, o, 4)) {
      ++fast_count_;
      last = k;
      continue;
    }
    clear_marks(m);
    single(k);  // exactly what slice() gives
  }
}

}  // namespace cw4d
