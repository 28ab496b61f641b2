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

// --- scenes ---------------------------------------------------------------------------------

SceneSlicer::SceneSlicer(const Scene& scene, const SliceModelOptions& options) : dim_(scene.dim()) {
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
    objects_.push_back({&m, obj.transform});
    centres_.insert(centres_.end(), centre.data(), centre.data() + centre.size());
    // Culled when |n.c - d| > radius + margin (tol::bounding_sphere_margin_rel of the size).
    reach_.push_back(radius + tol::bounding_sphere_margin_rel * (radius + centre.norm()));
  }
}

// The touched objects' placements for one normal: slot[i] indexes pl for object i (none: not
// made yet); a new normal forgets them all.
struct SceneSlicer::Placements {
  Eigen::VectorXd normal;
  std::vector<std::uint32_t> slot, used;
  std::vector<Slicer::Placement> pl;
  std::vector<char> fresh;  // slots made in this slice (their set() is still to run)
};

void Slicer::slice_with(const SliceModel& m, Placement& pl, const Hyperplane& plane,
                        const AffineTransform& xf, SliceBuffers& out, const SliceOptions& options) {
  // slice_placed() from its pl.set() on (the placement's normal part is that of this plane).
  pl.plane = &plane;
  near_parallel_ = tol::near_parallel_edge * pl.nm_norm;
  pl.set_offset(m, plane.offset);
  if (options.reuse_topology && reuse(m, pl, options, out)) {
    ++cached_count_;
    return;
  }
  reason_ = FallbackReason::None;
  kernel_ = options.kernel;
  if (!fast_slice(m, pl, options, out)) general_slice(m, plane, xf, out);
}

void SceneSlicer::slice(const Hyperplane& plane, std::vector<SliceBuffers>& out, unsigned threads,
                        const SliceOptions& options) {
  if (!objects_.empty() && plane.dim() != dim_)
    throw InputError("hyperplane in R^" + std::to_string(plane.dim()) + " for a scene in R^" +
                     std::to_string(dim_));
  const std::size_t count = objects_.size();
  out.resize(count);
  if (!placements_) placements_ = std::make_shared<Placements>();
  Placements& cache = *placements_;
  if (cache.slot.size() != count) cache.slot.assign(count, none), cache.used.clear();
  if (cache.normal.size() != plane.normal.size() || cache.normal != plane.normal) {
    for (std::uint32_t i : cache.used) cache.slot[i] = none;
    cache.used.clear();
    cache.pl.clear();
    cache.normal = plane.normal;
  }
  // The culling pass over the flat array of world-space spheres: a culled object is written
  // only when its buffers are not yet marked empty.
  touched_.clear();
  const double* nrm = plane.normal.data();
  const double* c = centres_.data();
  const int dim = dim_;
  for (std::size_t i = 0; i < count; ++i, c += dim) {
    bool culled = false;
    if (options.cull) {
      double dist = -plane.offset;
      for (int j = 0; j < dim; ++j) dist += nrm[j] * c[j];
      culled = std::abs(dist) > reach_[i];
    }
    if (!culled) {
      touched_.push_back(static_cast<std::uint32_t>(i));
      continue;
    }
    SliceBuffers& b = out[i];
    if (b.culled && b.vertex_source.empty()) continue;
    clear_to_empty(b, dim_ - 1);
    b.plane = plane;
    b.general = !objects_[i].model->fast();  // as the general path's empty result
    b.fallback = b.general ? FallbackReason::Model : FallbackReason::None;
    b.reused_topology = false;
    b.culled = true;
  }
  // Placements: slots for the touched objects that have none for this normal.
  cache.fresh.assign(cache.pl.size(), 0);
  for (std::uint32_t i : touched_)
    if (cache.slot[i] == none && objects_[i].model->fast()) {
      cache.slot[i] = static_cast<std::uint32_t>(cache.pl.size());
      cache.used.push_back(i);
      cache.pl.emplace_back();
      cache.fresh.push_back(1);
    }
  threads = resolve_threads(threads);
  threads = static_cast<unsigned>(
      std::max<std::size_t>(1, std::min<std::size_t>(threads, touched_.size())));
  if (slicers_.size() < threads) slicers_.resize(threads);
  auto run = [&](unsigned t, std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) {
      const std::uint32_t i = touched_[j];
      const Object& obj = objects_[i];
      SliceBuffers& o = out[i];
      o.culled = false;
      const std::uint32_t slot = cache.slot[i];
      if (slot == none || plane.dim() != obj.model->dim()) {
        slicers_[t].slice(*obj.model, plane, obj.transform, o, options);
        continue;
      }
      Slicer::Placement& pl = cache.pl[slot];
      if (cache.fresh[slot]) pl.set(*obj.model, plane, &obj.transform);
      slicers_[t].slice_with(*obj.model, pl, plane, obj.transform, o, options);
    }
  };
  // Blocks of consecutive touched objects; each thread writes only its own entries of out
  // (and its objects' placements).
  const std::size_t n = touched_.size();
  const std::size_t per = (n + threads - 1) / threads;
  fork_join(threads, [&](unsigned t) { run(t, std::min(n, t * per), std::min(n, (t + 1) * per)); });
}

}  // namespace cw4d
