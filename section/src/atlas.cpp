#include "cw4d/section/atlas.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "cw4d/complex/error.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/slicer.hpp"

namespace cw4d {

namespace {

std::vector<std::size_t> section_fvector(const Section& s, int model_dim) {
  std::vector<std::size_t> f(static_cast<std::size_t>(std::max(model_dim - 1, 1)), 0);
  for (std::size_t k = 0; k < f.size(); ++k) f[k] = s.complex.count(static_cast<int>(k));
  return f;
}

bool all_zero(const std::vector<std::size_t>& f) {
  return std::all_of(f.begin(), f.end(), [](std::size_t x) { return x == 0; });
}

// The vertex heights n.x of the placed model along the unit normal, in vertex order.
std::vector<double> vertex_heights(const Complex& model, const Eigen::VectorXd& unit,
                                   const AffineTransform& model_to_world, double* radius) {
  const Eigen::MatrixXd world =
      (model_to_world.linear() * model.positions()).colwise() + model_to_world.translation();
  std::vector<double> h(static_cast<std::size_t>(world.cols()));
  double r = 0.0;
  for (Eigen::Index v = 0; v < world.cols(); ++v) {
    h[static_cast<std::size_t>(v)] = unit.dot(world.col(v));
    r = std::max(r, world.col(v).norm());
  }
  if (radius) *radius = r;
  return h;
}

// Atlas::critical[i].contact for each critical section that is empty: the counts of the
// model's elements of ranks 0..n-2 that lie in that plane, for all of them in one pass over
// the model. A vertex lies in the plane of its nearest critical offset (the critical offsets
// are the vertex heights, merged); a higher element lies in a plane when its whole boundary
// does.
void add_contacts(const Complex& model, const AffineTransform& model_to_world, Atlas& atlas) {
  const std::vector<double>& c = atlas.critical_offsets;
  if (atlas.critical.size() != c.size() || c.empty()) return;
  std::vector<char> wanted(c.size(), 0);
  bool any = false;
  for (std::size_t i = 0; i < c.size(); ++i) {
    AtlasSection& s = atlas.critical[i];
    if (!all_zero(s.fvector)) continue;
    wanted[i] = 1, any = true;
    s.contact.assign(s.fvector.size(), 0);
  }
  if (!any) return;
  constexpr std::uint32_t none = ~std::uint32_t{0};
  const std::vector<double> height = vertex_heights(model, atlas.normal, model_to_world, nullptr);
  std::vector<std::uint32_t> level(height.size());
  for (std::size_t v = 0; v < height.size(); ++v) {
    std::size_t i =
        static_cast<std::size_t>(std::lower_bound(c.begin(), c.end(), height[v]) - c.begin());
    if (i == c.size() || (i > 0 && height[v] - c[i - 1] <= c[i] - height[v])) --i;
    level[v] = static_cast<std::uint32_t>(i);
    if (wanted[i]) ++atlas.critical[i].contact[0];
  }
  const std::size_t f_size = atlas.critical.front().fvector.size();
  for (std::size_t k = 1; k < f_size && static_cast<int>(k) <= model.top_rank(); ++k) {
    const Incidence& rows = model.boundary(static_cast<int>(k));
    std::vector<std::uint32_t> next(rows.size(), none);
    for (std::size_t e = 0; e < rows.size(); ++e) {
      const auto ids = rows.ids(e);
      if (ids.empty()) continue;
      const std::uint32_t l = level[ids[0]];
      if (l == none ||
          !std::all_of(ids.begin(), ids.end(), [&](std::uint32_t b) { return level[b] == l; }))
        continue;
      next[e] = l;
      if (wanted[l]) ++atlas.critical[l].contact[k];
    }
    level.swap(next);
  }
}

}  // namespace

std::vector<double> critical_offsets(const Complex& model, const Eigen::VectorXd& normal,
                                     const AffineTransform& model_to_world, double* tolerance) {
  const int n = model.ambient_dim();
  if (normal.size() != n)
    throw InputError("the normal has " + std::to_string(normal.size()) +
                     " components; the model lives in R^" + std::to_string(n));
  if (model_to_world.dim() != n)
    throw InputError("the placement acts on R^" + std::to_string(model_to_world.dim()) +
                     "; the model lives in R^" + std::to_string(n));
  const Eigen::VectorXd unit = Hyperplane::from(normal, 0.0).normal;
  double radius = 0.0;
  std::vector<double> h = vertex_heights(model, unit, model_to_world, &radius);
  if (!std::isfinite(radius)) throw InputError("the placed model has a coordinate beyond range");
  std::sort(h.begin(), h.end());
  const double tol = atlas_merge_rel * radius;
  if (tolerance) *tolerance = tol;
  std::vector<double> out;
  for (std::size_t i = 0; i < h.size();) {
    std::size_t j = i + 1;
    while (j < h.size() && h[j] - h[j - 1] <= tol) ++j;
    // The value most often computed in the run (rounding scatters a few heights of a
    // symmetric model around the exact one), else the run's median.
    std::size_t best = i + (j - 1 - i) / 2, best_count = 1;
    for (std::size_t a = i; a < j;) {
      std::size_t b = a + 1;
      while (b < j && h[b] == h[a]) ++b;
      if (b - a > best_count) best = a, best_count = b - a;
      a = b;
    }
    out.push_back(h[best]);
    i = j;
  }
  return out;
}

Atlas section_atlas(const Complex& model, const Eigen::VectorXd& normal,
                    const AffineTransform& model_to_world, const AtlasOptions& options) {
  Atlas atlas;
  atlas.critical_offsets = critical_offsets(model, normal, model_to_world, &atlas.tolerance);
  atlas.normal = Hyperplane::from(normal, 0.0).normal;
  const int n = model.ambient_dim();
  const auto& c = atlas.critical_offsets;
  // The cuts in increasing offset order: each critical offset (when asked for) and the
  // midpoint of the interval above it.
  std::vector<double> offsets;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (options.critical_sections) offsets.push_back(c[i]);
    if (i + 1 < c.size()) offsets.push_back(0.5 * c[i] + 0.5 * c[i + 1]);
  }
  const std::size_t per = options.critical_sections ? 2 : 1;  // cuts per critical offset
  const SliceModel compiled(model, SliceModelOptions::unclustered());
  if (compiled.fast()) {
    // One sweep: every layer is exactly the slice section() makes of its plane, and the
    // sweep renews the section only around the vertices between two layers.
    Slicer slicer;
    std::vector<SliceBuffers> layers;
    slicer.sweep(compiled, atlas.normal, offsets, model_to_world, layers);
    const auto fvector = [&](const SliceBuffers& b) {
      std::vector<std::size_t> f(static_cast<std::size_t>(std::max(n - 1, 1)), 0);
      for (std::size_t k = 0; k < f.size(); ++k) f[k] = b.count(static_cast<int>(k));
      return f;
    };
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (options.critical_sections) atlas.critical.push_back({c[i], fvector(layers[per * i]), {}});
      if (i + 1 == c.size()) break;
      const std::size_t k = per * i + per - 1;
      atlas.intervals.push_back({c[i], c[i + 1], {offsets[k], fvector(layers[k]), {}}});
      if (options.keep_sections) atlas.sections.push_back(to_section(layers[k]));
    }
    add_contacts(model, model_to_world, atlas);
    return atlas;
  }
  const auto cut = [&](double d) {
    return section(model, Hyperplane::from(atlas.normal, d), model_to_world);
  };
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (options.critical_sections)
      atlas.critical.push_back({c[i], section_fvector(cut(c[i]), n), {}});
    if (i + 1 == c.size()) break;
    const double mid = offsets[per * i + per - 1];
    Section s = cut(mid);
    atlas.intervals.push_back({c[i], c[i + 1], {mid, section_fvector(s, n), {}}});
    if (options.keep_sections) atlas.sections.push_back(std::move(s));
  }
  add_contacts(model, model_to_world, atlas);
  return atlas;
}

Atlas section_atlas(const Complex& model, const Eigen::VectorXd& normal,
                    const AtlasOptions& options) {
  return section_atlas(model, normal, AffineTransform::identity(model.ambient_dim()), options);
}

}  // namespace cw4d
