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

// The kernel's loop steps and the generic gathering's vertex and edge stamps share stamp_: when it
// wraps, every stamp of both is cleared, so no old stamp can equal a new one.
void Slicer::Impl::forget_stamps() {
  for (auto& step : loop_step_) step.stamp = 0;
  std::fill(vertex_stamp_.begin(), vertex_stamp_.end(), 0u);
  std::fill(edge_stamp_.begin(), edge_stamp_.end(), 0u);
  stamp_ = 1;
}

// --- the facade -----------------------------------------------------------------------------

Slicer::Slicer() : impl_(std::make_unique<Impl>()) {}
Slicer::~Slicer() = default;
Slicer::Slicer(Slicer&&) noexcept = default;
Slicer& Slicer::operator=(Slicer&&) noexcept = default;
Slicer::Slicer(const Slicer& other)
    : impl_(std::make_unique<Impl>(other.impl_ ? *other.impl_ : Impl{})) {}
Slicer& Slicer::operator=(const Slicer& other) {
  if (this != &other) impl_ = std::make_unique<Impl>(other.impl_ ? *other.impl_ : Impl{});
  return *this;
}

void Slicer::slice(const SliceModel& model, const Hyperplane& plane,
                   const AffineTransform& model_to_world, SliceBuffers& out,
                   const SliceOptions& options) {
  if (!impl_) impl_ = std::make_unique<Impl>();  // (moved from)
  impl_->slice(*model.compiled_, plane, model_to_world, out, options);
}

void Slicer::slice(const SliceModel& model, const Hyperplane& plane, SliceBuffers& out,
                   const SliceOptions& options) {
  if (!impl_) impl_ = std::make_unique<Impl>();
  impl_->slice(*model.compiled_, plane, out, options);
}

void Slicer::sweep(const SliceModel& model, const Eigen::VectorXd& normal,
                   std::span<const double> offsets, const AffineTransform& model_to_world,
                   std::vector<SliceBuffers>& out, unsigned threads) {
  if (!impl_) impl_ = std::make_unique<Impl>();
  impl_->sweep(*model.compiled_, normal, offsets, model_to_world, out, threads);
}

std::size_t Slicer::fast_slices() const {
  return impl_ ? impl_->fast_count_ : 0;
}
std::size_t Slicer::cached_slices() const {
  return impl_ ? impl_->cached_count_ : 0;
}
std::size_t Slicer::kernel_elements() const {
  return impl_ ? impl_->kernel_count_ : 0;
}
std::size_t Slicer::generic_elements() const {
  return impl_ ? impl_->generic_count_ : 0;
}

// --- slicing --------------------------------------------------------------------------------

void Slicer::Impl::slice(const SliceModel::Compiled& model, const Hyperplane& plane,
                         SliceBuffers& out, const SliceOptions& options) {
  slice_placed(model, plane, nullptr, out, options);
}

void Slicer::Impl::slice(const SliceModel::Compiled& m, const Hyperplane& plane,
                         const AffineTransform& xf, SliceBuffers& out,
                         const SliceOptions& options) {
  slice_placed(m, plane, &xf, out, options);
}

void Slicer::Impl::slice_placed(const SliceModel::Compiled& m, const Hyperplane& plane,
                                const AffineTransform* xf, SliceBuffers& out,
                                const SliceOptions& options) {
  if (!m.fast() || plane.dim() != m.dim() || (xf && xf->dim() != m.dim())) {
    general_from(m, plane, xf, out);  // (which throws InputError for mismatched dimensions)
    return;
  }
  Placement pl;
  pl.set(m, plane, xf);
  slice_with(m, pl, plane, xf, out, options);
}

void Slicer::Impl::slice_with(const SliceModel::Compiled& m, Placement& pl, const Hyperplane& plane,
                              const AffineTransform* xf, SliceBuffers& out,
                              const SliceOptions& options) {
  pl.plane = &plane;  // (a scene's cached placement was made for an equal plane)
  out.source_fingerprint = m.fingerprint_;
  near_parallel_ = tol::near_parallel_edge * pl.nm_norm;
  pl.set_offset(m, plane.offset);
  if (options.reuse_topology && reuse(m, pl, options, out)) {
    ++cached_count_;
    return;
  }
  reason_ = FallbackReason::None;
  kernel_ = options.kernel;
  if (!fast_slice(m, pl, options, out)) general_from(m, plane, xf, out);
}

void Slicer::Impl::general_from(const SliceModel::Compiled& m, const Hyperplane& plane,
                                const AffineTransform* xf, SliceBuffers& out) {
  out.source_fingerprint = m.fingerprint_;
  if (xf)
    general_slice(m, plane, *xf, out);
  else
    general_slice(m, plane, AffineTransform::identity(m.dim()), out);
}

void Slicer::Impl::general_slice(const SliceModel::Compiled& m, const Hyperplane& plane,
                                 const AffineTransform& xf, SliceBuffers& out) {
  Section sec = general_cut(m.complex(), plane, xf, /*test_self_intersection=*/false);
  const Complex& c = sec.complex;
  out.dim = c.ambient_dim();
  out.plane = plane;
  out.coords.assign(c.positions().data(), c.positions().data() + c.positions().size());
  out.vertex_source = std::move(sec.vertex_source);
  out.boundary.resize(c.top_rank());
  for (int r = 1; r <= c.top_rank(); ++r) out.boundary[r - 1] = c.boundary(r);
  out.source = std::move(sec.source);
  out.facet_normals.assign(c.facet_normals().data(),
                           c.facet_normals().data() + c.facet_normals().size());
  out.general = true;
  out.fallback = m.fast() ? reason_ : FallbackReason::Model;
  out.reused_topology = false;
  out.cache_valid_ = false;
}

