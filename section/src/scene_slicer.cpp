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

void SceneSlicer::slice(const Hyperplane& plane, std::vector<SliceBuffers>& out, unsigned threads,
                        const SliceOptions& options) {
  if (!objects_.empty() && plane.dim() != dim_)
    throw InputError("hyperplane in R^" + std::to_string(plane.dim()) + " for a scene in R^" +
                     std::to_string(dim_));
  out.resize(objects_.size());
  threads = resolve_threads(threads);
  threads = static_cast<unsigned>(
      std::max<std::size_t>(1, std::min<std::size_t>(threads, objects_.size())));
  if (slicers_.size() < threads) slicers_.resize(threads);
  // The culling pass: one flat array of world-space spheres.
  std::vector<char>& culled = culled_;
  culled.assign(objects_.size(), 0);
  std::size_t touched = objects_.size();
  if (options.cull) {
    const double* nrm = plane.normal.data();
    const double* c = centres_.data();
    const int dim = dim_;
    touched = 0;
    for (std::size_t i = 0; i < objects_.size(); ++i, c += dim) {
      double dist = -plane.offset;
      for (int j = 0; j < dim; ++j) dist += nrm[j] * c[j];
      culled[i] = std::abs(dist) > reach_[i];
      touched += !culled[i];
    }
  }
  touched_ = touched;
  auto run = [&](unsigned t, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (culled[i]) {
        clear_to_empty(out[i], dim_ - 1);
        out[i].plane = plane;
        out[i].general = !objects_[i].model->fast();  // as the general path's empty result
        out[i].fallback = out[i].general ? FallbackReason::Model : FallbackReason::None;
        out[i].reused_topology = false;
        continue;
      }
      slicers_[t].slice(*objects_[i].model, plane, objects_[i].transform, out[i], options);
    }
  };
  // Blocks of consecutive objects; each thread writes only its own entries of out.
  const std::size_t per = (objects_.size() + threads - 1) / threads;
  fork_join(threads, [&](unsigned t) {
    run(t, std::min(objects_.size(), t * per), std::min(objects_.size(), (t + 1) * per));
  });
}

}  // namespace cw4d
