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

// --- sweeps ---------------------------------------------------------------------------------

void Slicer::sweep(const SliceModel& m, const Eigen::VectorXd& normal,
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

void Slicer::sweep_layers(const SliceModel& m, const Hyperplane& plane, const AffineTransform& xf,
                          std::span<const double> offsets, std::span<const std::uint32_t> layers,
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
  const std::size_t nv = m.positions_.size() / n;
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
  auto first_above = [&](double h) {  // first layer with d > h
    return static_cast<std::uint32_t>(std::upper_bound(D, D + L, h) - D);
  };
  // Heights once per vertex. A vertex within a layer's ON band sends that layer to slice().
  const double* P = m.positions_.data();
  height_.resize(nv);
  layer_bad_.assign(L, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    const double h = height(pl.nm, P + v * n, n);
    height_[v] = h;
    const double delta = 2.0 * max_tol;
    for (std::uint32_t j = static_cast<std::uint32_t>(std::lower_bound(D, D + L, h - delta) - D);
         j < L && D[j] <= h + delta; ++j)
      if (classify_side(h - D[j], layer_tol_[j]) == Side::On) layer_bad_[j] = 1;
  }
  if (n == 4 && m.top_ >= 3) {
    sweep_events(m, pl, offsets, layers, out, xf, plane);
    return;
  }
  // Without ON vertices, edge (a, b) crosses layer j exactly when lo < d_j < hi for its end
  // heights lo < hi (the sign of the rounded h - d is the sign of h - d). Edges enter the
  // active set at the first layer above lo (bucketed by that layer) and leave it at the first
  // layer at or above hi (dropped before the layer is built), so each layer sees exactly its
  // crossing edges.
  const SliceModel::Rank& E = m.ranks_[1];
  const std::uint32_t ne = static_cast<std::uint32_t>(E.offsets.size() - 1);
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
      side_[a] = s_[a] < 0.0 ? -1 : 1;
      side_[b] = s_[b] < 0.0 ? -1 : 1;
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
// tail edge, and an element outside the star of a passed vertex keeps its description. When
// the plane passes vertices only their edges, the faces on those and the cells on these are
// recomputed, and the layer writes its buffers from the structure in the kernel's layout (the
// cut above the cells, the orientation, positions and normals by the kernel's own code); a
// layer that passes no vertex copies the previous layer's connectivity and normals and
// computes only its crossing parameters (with the kernel's arithmetic) and positions. Elements
// the kernel does not decide (a face with other than two crossings, a pinch, an open chain,
// several loops) are counted; while any is, a layer goes to slice(), as does a layer with a
// vertex in its ON band or a crossing the kernel leaves to the general path.

namespace {

constexpr std::uint32_t kSweepFlip = 0x80000000u;

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

// list := the set bits, increasing.
void list_bits(const std::vector<std::uint64_t>& bits, std::vector<std::uint32_t>& list) {
  list.clear();
  for (std::size_t w = 0; w < bits.size(); ++w)
    for (std::uint64_t b = bits[w]; b; b &= b - 1)
      list.push_back(static_cast<std::uint32_t>(w * 64 + __builtin_ctzll(b)));
}

}  // namespace

std::uint8_t Slicer::sweep_face(const SliceModel& m, std::uint32_t f) {
  // As the kernel's face pass: exactly two crossings of opposite coefficients (+1 when the
  // edge's tail is below) give the section edge from the -1 crossing to the +1 one.
  SweepState& w = sweep_;
  const SliceModel::Rank& F = m.ranks_[2];
  const std::uint32_t* edge_ends = m.ranks_[1].ids.data();
  std::uint32_t e[2];
  int coef[2];
  int cnt = 0;
  for (std::uint32_t i = F.offsets[f], end = F.offsets[f + 1]; i < end; ++i) {
    const std::uint32_t x = F.ids[i];
    if (!w.edge_in[x]) continue;
    if (cnt == 2) return 2;
    coef[cnt] = side_[edge_ends[2 * x]] < 0 ? -F.signs[i] : F.signs[i];
    e[cnt++] = x;
  }
  if (cnt == 0) return 0;
  if (cnt != 2 || e[0] == e[1] || coef[0] != -coef[1]) return 2;
  w.face_tail[f] = coef[0] < 0 ? e[0] : e[1];
  w.face_head[f] = coef[0] < 0 ? e[1] : e[0];
  return 1;
}

std::uint8_t Slicer::sweep_cell(const SliceModel& m, std::uint32_t c) {
  // As the kernel's cell pass: one step per cut face (forward when the face's sign in the cell
  // is -1), one leaving each tail, followed from the smallest tail through every step.
  SweepState& w = sweep_;
  const SliceModel::Rank& C = m.ranks_[3];
  const std::uint32_t st = next_stamp(w.loop_gen, {&w.loop_stamp});
  std::uint32_t lo = no_index, ns = 0;
  for (std::uint32_t i = C.offsets[c], end = C.offsets[c + 1]; i < end; ++i) {
    const std::uint32_t f = C.ids[i];
    const std::uint8_t fs = w.face_state[f];
    if (fs == 0) continue;
    if (fs != 1) return 2;
    const bool forward = C.signs[i] < 0;
    const std::uint32_t tail = forward ? w.face_tail[f] : w.face_head[f];
    const std::uint32_t head = forward ? w.face_head[f] : w.face_tail[f];
    if (w.loop_stamp[tail] == st) return 2;  // a pinch (or a face listed twice)
    w.loop_stamp[tail] = st;
    w.loop_head[tail] = head;
    w.loop_entry[tail] = forward ? f : f | kSweepFlip;
    lo = std::min(lo, tail);
    ++ns;
  }
  if (ns == 0) return 0;
  if (ns < 3) return 2;
  const std::size_t first = w.loops.size();
  std::uint32_t cur = lo, k = 0;
  for (;;) {
    if (w.loop_stamp[cur] != st) break;  // the chain does not close
    w.loops.push_back(w.loop_entry[cur]);
    ++k;
    cur = w.loop_head[cur];
    if (cur == lo || k == ns) break;
  }
  if (cur != lo || k != ns) {  // open, or several loops
    w.loops.resize(first);
    return 2;
  }
  w.cell_loop[c] = static_cast<std::uint32_t>(first);
  w.cell_size[c] = k;
  return 1;
}

void Slicer::sweep_update(const SliceModel& m, std::span<const std::uint32_t> moved, bool rebuild) {
  // The sides of `moved` (of every vertex when rebuilding) are already those of the new layer.
  SweepState& w = sweep_;
  const SliceModel::Rank& E = m.ranks_[1];
  const std::uint32_t ne = static_cast<std::uint32_t>(E.offsets.size() - 1);
  const std::uint32_t nf = static_cast<std::uint32_t>(m.ranks_[2].offsets.size() - 1);
  const std::uint32_t nc = static_cast<std::uint32_t>(m.ranks_[3].offsets.size() - 1);
  const std::uint32_t* edge_ends = E.ids.data();
  const std::uint32_t st = next_stamp(w.stamp, {&w.stamp_e, &w.stamp_f, &w.stamp_c});
  // Rank 1: the edges at the moved vertices. The cut elements of each rank are kept as bits
  // (listed in increasing order after a change).
  w.near_e.clear();
  bool changed = rebuild;
  if (rebuild) {
    w.edge_in.assign(ne, 0);
    w.face_state.assign(nf, 0);
    w.cell_state.assign(nc, 0);
    w.edge_bits.assign((ne + 63) / 64, 0);
    w.face_bits.assign((nf + 63) / 64, 0);
    w.cell_bits.assign((nc + 63) / 64, 0);
    w.loops.clear();
    w.live = 0;
    w.bad = 0;
    for (std::uint32_t e = 0; e < ne; ++e)
      if (side_[edge_ends[2 * e]] != side_[edge_ends[2 * e + 1]]) {
        w.edge_in[e] = 1;
        w.near_e.push_back(e);
        put_bit(w.edge_bits, e, true);
      }
  } else {
    for (std::uint32_t v : moved)
      for (std::uint32_t i = w.vertex_edge_offsets[v]; i < w.vertex_edge_offsets[v + 1]; ++i) {
        const std::uint32_t e = w.vertex_edges[i];
        if (w.stamp_e[e] == st) continue;
        w.stamp_e[e] = st;
        w.near_e.push_back(e);
        const std::uint8_t in = side_[edge_ends[2 * e]] != side_[edge_ends[2 * e + 1]];
        if (in != w.edge_in[e]) put_bit(w.edge_bits, e, in), changed = true;
        w.edge_in[e] = in;
      }
  }
  if (changed) list_bits(w.edge_bits, w.edges);
  // Rank 2: the faces on those edges.
  w.near_f.clear();
  changed = rebuild;
  const std::uint32_t* edge_up = m.up_offsets_[1].data();
  const std::uint32_t* edge_up_ids = m.up_ids_[1].data();
  for (std::uint32_t e : w.near_e)
    for (std::uint32_t i = edge_up[e]; i < edge_up[e + 1]; ++i) {
      const std::uint32_t f = edge_up_ids[i] & SliceModel::kUpIndex;
      if (w.stamp_f[f] == st) continue;
      w.stamp_f[f] = st;
      w.near_f.push_back(f);
      const std::uint8_t was = w.face_state[f], now = sweep_face(m, f);
      w.bad += (now == 2) - (was == 2);
      if ((now == 1) != (was == 1)) put_bit(w.face_bits, f, now == 1), changed = true;
      w.face_state[f] = now;
    }
  if (changed) list_bits(w.face_bits, w.faces);
  // Rank 3: the cells on those faces (after every face is renewed).
  w.near_c.clear();
  const std::uint32_t* face_up = m.up_offsets_[2].data();
  const std::uint32_t* face_up_ids = m.up_ids_[2].data();
  for (std::uint32_t f : w.near_f)
    for (std::uint32_t i = face_up[f]; i < face_up[f + 1]; ++i) {
      const std::uint32_t c = face_up_ids[i] & SliceModel::kUpIndex;
      if (w.stamp_c[c] == st) continue;
      w.stamp_c[c] = st;
      w.near_c.push_back(c);
    }
  changed = rebuild;
  for (std::uint32_t c : w.near_c) {
    const std::uint8_t was = w.cell_state[c];
    if (was == 1) w.live -= w.cell_size[c];
    const std::uint8_t now = sweep_cell(m, c);
    if (now == 1) w.live += w.cell_size[c];
    w.bad += (now == 2) - (was == 2);
    if ((now == 1) != (was == 1)) put_bit(w.cell_bits, c, now == 1), changed = true;
    w.cell_state[c] = now;
  }
  if (changed) list_bits(w.cell_bits, w.cells);
  // Recomputed cells appended their loops: compact when the dead ones dominate.
  if (w.loops.size() > 4 * w.live + 4096) {
    w.merged.clear();
    for (std::uint32_t c : w.cells) {
      const std::uint32_t b = w.cell_loop[c];
      w.cell_loop[c] = static_cast<std::uint32_t>(w.merged.size());
      w.merged.insert(w.merged.end(), w.loops.begin() + b, w.loops.begin() + b + w.cell_size[c]);
    }
    w.loops.swap(w.merged);
  }
}

void Slicer::sweep_events(const SliceModel& m, Placement& pl, std::span<const double> offsets,
                          std::span<const std::uint32_t> layers, std::vector<SliceBuffers>& out,
                          const AffineTransform& xf, const Hyperplane& plane) {
  SweepState& w = sweep_;
  const std::size_t L = layers.size();
  const SliceModel::Rank& E = m.ranks_[1];
  const SliceModel::Rank& F = m.ranks_[2];
  const SliceModel::Rank& C = m.ranks_[3];
  const std::uint32_t nv = static_cast<std::uint32_t>(m.positions_.size() / 4);
  const std::uint32_t ne = static_cast<std::uint32_t>(E.offsets.size() - 1);
  const std::uint32_t nf = static_cast<std::uint32_t>(F.offsets.size() - 1);
  const std::uint32_t nc = static_cast<std::uint32_t>(C.offsets.size() - 1);
  bool valid = false;       // the structure describes the sides of the last layer it built
  std::uint32_t below = 0;  // vertices by_height[0, below) are below that layer
  bool restore = false;     // slice() wrote its own sides
  constexpr std::uint32_t kNoLayer = 0xffffffffu;
  std::uint32_t last = kNoLayer;  // the last layer built from the structure as it is
  auto single = [&](std::uint32_t k) {
    slice(m, Hyperplane{plane.normal, offsets[k]}, xf, out[k]);
    restore = true;
  };
  // The edges at each vertex, the vertices by height.
  w.vertex_edge_offsets.assign(nv + 1, 0);
  for (std::uint32_t i = 0; i < 2 * ne; ++i) ++w.vertex_edge_offsets[E.ids[i] + 1];
  for (std::uint32_t v = 0; v < nv; ++v) w.vertex_edge_offsets[v + 1] += w.vertex_edge_offsets[v];
  w.vertex_edges.resize(2 * std::size_t{ne});
  w.merged.assign(w.vertex_edge_offsets.begin(), w.vertex_edge_offsets.end() - 1);
  for (std::uint32_t e = 0; e < ne; ++e) {
    w.vertex_edges[w.merged[E.ids[2 * e]]++] = e;
    w.vertex_edges[w.merged[E.ids[2 * e + 1]]++] = e;
  }
  w.by_height.resize(nv);
  std::iota(w.by_height.begin(), w.by_height.end(), 0u);
  std::sort(w.by_height.begin(), w.by_height.end(), [&](std::uint32_t a, std::uint32_t b) {
    return height_[a] < height_[b] || (height_[a] == height_[b] && a < b);
  });
  for (auto* a : {&w.stamp_e, &w.loop_stamp, &w.loop_head, &w.loop_entry, &w.vertex_index})
    if (a->size() < ne) a->resize(ne, 0);
  for (auto* a : {&w.stamp_f, &w.face_tail, &w.face_head, &w.edge_index})
    if (a->size() < nf) a->resize(nf, 0);
  for (auto* a : {&w.stamp_c, &w.cell_loop, &w.cell_size})
    if (a->size() < nc) a->resize(nc, 0);
  if (s_.size() < nv) s_.resize(nv), side_.resize(nv);
  const double* H = height_.data();
  const double* D = layer_d_.data();
  const double weld = m.weld_;
  const double* edge_length = m.edge_length_.data();
  const std::uint32_t* edge_ends = E.ids.data();
  const bool above = m.top_ > 3;
  const bool chains_above = above && !m.single_solid_;
  std::vector<std::uint32_t>& moved = touched_;  // (scratch: the kernel's cluster list is unused)
  for (std::size_t j = 0; j < L; ++j) {
    const std::uint32_t k = layers[j];
    if (layer_bad_[j]) {
      single(k);  // a vertex in the ON band: slice() decides
      continue;
    }
    const double d = D[j];
    // Without ON vertices the side of v is the sign of h_v - d (a rounded difference has the
    // exact difference's sign), so the vertices passed since the structure's layer are those
    // with heights in between.
    std::uint32_t to = below;
    while (to < nv && H[w.by_height[to]] < d) ++to;
    const bool rebuild = !valid || 4 * std::size_t{to - below} > nv;
    if (restore && !rebuild) {  // the structure's sides again
      for (std::uint32_t i = 0; i < nv; ++i) side_[w.by_height[i]] = i < below ? -1 : 1;
    }
    restore = false;
    if (rebuild) {
      for (std::uint32_t v = 0; v < nv; ++v) side_[v] = H[v] - d < 0.0 ? -1 : 1;
    } else {
      moved.assign(w.by_height.begin() + below, w.by_height.begin() + to);
      for (std::uint32_t v : moved) side_[v] = -1;
    }
    if (rebuild || to != below) {
      sweep_update(m, moved, rebuild);
      last = kNoLayer;
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
    // Rank 1: a section vertex per crossing edge, t as the kernel computes it.
    const std::uint32_t nx = static_cast<std::uint32_t>(w.edges.size());
    o.vertex_source.resize(nx);
    VertexSource* vs = o.vertex_source.data();
    const std::uint32_t* xe = w.edges.data();
    std::uint32_t* vertex_index = w.vertex_index.data();
    bool ok = true;
    for (std::uint32_t i = 0; i < nx; ++i) {
      const std::uint32_t e = xe[i];
      const std::uint32_t a = edge_ends[2 * e], b = edge_ends[2 * e + 1];
      const double sa = H[a] - d, sb = H[b] - d;
      const double t = sa / (sa - sb);
      if (needs_general(sa, sb, t, edge_length[e], near_parallel_, weld)) {
        ok = false;
        break;
      }
      vs[i] = {E.model_id.empty() ? e : E.model_id[e], 1, t};
      vertex_index[e] = i;
    }
    if (!ok) {
      single(k);  // a crossing within the weld distance, or nearly parallel
      continue;
    }
    o.dim = 3;
    o.plane.normal = pl.plane->normal;
    o.plane.offset = pl.offset;
    o.general = false;
    o.fallback = FallbackReason::None;
    o.reused_topology = false;
    o.cache_valid_ = false;
    if (same) {
      // No vertex passed since layer `last`: its connectivity and its facet normals (they
      // depend on the normal alone), new positions.
      const SliceBuffers& p = out[last];
      o.boundary = p.boundary;
      o.source = p.source;
      write_geometry(m, pl, o, w.edges, {});  // (no facets: nothing can fail)
      o.facet_normals = p.facet_normals;
      ++fast_count_;
      continue;
    }
    prepare(m);
    o.set_ranks(m.top_ > 3 ? 3 : 2);  // as start_buffers
    section_edge_.assign(w.edges.begin(), w.edges.end());
    o.coords.clear();
    o.facet_normals.clear();
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
      const std::uint32_t* tail = w.face_tail.data();
      const std::uint32_t* head = w.face_head.data();
      std::uint32_t* edge_index = w.edge_index.data();
      const std::uint32_t* face_id = F.model_id.empty() ? nullptr : F.model_id.data();
      for (std::uint32_t i = 0; i < nse; ++i) {
        const std::uint32_t f = faces[i];
        ids[2 * i] = vertex_index[tail[f]];
        ids[2 * i + 1] = vertex_index[head[f]];
        signs[2 * i] = -1;
        signs[2 * i + 1] = 1;
        offs[i] = 2 * i;
        src[i] = face_id ? face_id[f] : f;
        edge_index[f] = i;
      }
      offs[nse] = 2 * nse;
    }
    // Rank 3: a polygon per cut cell.
    const std::uint32_t npoly = static_cast<std::uint32_t>(w.cells.size());
    {
      const std::uint32_t* cells = w.cells.data();
      const std::uint32_t* cell_size = w.cell_size.data();
      const std::uint32_t* cell_loop = w.cell_loop.data();
      const std::uint32_t* loops = w.loops.data();
      const std::uint32_t* edge_index = w.edge_index.data();
      std::size_t entries = 0;
      for (std::uint32_t p = 0; p < npoly; ++p) entries += cell_size[cells[p]];
      Incidence::Storage polys = o.boundary[1].storage();
      polys.ids.resize(entries);
      polys.signs.resize(entries);
      polys.offsets.resize(std::size_t{npoly} + 1);
      std::vector<std::uint32_t>& src_store = o.source[2];
      src_store.resize(npoly);
      facet_internal_.resize(npoly);
      std::uint32_t* ids = polys.ids.data();
      std::int8_t* signs = polys.signs.data();
      std::uint32_t* offs = polys.offsets.data();
      std::uint32_t* src = src_store.data();
      std::uint32_t* facet = facet_internal_.data();
      const std::uint32_t* cell_id = C.model_id.empty() ? nullptr : C.model_id.data();
      std::uint32_t at = 0;
      offs[0] = 0;
      for (std::uint32_t p = 0; p < npoly; ++p) {
        const std::uint32_t c = cells[p];
        const std::uint32_t* loop = loops + cell_loop[c];
        for (std::uint32_t i = 0, cnt = cell_size[c]; i < cnt; ++i) {
          ids[at + i] = edge_index[loop[i] & ~kSweepFlip];
          signs[at + i] = (loop[i] & kSweepFlip) ? -1 : 1;
        }
        at += cell_size[c];
        offs[p + 1] = at;
        src[p] = cell_id ? cell_id[c] : c;
        facet[p] = c;
      }
      if (above)
        for (std::uint32_t p = 0; p < npoly; ++p) {
          const std::uint32_t c = cells[p];
          if (chains_above) {
            images_[3][c] = {gen_, static_cast<std::uint32_t>(terms_[3].size()), 1};
            terms_[3].push_back({p, 1});
          }
          mark_parents(m, 3, c);
        }
    }
    kernel_count_ += nse + npoly;
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