bool Slicer::Impl::emit_loops(std::span<Term> chain, std::uint32_t source, SliceBuffers& out,
                              std::vector<Term>& image) {
  // As the general path's emit_faces: signed section edges chained into closed loops, each
  // loop one polygon in cycle order; loops start at the smallest unused tail.
  Incidence& edges = out.boundary[0];
  steps_.clear();
  for (const Term& t : chain) {
    const auto e = edges.ids(t.id);
    const int sign = t.coef > 0 ? 1 : -1;
    if (std::abs(t.coef) != 1) return fail(FallbackReason::Multiplicity);
    steps_.push_back({sign > 0 ? e[0] : e[1], sign > 0 ? e[1] : e[0], t.id, sign, false});
  }
  // With distinct tails any sort gives the general path's order (repeated tails, a pinched
  // cut, are left to the general path); a cell's cut usually has a handful of steps.
  // A total order (steps leaving one vertex by edge, then direction), so the loops a vertex
  // starts several of come out the same with every standard library's sort.
  const auto before = [](const Step& a, const Step& b) {
    if (a.tail != b.tail) return a.tail < b.tail;
    if (a.edge != b.edge) return a.edge < b.edge;
    return a.sign < b.sign;
  };
  if (steps_.size() <= 16) {
    for (std::size_t i = 1; i < steps_.size(); ++i)
      for (std::size_t j = i; j > 0 && before(steps_[j], steps_[j - 1]); --j)
        std::swap(steps_[j], steps_[j - 1]);
  } else {
    std::sort(steps_.begin(), steps_.end(), before);
  }
  for (std::size_t i = 1; i < steps_.size(); ++i)
    if (steps_[i].tail == steps_[i - 1].tail) return fail(FallbackReason::CellCut);
  auto find_from = [&](std::uint32_t tail) -> Step* {
    auto it = std::lower_bound(steps_.begin(), steps_.end(), tail,
                               [](const Step& s, std::uint32_t v) { return s.tail < v; });
    for (; it != steps_.end() && it->tail == tail; ++it)
      if (!it->used) return &*it;
    return nullptr;
  };
  Incidence& faces = out.boundary[1];
  for (std::size_t start = 0; start < steps_.size(); ++start) {
    if (steps_[start].used) continue;
    row_ids_.clear();
    row_signs_.clear();
    Step* cur = &steps_[start];
    bool closed = false;
    while (cur && !cur->used) {
      cur->used = true;
      row_ids_.push_back(cur->edge);
      row_signs_.push_back(static_cast<std::int8_t>(cur->sign));
      if (cur->head == steps_[start].tail) {
        closed = true;
        break;
      }
      cur = find_from(cur->head);
    }
    if (!closed || row_ids_.size() < 3) return fail(FallbackReason::CellCut);  // (dropped there)
    image.push_back({static_cast<std::uint32_t>(faces.size()), 1});
    faces.add_row(row_ids_, row_signs_);
    out.source[2].push_back(source);
  }
  return true;
}

bool Slicer::Impl::emit_element(const SliceModel::Compiled& m, int k, std::uint32_t x,
                                SliceBuffers& out, std::vector<std::uint32_t>& facets,
                                std::vector<Term>& image) {
  combine_chain(chain_);  // as the general path does
  if (chain_.empty()) return true;
  const SliceModel::Compiled::Rank& R = m.ranks_[k];
  const int fr = m.dim_ - 1;
  const std::uint32_t model_x = R.model_id.empty() ? x : R.model_id[x];
  if (k == 2) {
    if (chain_.size() != 2 || chain_[0].coef != -chain_[1].coef || std::abs(chain_[0].coef) != 1)
      return fail(FallbackReason::FaceCut);  // cut in more than two points: the general path
    const bool first_is_tail = chain_[0].coef < 0;
    const std::uint32_t ends[2] = {first_is_tail ? chain_[0].id : chain_[1].id,
                                   first_is_tail ? chain_[1].id : chain_[0].id};
    const std::int8_t signs[2] = {-1, 1};
    image.push_back({static_cast<std::uint32_t>(out.boundary[0].size()), 1});
    out.boundary[0].add_row(ends, signs);
    out.source[1].push_back(model_x);
    if (k == fr) facets.push_back(x);
  } else if (k == 3) {
    const std::size_t before = image.size();
    if (!emit_loops(chain_, model_x, out, image)) return false;
    if (k == fr) facets.insert(facets.end(), image.size() - before, x);
  } else {
    row_ids_.clear();
    row_signs_.clear();
    for (const Term& t : chain_) {
      if (std::abs(t.coef) != 1) return fail(FallbackReason::Multiplicity);
      row_ids_.push_back(t.id);
      row_signs_.push_back(static_cast<std::int8_t>(t.coef));
    }
    Incidence& table = out.boundary[k - 2];
    image.push_back({static_cast<std::uint32_t>(table.size()), 1});
    table.add_row(row_ids_, row_signs_);
    out.source[k - 1].push_back(model_x);
  }
  return true;
}

void Slicer::Impl::mark_parents(const SliceModel::Compiled& m, int k, std::uint32_t x) {
  const SliceModel::Compiled::Up up = m.up(k);
  std::vector<std::uint64_t>& bits = mark_[k + 1];
  for (std::uint32_t i = up.begin(x), end = up.end(x); i < end; ++i) {
    const std::uint32_t y = up.ids[i] & SliceModel::Compiled::kUpIndex;
    bits[y >> 6] |= std::uint64_t{1} << (y & 63);
  }
}

bool Slicer::Impl::fast_slice(const SliceModel::Compiled& m, const Placement& pl,
                              const SliceOptions& options, SliceBuffers& out) {
  prepare(m);
  if (fast_slice_marked(m, pl, options, out)) return true;
  clear_marks(m);
  return false;
}

void Slicer::Impl::clear_marks(const SliceModel::Compiled& m) {
  // Given up half way: no marks may survive into the next slice.
  for (int k = 1; k <= m.top_; ++k) std::fill(mark_[k].begin(), mark_[k].end(), 0);
}

