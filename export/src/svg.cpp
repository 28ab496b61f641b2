#include "cw4d/export/svg.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"

namespace cw4d {

namespace {

// A well-spread hue per source cell (golden-angle steps), as an RGB triple in [0,1].
Eigen::Vector3d cell_color(std::uint32_t cell) {
  const double h = std::fmod(cell * 0.618033988749895, 1.0) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(h, 2.0) - 1.0);
  Eigen::Vector3d rgb;
  switch (static_cast<int>(h)) {
    case 0:
      rgb << 1, x, 0;
      break;
    case 1:
      rgb << x, 1, 0;
      break;
    case 2:
      rgb << 0, 1, x;
      break;
    case 3:
      rgb << 0, x, 1;
      break;
    case 4:
      rgb << x, 0, 1;
      break;
    default:
      rgb << 1, 0, x;
      break;
  }
  return 0.35 * Eigen::Vector3d::Ones() + 0.6 * rgb;  // pastel, so shading stays visible
}

}  // namespace

std::string svg_text(const Section& section, const SvgOptions& opt) {
  const Complex& c = section.complex;
  if (c.ambient_dim() != 3)
    throw InputError("SVG pictures need a 3D section; this one lives in R^" +
                     std::to_string(c.ambient_dim()));
  // Camera frame: forward looks from view_from towards the centre.
  const Eigen::Vector3d back = opt.view_from.normalized();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  if (std::abs(up.dot(back)) > 0.99) up = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d right = up.cross(back).normalized();
  const Eigen::Vector3d cam_up = back.cross(right);
  const Eigen::Vector3d light = opt.light_from.normalized();
  const auto& p = c.positions();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  if (p.cols() > 0) centre = 0.5 * (p.rowwise().minCoeff() + p.rowwise().maxCoeff());
  double radius = 1e-12;
  for (Eigen::Index v = 0; v < p.cols(); ++v) radius = std::max(radius, (p.col(v) - centre).norm());
  const double s = 0.45 * std::min(opt.width, opt.height) / radius;
  auto project = [&](std::uint32_t v) {
    const Eigen::Vector3d q = p.col(v) - centre;
    return Eigen::Vector3d(opt.width / 2.0 + s * q.dot(right), opt.height / 2.0 - s * q.dot(cam_up),
                           q.dot(back));
  };
  struct Poly {
    double depth;
    std::uint32_t face;
  };
  std::vector<Poly> polys;
  const std::size_t nf = c.top_rank() >= 2 ? c.count(2) : 0;
  for (std::uint32_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d n =
        c.has_facet_normals() ? Eigen::Vector3d(c.facet_normals().col(f)) : Eigen::Vector3d::Zero();
    if (n.dot(back) <= 0.0) continue;  // back face of a closed outward surface
    double depth = 0.0;
    const auto cyc = c.face_cycle(f);
    for (auto v : cyc) depth += project(v).z();
    polys.push_back({depth / static_cast<double>(cyc.size()), f});
  }
  std::sort(polys.begin(), polys.end(),
            [](const Poly& a, const Poly& b) { return a.depth < b.depth; });
  std::string out;
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
                "viewBox=\"0 0 %d %d\">\n",
                opt.width, opt.height, opt.width, opt.height);
  out += buf;
  out += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  const bool have_source = section.source.size() > 2 && section.source[2].size() == nf;
  // Face colors (a scene's) win over the per-cell hues; their alpha becomes fill-opacity.
  const auto& colors = c.colors(2);
  const bool have_colors = colors.size() == nf;
  for (const Poly& poly : polys) {
    const Eigen::Vector3d n = c.facet_normals().col(poly.face);
    const double lambert = std::max(0.0, n.dot(light));
    Eigen::Vector3d base;
    double opacity = 1.0;
    if (have_colors) {
      const Rgba& rgba = colors[poly.face];
      base = Eigen::Vector3d(rgba.r, rgba.g, rgba.b);
      opacity = std::clamp(static_cast<double>(rgba.a), 0.0, 1.0);
    } else {
      base = cell_color(have_source ? section.source[2][poly.face] : poly.face);
    }
    const Eigen::Vector3d col = (0.35 + 0.65 * lambert) * base;
    std::snprintf(buf, sizeof buf, "<polygon fill=\"#%02x%02x%02x\"",
                  static_cast<int>(std::clamp(col.x(), 0.0, 1.0) * 255.0 + 0.5),
                  static_cast<int>(std::clamp(col.y(), 0.0, 1.0) * 255.0 + 0.5),
                  static_cast<int>(std::clamp(col.z(), 0.0, 1.0) * 255.0 + 0.5));
    out += buf;
    if (opacity < 1.0) {
      std::snprintf(buf, sizeof buf, " fill-opacity=\"%.3f\"", opacity);
      out += buf;
    }
    out += opt.edges ? " stroke=\"#202020\" stroke-width=\"1.2\" stroke-linejoin=\"round\"" : "";
    out += " points=\"";
    for (auto v : c.face_cycle(poly.face)) {
      const Eigen::Vector3d q = project(v);
      std::snprintf(buf, sizeof buf, "%.2f,%.2f ", q.x(), q.y());
      out += buf;
    }
    out.back() = '"';
    out += "/>\n";
  }
  out += "</svg>\n";
  return out;
}

void write_svg_file(const std::string& path, const Section& section, const SvgOptions& options) {
  write_file_atomically(path, svg_text(section, options));
}

}  // namespace cw4d
