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
    if (n == 4 && m.top_ >= 3) {  // the slice's own kernel on the marked crossings
      if (kernel_slice(m, pl, o, true) > 0) {
        ++fast_count_;
        continue;
      }
      clear_marks(m);
      single(k);  // degenerate, or for the generic gathering: exactly what slice() gives
      continue;
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

}  // namespace cw4d