void Slicer::Impl::prepare(const SliceModel::Compiled& m) {
  const int top = m.top_;
  const std::size_t nv = m.nv_;
  if (++gen_ == 0) {  // wrapped: forget every stamp
    for (auto& im : images_) std::fill(im.begin(), im.end(), Image{});
    gen_ = 1;
  }
  if (s_.size() < nv) s_.resize(nv), side_.resize(nv);
  if (images_.size() < static_cast<std::size_t>(top + 1))
    images_.resize(top + 1), terms_.resize(top + 1);
  if (mark_.size() < static_cast<std::size_t>(top + 1)) mark_.resize(top + 1);
  // The R^4 kernel needs the images of ranks 3 and up only (cut_upper above its polygons); the
  // generic gathering sizes the rest when it runs (size_images).
  const int from = m.dim_ == 4 && top >= 3 ? 3 : 1;
  for (int k = 1; k <= top; ++k) {
    const std::size_t count = m.ranks_[k].count;
    if (k >= from && images_[k].size() < count) images_[k].resize(count);
    terms_[k].clear();
    if (mark_[k].size() < (count + 63) / 64) mark_[k].resize((count + 63) / 64, 0);
  }
}

void Slicer::Impl::size_images(const SliceModel::Compiled& m) {
  for (int k = 1; k <= m.top_; ++k) {
    const std::size_t count = m.ranks_[k].count;
    if (images_[k].size() < count) images_[k].resize(count);
  }
}

void Slicer::Impl::start_buffers(const SliceModel::Compiled& m, const Placement& pl,
                                 SliceBuffers& out) {
  start_kernel_buffers(m, pl, out);
  // ... and the lists it keeps emptied as well: every table and list of the slice is empty.
  out.coords.clear();
  out.vertex_source.clear();
  section_edge_.clear();
  facet_internal_.clear();
  out.facet_normals.clear();
  for (std::size_t r = 0; r < std::min<std::size_t>(2, out.boundary.size()); ++r)
    out.boundary[r].clear();
  for (std::size_t r = 1; r < std::min<std::size_t>(3, out.source.size()); ++r)
    out.source[r].clear();
}

void Slicer::Impl::start_kernel_buffers(const SliceModel::Compiled& m, const Placement& pl,
                                        SliceBuffers& out) {
  // The buffers' plane, frame and flags, their tables and lists for the model's ranks, the
  // tables above the polygons and the lists above theirs empty. What the kernel writes whole at
  // its final size (vertices and their sources, coordinates, section edges, polygons, their
  // sources, facet normals, the section-to-model maps) keeps its length, so that sizing it
  // initialises only what it grows by (start_buffers empties those too).
  const int n = m.dim_;
  out.reused_topology = false;
  out.general = false;
  out.fallback = FallbackReason::None;
  out.cache_valid_ = false;
  out.dim = n - 1;
  out.plane.normal = pl.plane->normal;
  out.plane.offset = pl.offset;
  out.frame_normal_.assign(pl.plane->normal.data(), pl.plane->normal.data() + n);
  out.frame_basis_.assign(pl.basis, pl.basis + n * (n - 1));
  const int top = std::max(1, std::min(m.top_ - 1, n - 1));
  if (out.boundary.size() != static_cast<std::size_t>(top) ||
      out.source.size() != static_cast<std::size_t>(top) + 1) {
    out.set_ranks(top);
    return;
  }
  for (std::size_t r = 2; r < out.boundary.size(); ++r) out.boundary[r].clear();
  out.source[0].clear();
  for (std::size_t r = 3; r < out.source.size(); ++r) out.source[r].clear();
}

bool Slicer::Impl::crossing(const SliceModel::Compiled& m, std::uint32_t e, double* t_out) const {
  const std::uint32_t a = m.ranks_[1].ids[2 * e], b = m.ranks_[1].ids[2 * e + 1];
  const double t = s_[a] / (s_[a] - s_[b]);
  *t_out = t;
  return !m.crossing_test(near_parallel_)(a, b, s_[a], s_[b], t);
}

bool Slicer::Impl::add_crossing(const SliceModel::Compiled& m, std::uint32_t e, SliceBuffers& out) {
  double t;
  if (!crossing(m, e, &t)) return fail(FallbackReason::Weld);
  const SliceModel::Compiled::Rank& E = m.ranks_[1];
  const std::uint32_t a = E.ids[2 * e];
  const std::uint32_t v = static_cast<std::uint32_t>(out.vertex_source.size());
  out.vertex_source.push_back({E.model_id.empty() ? e : E.model_id[e], 1, t});
  section_edge_.push_back(e);
  images_[1][e] = {gen_, static_cast<std::uint32_t>(terms_[1].size()), 1};
  terms_[1].push_back({v, side_[a] == Side::Negative ? 1 : -1});
  mark_parents(m, 1, e);
  return true;
}

