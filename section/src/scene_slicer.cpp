#include "cw4d/section/slicer.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/fork_join.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "general.hpp"
#include "slicer_detail.hpp"
#include "slicer_impl.hpp"

namespace cw4d {

// --- scenes ---------------------------------------------------------------------------------

// What a SceneSlicer keeps: the compiled models, every object's placement and bounding sphere,
// one Slicer per thread, the buffers between calls and the placements for the last normal.
class SceneSlicer::Impl {
 public:
  Impl(const Scene& scene, const SliceModelOptions& options);
  void slice(const Hyperplane& plane, SceneSlice& out, unsigned threads,
             const SliceOptions& options);

  std::vector<std::unique_ptr<SliceModel>> models_;
  std::vector<const SliceModel*> model_of_;  // per object
  std::vector<AffineTransform> transforms_;  // copied: the scene may move its objects afterwards
  std::vector<double> centres_;              // world-space bounding-sphere centres, dim_ per object
  std::vector<double> reach_;                // their radii plus the culling margin
  std::vector<Slicer> slicers_;
  std::vector<std::uint32_t> touched_;
  // Buffers between calls: those no object of the output needs (their storage kept), and the
  // vector the output's buffers are rearranged into.
  std::vector<SliceBuffers> spare_, arranged_;
  std::vector<std::uint32_t> need_, left_;  // arrange()'s: new entries, held entries free
  void arrange(SceneSlice& out);
  struct Placements;  // the touched objects' placements for the last normal
  std::shared_ptr<Placements> placements_;
  int dim_ = 0;
};

SceneSlicer::SceneSlicer(const Scene& scene, const SliceModelOptions& options)
    : impl_(std::make_unique<Impl>(scene, options)) {}
SceneSlicer::~SceneSlicer() = default;
SceneSlicer::SceneSlicer(SceneSlicer&&) noexcept = default;
SceneSlicer& SceneSlicer::operator=(SceneSlicer&&) noexcept = default;

std::size_t SceneSlicer::size() const {
  return impl_->model_of_.size();
}

void SceneSlicer::slice(const Hyperplane& plane, SceneSlice& out, unsigned threads,
                        const SliceOptions& options) {
  impl_->slice(plane, out, threads, options);
}

std::size_t SceneSlicer::touched() const {
  return impl_->touched_.size();
}

std::span<const std::uint32_t> SceneSlicer::touched_objects() const {
  return impl_->touched_;
}

SceneSlicer::Impl::Impl(const Scene& scene, const SliceModelOptions& options) : dim_(scene.dim()) {
  std::unordered_map<const Complex*, const SliceModel*> compiled;
  for (const SceneObject& obj : scene.objects) {
    const Complex* c = obj.complex.get();
    auto it = compiled.find(c);
    if (it == compiled.end()) {
      models_.push_back(std::make_unique<SliceModel>(*c, options));
      it = compiled.emplace(c, models_.back().get()).first;
    }
    const SliceModel& m = *it->second;
    // The sphere in the world: centre moved, radius stretched by the largest singular value.
    const double stretch =
        Eigen::JacobiSVD<Eigen::MatrixXd>(obj.transform.linear()).singularValues()(0);
    const Eigen::VectorXd centre = obj.transform.apply(m.centre());
    const double radius = stretch * m.radius();
    model_of_.push_back(&m);
    transforms_.push_back(obj.transform);
    centres_.insert(centres_.end(), centre.data(), centre.data() + centre.size());
    // Culled when |n.c - d| > radius + margin (tol::bounding_sphere_margin_rel of the size).
    reach_.push_back(radius + tol::bounding_sphere_margin_rel * (radius + centre.norm()));
  }
}

// The touched objects' placements for one normal: slot[i] indexes pl for object i (no_index: none
// made yet); a new normal forgets them all.
struct SceneSlicer::Impl::Placements {
  Eigen::VectorXd normal;
  std::vector<std::uint32_t> slot, used;
  std::vector<Slicer::Placement> pl;
  // Culling for the same normal: the objects by height n.c (key sorted, order their indices,
  // key_reach their reaches), the largest sum |n_j c_j| and reach; a bit per object (all
  // clear between calls) that lists the touched ones in increasing order.
  std::size_t calls = 0;
  std::vector<double> key, key_reach;
  std::vector<std::uint32_t> order;
  std::vector<std::uint64_t> bits;
  double scale = 0.0, max_reach = 0.0;
  // Per touched object (in the order of the output), what the slice reads: read from the
  // per-object arrays in one pass, so that cutting reads them contiguously.
  struct Job {
    const SliceModel* model;
    const AffineTransform* transform;
    std::uint32_t slot;  // no_index: no placement (the plain slice)
    bool fresh;          // the placement is new (its set() is still to run)
  };
  std::vector<Job> jobs;
};

// out.buffers[k] holds what the previous call into out cut for object out.objects[k]: an object
// touched again takes its own buffers, the others those left over, then the spares; buffers
// left after that become spares. (Only the storage and the topology cache depend on which
// buffers an object gets, not the result.)
void SceneSlicer::Impl::arrange(SceneSlice& out) {
  std::vector<SliceBuffers>& held = out.buffers;
  const std::size_t n = touched_.size();
  const std::size_t m = std::min(out.objects.size(), held.size());
  if (m == n && held.size() == n &&
      std::equal(touched_.begin(), touched_.end(), out.objects.begin()))
    return;
  // Both lists increase: one merge pass pairs them; every held entry is taken or left once.
  arranged_.resize(n);
  need_.clear();
  left_.clear();
  std::size_t i = 0;
  for (std::size_t k = 0; k < n; ++k) {
    while (i < m && out.objects[i] < touched_[k]) left_.push_back(static_cast<std::uint32_t>(i++));
    if (i < m && out.objects[i] == touched_[k])
      std::swap(arranged_[k], held[i++]);
    else
      need_.push_back(static_cast<std::uint32_t>(k));
  }
  for (; i < held.size(); ++i) left_.push_back(static_cast<std::uint32_t>(i));
  std::size_t next = 0;
  for (std::uint32_t k : need_) {
    if (next < left_.size()) {
      std::swap(arranged_[k], held[left_[next++]]);
    } else if (!spare_.empty()) {
      std::swap(arranged_[k], spare_.back());
      spare_.pop_back();
    }
  }
  for (; next < left_.size(); ++next) spare_.push_back(std::move(held[left_[next]]));
  held.swap(arranged_);
}

void SceneSlicer::Impl::slice(const Hyperplane& plane, SceneSlice& out, unsigned threads,
                              const SliceOptions& options) {
  if (!model_of_.empty() && plane.dim() != dim_)
    throw InputError("hyperplane in R^" + std::to_string(plane.dim()) + " for a scene in R^" +
                     std::to_string(dim_));
  const std::size_t count = model_of_.size();
  if (!placements_) placements_ = std::make_shared<Placements>();
  Placements& cache = *placements_;
  if (cache.slot.size() != count) cache.slot.assign(count, no_index), cache.used.clear();
  if (cache.normal.size() != plane.normal.size() || cache.normal != plane.normal) {
    for (std::uint32_t i : cache.used) cache.slot[i] = no_index;
    cache.used.clear();
    cache.pl.clear();
    cache.normal = plane.normal;
    cache.calls = 0;
    cache.order.clear();
  }
  // The culling test: the distance summed from -d in coordinate order, against the reach.
  touched_.clear();
  const double* nrm = plane.normal.data();
  const int dim = dim_;
  const double* centres = centres_.data();
  const double* reach = reach_.data();
  auto culled = [&](std::size_t i) {
    const double* c = centres + i * dim;
    double dist = -plane.offset;
    for (int j = 0; j < dim; ++j) dist += nrm[j] * c[j];
    return std::abs(dist) > reach[i];
  };
  ++cache.calls;
  if (options.cull && cache.calls >= 2 && count >= 256) {
    // The same normal again (a sweep or an animation of the offset): the objects by height n.c
    // (sorted once per normal), so only those whose height lies within the largest reach (plus
    // far more than the rounding of either sum) of the offset are tested; every other object
    // costs nothing.
    if (cache.order.empty()) {
      cache.key.resize(count);
      cache.order.resize(count);
      cache.scale = 0.0;
      cache.max_reach = 0.0;
      for (std::size_t i = 0; i < count; ++i) {
        const double* c = centres + i * dim;
        double h = 0.0, a = 0.0;
        for (int j = 0; j < dim; ++j) h += nrm[j] * c[j], a += std::abs(nrm[j] * c[j]);
        cache.key[i] = h;
        cache.scale = std::max(cache.scale, a);
        cache.max_reach = std::max(cache.max_reach, reach[i]);
      }
      std::iota(cache.order.begin(), cache.order.end(), 0u);
      std::sort(cache.order.begin(), cache.order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return cache.key[a] < cache.key[b] || (cache.key[a] == cache.key[b] && a < b);
      });
      std::vector<double> sorted(count);
      cache.key_reach.resize(count);
      for (std::size_t k = 0; k < count; ++k) {
        sorted[k] = cache.key[cache.order[k]];
        cache.key_reach[k] = reach[cache.order[k]];
      }
      cache.key.swap(sorted);
    }
    const double margin = cache.max_reach + 1e-12 * (std::abs(plane.offset) + cache.scale);
    const auto lo = std::lower_bound(cache.key.begin(), cache.key.end(), plane.offset - margin);
    const auto hi = std::upper_bound(lo, cache.key.end(), plane.offset + margin);
    // |height - d| against the reach decides alike with the culling test's own sum unless
    // they differ by less than far more than the rounding of either: only those objects are
    // tested (their centres read).
    const double band = 1e-12 * (std::abs(plane.offset) + cache.scale + cache.max_reach);
    // The touched ones as bits, listed in increasing order from the words between the first
    // and the last (and cleared on the way).
    cache.bits.resize((count + 63) / 64);
    std::uint64_t* bits = cache.bits.data();
    std::size_t first = count, last = 0;
    for (auto k = lo; k != hi; ++k) {
      const std::size_t at = static_cast<std::size_t>(k - cache.key.begin());
      const double gap = std::abs(*k - plane.offset) - cache.key_reach[at];
      if (gap > band) continue;
      const std::uint32_t i = cache.order[at];
      if (gap >= -band && culled(i)) continue;
      bits[i / 64] |= std::uint64_t{1} << (i % 64);
      first = std::min<std::size_t>(first, i);
      last = std::max<std::size_t>(last, i);
    }
    for (std::size_t w = first / 64; first <= last && w <= last / 64; ++w)
      for (std::uint64_t b = std::exchange(bits[w], 0); b != 0; b &= b - 1)
        touched_.push_back(static_cast<std::uint32_t>(w * 64 + std::countr_zero(b)));
  } else {
    for (std::size_t i = 0; i < count; ++i)
      if (!options.cull || !culled(i)) touched_.push_back(static_cast<std::uint32_t>(i));
  }
  arrange(out);
  out.objects.assign(touched_.begin(), touched_.end());
  out.plane = plane;
  // The jobs, with slots for the touched objects that have none for this normal.
  cache.jobs.resize(touched_.size());
  for (std::size_t j = 0; j < touched_.size(); ++j) {
    const std::uint32_t i = touched_[j];
    Placements::Job& job = cache.jobs[j];
    job.model = model_of_[i];
    job.transform = &transforms_[i];
    job.slot = cache.slot[i];
    job.fresh = false;
    if (job.slot == no_index && job.model->fast() && job.model->dim() == plane.dim()) {
      job.slot = cache.slot[i] = static_cast<std::uint32_t>(cache.pl.size());
      job.fresh = true;
      cache.used.push_back(i);
      cache.pl.emplace_back();
    }
  }
  threads = resolve_threads(threads);
  threads = static_cast<unsigned>(
      std::max<std::size_t>(1, std::min<std::size_t>(threads, touched_.size())));
  if (slicers_.size() < threads) slicers_.resize(threads);
  auto run = [&](unsigned t, std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) {
      const Placements::Job& job = cache.jobs[j];
      SliceBuffers& o = out.buffers[j];
      if (job.slot == no_index) {
        slicers_[t].slice(*job.model, plane, *job.transform, o, options);
        continue;
      }
      Slicer::Placement& pl = cache.pl[job.slot];
      if (job.fresh) pl.set(*job.model->compiled_, plane, job.transform);
      slicers_[t].impl_->slice_with(*job.model->compiled_, pl, plane, job.transform, o, options);
    }
  };
  // Blocks of consecutive touched objects; each thread writes only its own entries of
  // out.buffers (and its objects' placements).
  const std::size_t n = touched_.size();
  const std::size_t per = (n + threads - 1) / threads;
  fork_join(threads, [&](unsigned t) { run(t, std::min(n, t * per), std::min(n, (t + 1) * per)); });
}

std::vector<Section> to_sections(const SceneSlice& slice, std::size_t count) {
  if (count == 0) return {};
  SliceBuffers none;
  clear_to_empty(none, static_cast<int>(slice.plane.dim()) - 1);
  none.plane = slice.plane;
  const Section empty = to_section(none);
  std::vector<Section> pieces;
  pieces.reserve(count);
  std::size_t k = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (k < slice.objects.size() && slice.objects[k] == i)
      pieces.push_back(to_section(slice.buffers[k++]));
    else
      pieces.push_back(empty);
  }
  return pieces;
}

}  // namespace cw4d