namespace {

// The R^4 vertex pass over every vertex: the signed value n.x - d of vertices [v, nv) (four
// coordinates each in P), summed in the fixed order of slicer_detail::height, into sv, and
// their sides into sd; true when one is on the plane (within tol). The scalar form, which also
// finishes what classify_vertices_r4_sse2 leaves.
bool classify_vertices_r4_scalar(const double* P, std::uint32_t v, std::uint32_t nv,
                                 const double* nm, double dm, double tol, double* sv, Side* sd) {
  const double n0 = nm[0], n1 = nm[1], n2 = nm[2], n3 = nm[3];
  bool on = false;
  for (; v < nv; ++v) {
    const double* x = P + 4 * v;
    double h = n0 * x[0];
    h += n1 * x[1];
    h += n2 * x[2];
    h += n3 * x[3];
    const double sval = h - dm;
    const std::int8_t sgn = static_cast<std::int8_t>((sval > tol) - (sval < -tol));
    sv[v] = sval;
    sd[v] = static_cast<Side>(sgn);
    on |= sgn == 0;
  }
  return on;
}

#if defined(__SSE2__)
// classify_vertices_r4_scalar for the vertices [0, *done), two per register, each lane the same
// operations in the same order (the same bits); eight vertices' sides are packed to bytes and
// stored at once. A side is the difference of the comparison masks (-1 below, 1 above, 0 on the
// plane). *done: the first vertex left to the scalar form.
bool classify_vertices_r4_sse2(const double* P, std::uint32_t nv, const double* nm, double dm,
                               double tol, double* sv, Side* side_out, std::uint32_t* done) {
  std::int8_t* const sd = reinterpret_cast<std::int8_t*>(side_out);  // (Side is one signed byte)
  const double n0 = nm[0], n1 = nm[1], n2 = nm[2], n3 = nm[3];
  std::uint32_t v = 0;
  const __m128d c0 = _mm_set1_pd(n0), c1 = _mm_set1_pd(n1), c2 = _mm_set1_pd(n2),
                c3 = _mm_set1_pd(n3), cd = _mm_set1_pd(dm), hi = _mm_set1_pd(tol),
                lo = _mm_set1_pd(-tol);
  // Two vertices per lane pair, each lane the same operations in the same order (same
  // bits); eight vertices' sides packed to bytes and stored at once. A side is the
  // difference of the comparison masks (-1 below, 1 above, 0 on the plane).
  const auto values = [&](std::uint32_t w) {
    const double* x = P + 4 * w;
    const __m128d a01 = _mm_loadu_pd(x), a23 = _mm_loadu_pd(x + 2);
    const __m128d b01 = _mm_loadu_pd(x + 4), b23 = _mm_loadu_pd(x + 6);
    __m128d h = _mm_mul_pd(c0, _mm_unpacklo_pd(a01, b01));
    h = _mm_add_pd(h, _mm_mul_pd(c1, _mm_unpackhi_pd(a01, b01)));
    h = _mm_add_pd(h, _mm_mul_pd(c2, _mm_unpacklo_pd(a23, b23)));
    h = _mm_add_pd(h, _mm_mul_pd(c3, _mm_unpackhi_pd(a23, b23)));
    const __m128d sval = _mm_sub_pd(h, cd);
    _mm_storeu_pd(sv + w, sval);
    return _mm_sub_epi64(_mm_castpd_si128(_mm_cmplt_pd(sval, lo)),
                         _mm_castpd_si128(_mm_cmpgt_pd(sval, hi)));
  };
  __m128i zeros = _mm_setzero_si128();  // (a byte per vertex: 0xff where on the plane)
  for (; v + 8 <= nv; v += 8) {
    // The low 32 bits of each 64-bit side, four vertices per register, then packed.
    const auto low = [](__m128i a, __m128i b) {
      return _mm_unpacklo_epi64(_mm_shuffle_epi32(a, _MM_SHUFFLE(3, 3, 2, 0)),
                                _mm_shuffle_epi32(b, _MM_SHUFFLE(3, 3, 2, 0)));
    };
    const __m128i s03 = low(values(v), values(v + 2));
    const __m128i s47 = low(values(v + 4), values(v + 6));
    const __m128i w16 = _mm_packs_epi32(s03, s47);
    const __m128i b8 = _mm_packs_epi16(w16, w16);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(sd + v), b8);
    zeros = _mm_or_si128(zeros, _mm_cmpeq_epi8(b8, _mm_setzero_si128()));
  }
  int on_bits = _mm_movemask_epi8(zeros) & 0xff;
  for (; v + 2 <= nv; v += 2) {
    const __m128i sides = values(v);
    const int s0 = _mm_cvtsi128_si32(sides);
    const int s1 = _mm_cvtsi128_si32(_mm_shuffle_epi32(sides, _MM_SHUFFLE(3, 3, 3, 2)));
    sd[v] = static_cast<std::int8_t>(s0);
    sd[v + 1] = static_cast<std::int8_t>(s1);
    on_bits |= (s0 == 0) | (s1 == 0);
  }
  *done = v;
  return on_bits != 0;
}
#endif

// The vertex pass of an R^4 slice that touches every vertex, without early exits: the values
// and sides `value` in fast_slice_marked gives, SSE2 where there is SSE2.
bool classify_vertices_r4(const double* P, std::uint32_t nv, const double* nm, double dm,
                          double tol, double* sv, Side* sd) {
  std::uint32_t v = 0;
  bool on = false;
#if defined(__SSE2__)
  on = classify_vertices_r4_sse2(P, nv, nm, dm, tol, sv, sd, &v);
#endif
  return classify_vertices_r4_scalar(P, v, nv, nm, dm, tol, sv, sd) || on;
}

}  // namespace

bool Slicer::Impl::fast_slice_marked(const SliceModel::Compiled& m, const Placement& pl,
                                     const SliceOptions& options, SliceBuffers& out) {
  const int n = m.dim_;
  const std::size_t nc = m.cluster_count();
  touched_.clear();
  for (std::size_t c = 0; c < nc; ++c)
    if (!options.cull ||
        pl.meets(&m.cluster_sphere_[c * (n + 1)], m.cluster_sphere_[c * (n + 1) + n]))
      touched_.push_back(static_cast<std::uint32_t>(c));
  // Signed values of the touched clusters' vertices (of all vertices, once each, when every
  // cluster is touched: the clusters' vertex lists share their border vertices).
  const double* P = m.positions();
  auto value = [&](std::uint32_t v) {
    const double s = height(pl.nm, P + v * n, n) - pl.dm;
    const Side side = classify_side(s, pl.tol);
    s_[v] = s;
    side_[v] = side;
    return side != Side::On;  // on the plane: symbolic perturbation, the general path
  };
  if (touched_.size() == nc && n == 4) {
    // Every vertex (each belongs to a cluster): one pass without early exits, the same values
    // and sides as `value` gives.
    const bool on = classify_vertices_r4(P, static_cast<std::uint32_t>(m.nv_), pl.nm, pl.dm, pl.tol,
                                         s_.data(), side_.data());
    if (on) return fail(FallbackReason::OnPlane);
  } else if (touched_.size() == nc && nc > 1) {
    const std::uint32_t nv = static_cast<std::uint32_t>(m.nv_);
    for (std::uint32_t v = 0; v < nv; ++v)
      if (!value(v)) return fail(FallbackReason::OnPlane);
  } else {
    for (auto c : touched_)
      if (!m.each_cluster_vertex(c, value)) return fail(FallbackReason::OnPlane);
  }
  if (kernel_ && n == 4 && m.top_ >= 3) {
    const KernelResult done = kernel_slice(m, pl, out);
    if (done == KernelResult::General) return false;
    if (done == KernelResult::Done) {
      if (options.reuse_topology) remember(m, pl, out);
      ++fast_count_;
      return true;
    }
    clear_marks(m);  // something for the generic gathering: it cuts the slice from the start
  }
  size_images(m);
  // Rank 1: a section vertex per crossing edge, in id order.
  start_buffers(m, pl, out);
  const SliceModel::Compiled::Rank& E = m.ranks_[1];
  for (auto c : touched_)
    for (std::uint32_t e = m.begin_[0][c]; e < m.begin_[0][c + 1]; ++e)
      if (side_[E.ids[2 * e]] != side_[E.ids[2 * e + 1]] && !add_crossing(m, e, out)) return false;
  if (out.vertex_source.empty()) {
    clear_to_empty(out, n - 1);
    if (options.reuse_topology) remember(m, pl, out);
    ++fast_count_;
    return true;
  }
  if (!cut_upper(m, pl, out)) return false;
  // The topology cache is kept only for callers that use it (animation frames).
  if (options.reuse_topology) remember(m, pl, out);
  ++fast_count_;
  return true;
}

bool Slicer::Impl::cut_upper(const SliceModel::Compiled& m, const Placement& pl, SliceBuffers& out,
                             int from) {
  const int fr = m.dim_ - 1;
  const int top = m.top_;
  // Ranks 2..top: only the elements a crossing reaches (marked through the cofaces), in
  // increasing id order within each touched cluster, so the order is that of a full scan.
  for (int k = from; k <= top; ++k) {
    const SliceModel::Compiled::Rank& R = m.ranks_[k];
    const std::size_t count = R.offsets.size() - 1;
    std::vector<std::uint64_t>& bits = mark_[k];
    // (rank k - 1 is complete: its images and terms stay put while rank k is cut)
    const Image* below = images_[k - 1].data();
    const Term* below_terms = terms_[k - 1].data();
    const std::uint32_t* offsets = R.offsets.data();
    const std::uint32_t* ids = R.ids.data();
    const std::int8_t* signs = R.signs.data();
    const std::uint32_t gen = gen_;
    auto process = [&](std::uint32_t x) -> bool {
      chain_.clear();
      for (std::uint32_t i = offsets[x], end = offsets[x + 1]; i < end; ++i) {
        const Image img = below[ids[i]];
        if (img.gen != gen) continue;
        for (std::uint32_t j = img.begin; j < img.begin + img.count; ++j)
          chain_.push_back({below_terms[j].id, -signs[i] * below_terms[j].coef});
      }
      if (chain_.empty()) return true;
      const std::uint32_t first = static_cast<std::uint32_t>(terms_[k].size());
      if (!emit_element(m, k, x, out, facet_internal_, terms_[k])) return false;
      const std::uint32_t produced = static_cast<std::uint32_t>(terms_[k].size()) - first;
      images_[k][x] = {gen_, first, produced};
      if (produced > 0 && k < top) mark_parents(m, k, x);
      return true;
    };
    // The specialised kernel. A convex face is cut in exactly two crossings: one section edge
    // from the crossing whose chain coefficient is -1 to the one with +1, as the generic
    // gathering gives after combine_chain. A cell whose faces each gave one section edge is
    // chained through a next map (the step leaving each section vertex, stamped per cell) from
    // its smallest tail; when that one loop uses every step it is the polygon emit_loops
    // builds (loops start at the smallest tail, steps follow heads). Anything else (more
    // crossings, a face twice, a pinch, several loops, an open chain) goes to `process`, which
    // decides it exactly as before. Returns 1 when done, -1 for `process`.
    Incidence& out_edges = out.boundary[0];
    auto face_kernel = [&](std::uint32_t x) -> int {
      std::uint32_t v[2];
      int c[2];
      int cnt = 0;
      for (std::uint32_t i = offsets[x], end = offsets[x + 1]; i < end; ++i) {
        const Image img = below[ids[i]];
        if (img.gen != gen) continue;
        if (cnt == 2) return -1;
        const Term& t = below_terms[img.begin];
        v[cnt] = t.id;
        c[cnt] = -signs[i] * t.coef;
        ++cnt;
      }
      if (cnt != 2 || v[0] == v[1] || c[0] != -c[1]) return -1;
      const std::uint32_t ends[2] = {c[0] < 0 ? v[0] : v[1], c[0] < 0 ? v[1] : v[0]};
      static constexpr std::int8_t kEdgeSigns[2] = {-1, 1};
      const std::uint32_t first = static_cast<std::uint32_t>(terms_[k].size());
      terms_[k].push_back({static_cast<std::uint32_t>(out_edges.size()), 1});
      out_edges.add_row(ends, kEdgeSigns);
      out.source[1].push_back(R.model_id.empty() ? x : R.model_id[x]);
      if (k == fr) facet_internal_.push_back(x);
      images_[k][x] = {gen, first, 1};
      if (k < top) mark_parents(m, k, x);
      return 1;
    };
    const std::uint32_t* edge_ends = out_edges.all_ids().data();
    auto cell_kernel = [&](std::uint32_t x) -> int {
      if (++stamp_ == 0) forget_stamps();  // wrapped
      const std::uint32_t st = stamp_;
      steps_.clear();
      std::uint32_t lo = no_index, start = 0;
      for (std::uint32_t i = offsets[x], end = offsets[x + 1]; i < end; ++i) {
        const Image img = below[ids[i]];
        if (img.gen != gen) continue;
        if (img.count != 1) return -1;
        const Term& t = below_terms[img.begin];
        if (edge_stamp_[t.id] == st) return -1;
        edge_stamp_[t.id] = st;
        const int sign = -signs[i] * t.coef;
        const std::uint32_t tail = edge_ends[2 * t.id + (sign > 0 ? 0 : 1)];
        const std::uint32_t head = edge_ends[2 * t.id + (sign > 0 ? 1 : 0)];
        if (vertex_stamp_[tail] == st) return -1;  // a pinch
        vertex_stamp_[tail] = st;
        vertex_next_[tail] = static_cast<std::uint32_t>(steps_.size());
        if (tail < lo) lo = tail, start = static_cast<std::uint32_t>(steps_.size());
        steps_.push_back({tail, head, t.id, sign, false});
      }
      const std::size_t ns = steps_.size();
      if (ns < 3) return -1;
      row_ids_.clear();
      row_signs_.clear();
      std::uint32_t cur = start;
      for (;;) {
        const Step& sp = steps_[cur];
        row_ids_.push_back(sp.edge);
        row_signs_.push_back(static_cast<std::int8_t>(sp.sign));
        if (sp.head == lo) break;
        if (row_ids_.size() == ns || vertex_stamp_[sp.head] != st) return -1;
        cur = vertex_next_[sp.head];
      }
      if (row_ids_.size() != ns) return -1;  // several loops
      Incidence& faces = out.boundary[1];
      const std::uint32_t first = static_cast<std::uint32_t>(terms_[k].size());
      terms_[k].push_back({static_cast<std::uint32_t>(faces.size()), 1});
      faces.add_row(row_ids_, row_signs_);
      out.source[2].push_back(R.model_id.empty() ? x : R.model_id[x]);
      if (k == fr) facet_internal_.push_back(x);
      images_[k][x] = {gen, first, 1};
      if (k < top) mark_parents(m, k, x);
      return 1;
    };
    const bool use_kernel = kernel_ && (k == 2 || (k == 3 && fr == 3));
    if (use_kernel && k == 3) {
      const std::size_t nsv = out.vertex_source.size(), nse = out_edges.size();
      if (vertex_stamp_.size() < nsv) vertex_stamp_.resize(nsv, 0), vertex_next_.resize(nsv);
      if (edge_stamp_.size() < nse) edge_stamp_.resize(nse, 0);
    }
    auto kernel_process = [&](std::uint32_t x) -> bool {
      if ((k == 2 ? face_kernel(x) : cell_kernel(x)) > 0) {
        ++kernel_count_;
        return true;
      }
      ++generic_count_;
      return process(x);
    };
    auto visit = [&](std::uint32_t b, std::uint32_t e) {
      return use_kernel ? visit_marked(bits, b, e, kernel_process)
                        : visit_marked(bits, b, e, process);
    };
    if (k == top && m.single_solid_ && k == 3) {
      // The one solid of a polyhedron: its cut's boundary is every section edge, with the
      // sign of the edge's facet in the solid (no gathering over the solid's long row).
      if (bits[0] & 1u) {
        bits[0] = 0;
        chain_.clear();
        for (std::uint32_t i = 0; i < facet_internal_.size(); ++i)
          chain_.push_back({i, -m.solid_sign_[facet_internal_[i]]});
        image_.clear();
        if (!emit_loops(chain_, R.model_id.empty() ? 0 : R.model_id[0], out, image_)) return false;
      }
      continue;
    }
    if (k == top && m.single_solid_) {
      // The one solid bounded by every facet once: its cut is every section facet, in order
      // (a rank >= 3 element lists its facets; finish_fast gives them sign +1).
      if (bits[0] & 1u) {
        bits[0] = 0;
        Incidence& table = out.boundary[k - 2];
        const std::uint32_t nf = static_cast<std::uint32_t>(out.boundary[k - 3].size());
        row_ids_.resize(nf);
        row_signs_.assign(nf, 1);
        for (std::uint32_t i = 0; i < nf; ++i) row_ids_[i] = i;
        table.add_row(row_ids_, row_signs_);
        out.source[k - 1].push_back(R.model_id.empty() ? 0 : R.model_id[0]);
      }
      continue;
    }
    if (k <= fr) {
      for (auto c : touched_)
        if (!visit(m.begin_[k - 1][c], m.begin_[k - 1][c + 1])) return false;
    } else if (!visit(0, static_cast<std::uint32_t>(count))) {
      return false;
    }
  }
  return finish_fast(m, pl, out, section_edge_, facet_internal_);
}

void Slicer::Impl::remember(const SliceModel::Compiled& m, const Placement& pl, SliceBuffers& out) {
  out.cache_model_ = m.serial_;
  out.cache_touched_ = touched_;
  out.cache_side_.clear();
  for (auto c : touched_)
    m.each_cluster_vertex(c, [&](std::uint32_t v) {
      out.cache_side_.push_back(static_cast<std::int8_t>(side_[v]));
      return true;
    });
  out.cache_edge_ = section_edge_;
  out.cache_facet_ = facet_internal_;
  out.cache_reflect_ = pl.reflect;
  out.cache_valid_ = true;
}

bool Slicer::Impl::finish_fast(const SliceModel::Compiled& m, const Placement& pl,
                               SliceBuffers& out, std::span<const std::uint32_t> section_edge,
                               std::span<const std::uint32_t> facet_internal) {
  const int n = m.dim_;
  // Orientation as section(): the facets' cuts face outward for even n, inward for odd n, and
  // a reflecting transform reverses them once more; solids list their facets with +1.
  const int ofr = n - 2;
  if (pl.reflect != (n % 2 == 1)) {
    Incidence& table = out.boundary[ofr - 1];
    for (std::size_t f = 0; f < table.size(); ++f) {
      auto ids = table.ids_mut(f);
      auto signs = table.signs_mut(f);
      if (ofr == 1) {
        std::swap(ids[0], ids[1]);
      } else {
        std::reverse(ids.begin(), ids.end());
        std::reverse(signs.begin(), signs.end());
        for (auto& s : signs) s = static_cast<std::int8_t>(-s);
      }
    }
  }
  if (static_cast<int>(out.boundary.size()) >= n - 1 && n - 1 >= 2) {
    Incidence& solids = out.boundary[n - 2];
    for (std::size_t i = 0; i < solids.size(); ++i)
      for (auto& s : solids.signs_mut(i)) s = 1;
  }
  return write_geometry(m, pl, out, section_edge, facet_internal);
}

namespace {

// The vertex and facet-normal passes of write_geometry with the dimension fixed at compile
// time (the loops unroll; the arithmetic is the same, term for term). False when a facet is
// nearly parallel to the plane.
template <int N>
bool geometry_pass(const double* P, const std::uint32_t* edge_ids, const double* M, const double* c,
                   const double* Nm, const double* facet_normals, const std::uint32_t* facet_id,
                   std::span<const std::uint32_t> section_edge, const VertexSource* source,
                   std::span<const std::uint32_t> facet_internal, double* coords, double* normals) {
  constexpr int O = N - 1;
#if defined(__SSE2__)
  if constexpr (N == 4) {
    // The same operations, each lane its own term in the same order (so the same bits): rows
    // 0 and 1 of M and Nm two at a time, the point's coordinates two at a time. Every matrix
    // entry is loaded into a register once, before the loops (the output stores could alias
    // the matrices, so the compiler would otherwise reload them per vertex and per facet).
    {
      __m128d m01[4], m2[4];
      for (int j = 0; j < 4; ++j)
        m01[j] = _mm_set_pd(M[4 + j], M[j]), m2[j] = _mm_load_sd(M + 8 + j);
      const __m128d c01 = _mm_loadu_pd(c), c2 = _mm_load_sd(c + 2);
      const __m128d one = _mm_set1_pd(1.0);
      const std::uint32_t* const se = section_edge.data();
      const std::size_t nv = section_edge.size();
      for (std::size_t i = 0; i < nv; ++i) {
        const std::uint32_t e = se[i];
        const double* pa = P + edge_ids[2 * e] * 4;
        const double* pb = P + edge_ids[2 * e + 1] * 4;
        const __m128d t = _mm_set1_pd(source[i].t);
        const __m128d u = _mm_sub_pd(one, t);
        const __m128d x01 =
            _mm_add_pd(_mm_mul_pd(u, _mm_loadu_pd(pa)), _mm_mul_pd(t, _mm_loadu_pd(pb)));
        const __m128d x23 =
            _mm_add_pd(_mm_mul_pd(u, _mm_loadu_pd(pa + 2)), _mm_mul_pd(t, _mm_loadu_pd(pb + 2)));
        const __m128d xj[4] = {_mm_unpacklo_pd(x01, x01), _mm_unpackhi_pd(x01, x01),
                               _mm_unpacklo_pd(x23, x23), _mm_unpackhi_pd(x23, x23)};
        __m128d sum = c01;
        for (int j = 0; j < 4; ++j) sum = _mm_add_pd(sum, _mm_mul_pd(m01[j], xj[j]));
        __m128d s2 = c2;
        for (int j = 0; j < 4; ++j) s2 = _mm_add_sd(s2, _mm_mul_sd(m2[j], xj[j]));
        _mm_storeu_pd(coords + i * 3, sum);
        _mm_store_sd(coords + i * 3 + 2, s2);
      }
    }
    __m128d n01[4], n2[4];
    for (int j = 0; j < 4; ++j)
      n01[j] = _mm_set_pd(Nm[4 + j], Nm[j]), n2[j] = _mm_load_sd(Nm + 8 + j);
    const std::uint32_t* const fi = facet_internal.data();
    const std::size_t nfacets = facet_internal.size();
    for (std::size_t f = 0; f < nfacets; ++f) {
      const std::uint32_t x = fi[f];
      const double* nf = facet_normals + std::size_t{facet_id ? facet_id[x] : x} * 4;
      __m128d y01 = _mm_setzero_pd(), y2 = _mm_setzero_pd();
      for (int j = 0; j < 4; ++j) {
        const __m128d v = _mm_set1_pd(nf[j]);
        y01 = _mm_add_pd(y01, _mm_mul_pd(n01[j], v));
        y2 = _mm_add_sd(y2, _mm_mul_sd(n2[j], v));
      }
      // |y|^2 in registers, summed as the scalar form sums it: ((0 + y0^2) + y1^2) + y2^2
      // (0 + y0^2 is y0^2, a square being +0 at least).
      const __m128d sq = _mm_mul_pd(y01, y01);
      const __m128d len2 = _mm_add_sd(_mm_add_sd(sq, _mm_unpackhi_pd(sq, sq)), _mm_mul_sd(y2, y2));
      const double len = std::sqrt(_mm_cvtsd_f64(len2));
      if (len < tol::near_parallel_normal) return false;
      const __m128d l = _mm_set1_pd(len);
      _mm_storeu_pd(normals + f * 3, _mm_div_pd(y01, l));
      _mm_store_sd(normals + f * 3 + 2, _mm_div_sd(y2, l));
    }
    return true;
  }
#endif
  // Vertices: y = M ((1 - t) a + t b) + c.
  for (std::size_t i = 0; i < section_edge.size(); ++i) {
    const std::uint32_t e = section_edge[i];
    const double* pa = P + edge_ids[2 * e] * N;
    const double* pb = P + edge_ids[2 * e + 1] * N;
    const double t = source[i].t;
    double x[N];
    for (int j = 0; j < N; ++j) x[j] = (1.0 - t) * pa[j] + t * pb[j];
    for (int r = 0; r < O; ++r) {
      double sum = c[r];
      for (int j = 0; j < N; ++j) sum += M[r * N + j] * x[j];
      coords[i * O + r] = sum;
    }
  }
  // Facet normals: the model facets' normals through A^{-T}, projected, unit.
  for (std::size_t f = 0; f < facet_internal.size(); ++f) {
    const std::uint32_t x = facet_internal[f];
    const double* nf = facet_normals + std::size_t{facet_id ? facet_id[x] : x} * N;
    double y[O], len2 = 0.0;
    for (int r = 0; r < O; ++r) {
      double sum = 0.0;
      for (int j = 0; j < N; ++j) sum += Nm[r * N + j] * nf[j];
      y[r] = sum;
      len2 += sum * sum;
    }
    const double len = std::sqrt(len2);
    // Nearly parallel to the plane: the general path's area vector.
    if (len < tol::near_parallel_normal) return false;
    for (int r = 0; r < O; ++r) normals[f * O + r] = y[r] / len;
  }
  return true;
}

}  // namespace

bool Slicer::Impl::write_geometry(const SliceModel::Compiled& m, const Placement& pl,
                                  SliceBuffers& out, std::span<const std::uint32_t> section_edge,
                                  std::span<const std::uint32_t> facet_internal, bool facets) {
  const int n = m.dim_;
  const int o = n - 1;
  out.coords.resize(section_edge.size() * o);
  if (facets)
    out.facet_normals.resize(facet_internal.size() * o);
  else
    facet_internal = {};
  const auto pass = n == 4 ? geometry_pass<4> : geometry_pass<3>;
  // The compiled copy of the facet normals, or (clustered models) the complex's own.
  const bool copied = !m.facet_normals_.empty() || m.ranks_[o].model_id.empty();
  const double* fn = copied ? m.facet_normals_.data() : m.model_->facet_normals().data();
  const std::uint32_t* fid = copied ? nullptr : m.ranks_[o].model_id.data();
  if (!pass(m.positions(), m.ranks_[1].ids.data(), pl.M, pl.c, pl.N, fn, fid, section_edge,
            out.vertex_source.data(), facet_internal, out.coords.data(), out.facet_normals.data()))
    return fail(FallbackReason::NearParallel);
  return true;
}

bool Slicer::Impl::reuse(const SliceModel::Compiled& m, const Placement& pl,
                         const SliceOptions& options, SliceBuffers& out) {
  if (!out.cache_valid_ || out.cache_model_ != m.serial_ || out.cache_reflect_ != pl.reflect)
    return false;
  const int n = m.dim_;
  const std::size_t nv = m.nv_;
  const std::size_t nc = m.cluster_count();
  if (s_.size() < nv) s_.resize(nv), side_.resize(nv);
  touched_.clear();
  for (std::size_t c = 0; c < nc; ++c)
    if (!options.cull ||
        pl.meets(&m.cluster_sphere_[c * (n + 1)], m.cluster_sphere_[c * (n + 1) + n]))
      touched_.push_back(static_cast<std::uint32_t>(c));
  if (touched_ != out.cache_touched_) return false;
  const double* P = m.positions();
  std::size_t k = 0;
  for (auto c : touched_)
    if (!m.each_cluster_vertex(c, [&](std::uint32_t v) {
          const double s = height(pl.nm, P + v * n, n) - pl.dm;
          const Side side = classify_side(s, pl.tol);
          if (side == Side::On || static_cast<std::int8_t>(side) != out.cache_side_[k++])
            return false;
          s_[v] = s;
          return true;
        }))
      return false;
  // Same sides: the same connectivity. New crossing parameters, positions and normals.
  for (std::size_t i = 0; i < out.cache_edge_.size(); ++i)
    if (!crossing(m, out.cache_edge_[i], &out.vertex_source[i].t)) return false;
  out.plane = *pl.plane;
  if (!write_geometry(m, pl, out, out.cache_edge_, out.cache_facet_)) return false;
  out.reused_topology = true;
  out.general = false;
  out.fallback = FallbackReason::None;
  return true;
}

// --- conversion -----------------------------------------------------------------------------

Section to_section(const SliceBuffers& b) {
  Section sec = to_section_untested(b);
  sec.self_intersecting = self_intersects(sec.complex);
  return sec;
}

Section to_section_untested(const SliceBuffers& b) {
  // Each array of the Section is allocated once at its final size (no default table grown,
  // no temporary complex moved in): what the caller frees is all that is allocated.
  Section sec;
  const int dim = b.dim;
  // The slice's own basis when it was computed for this very normal (bit for bit: the same
  // function of the same numbers), else computed.
  const auto n = b.plane.normal.size();
  if (b.frame_basis_.size() == static_cast<std::size_t>(n * (n - 1)) &&
      b.frame_normal_.size() == static_cast<std::size_t>(n) &&
      std::memcmp(b.frame_normal_.data(), b.plane.normal.data(), n * sizeof(double)) == 0) {
    sec.frame.plane = b.plane;
    sec.frame.basis = Eigen::Map<const Eigen::MatrixXd>(b.frame_basis_.data(), n, n - 1);
  } else {
    sec.frame = HyperplaneFrame(b.plane);
  }
  sec.source_fingerprint = b.source_fingerprint;
  if (sec.complex.ambient_dim() != dim) sec.complex = Complex(dim);
  Complex& c = sec.complex;
  const Eigen::Index nv = static_cast<Eigen::Index>(b.vertex_source.size());
  c.set_positions(Eigen::Map<const Eigen::MatrixXd>(b.coords.data(), dim, nv));
  // All tables at once (boundary_mut creates the lower ones), then each filled in place.
  if (!b.boundary.empty()) c.boundary_mut(static_cast<int>(b.boundary.size()));
  for (std::size_t r = 1; r <= b.boundary.size(); ++r) {
    const Incidence& from = b.boundary[r - 1];
    const Incidence::Storage to = c.boundary_mut(static_cast<int>(r)).storage();
    to.offsets.assign(from.offsets().begin(), from.offsets().end());
    to.ids.assign(from.all_ids().begin(), from.all_ids().end());
    to.signs.assign(from.all_signs().begin(), from.all_signs().end());
  }
  const int ofr = dim - 1;
  if (ofr >= 1 && c.count(ofr) > 0 && !b.facet_normals.empty())
    c.set_facet_normals(Eigen::Map<const Eigen::MatrixXd>(
        b.facet_normals.data(), dim, static_cast<Eigen::Index>(b.facet_normals.size()) / dim));
  sec.vertex_source.assign(b.vertex_source.begin(), b.vertex_source.end());
  sec.source.resize(std::max<std::size_t>(b.source.size(), 1));
  for (std::size_t r = 0; r < b.source.size(); ++r)
    sec.source[r].assign(b.source[r].begin(), b.source[r].end());
  return sec;
}

}  // namespace cw4d
