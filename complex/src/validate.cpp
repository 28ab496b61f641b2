#include "cw4d/complex/validate.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"

namespace cw4d {

std::string ValidationReport::summary(std::size_t max_issues) const {
  if (issues.empty()) return "valid";
  std::ostringstream out;
  for (std::size_t i = 0; i < issues.size() && i < max_issues; ++i) {
    if (i) out << "; ";
    out << issues[i].what;
  }
  if (issues.size() > max_issues) out << "; and " << issues.size() - max_issues << " more";
  return out.str();
}

namespace {

std::string element_name(int rank, std::uint32_t id) {
  static const char* names[] = {"vertex", "edge", "face", "cell"};
  std::string name = rank < 4 ? names[rank] : "rank-" + std::to_string(rank) + " element";
  return name + " " + std::to_string(id);
}

struct Checker {
  const Complex& c;
  const ValidateOptions& opt;
  ValidationReport report;

  bool full() const { return report.issues.size() >= opt.max_issues; }
  void add(int rank, std::uint32_t id, const std::string& what) {
    if (!full()) report.issues.push_back({rank, id, element_name(rank, id) + ": " + what});
  }

  // Returns false when the rows of this rank cannot be trusted for deeper checks.
  bool check_rows(int rank) {
    const Incidence& t = c.boundary(rank);
    const std::size_t below = c.count(rank - 1);
    // The table's own arrays first: rows are read through its offsets.
    if (!t.rows_readable()) {
      const std::vector<std::uint32_t>& off = t.offsets();
      std::uint32_t x = 0;  // the first row that ends before it starts, if any
      while (x < t.size() && off[x] <= off[x + 1]) ++x;
      if (x < t.size())
        add(rank, x,
            "boundary offsets out of order (" + std::to_string(off[x]) + " then " +
                std::to_string(off[x + 1]) + ")");
      else
        add(rank, 0,
            "the table's arrays disagree (offsets from " + std::to_string(off.front()) + " to " +
                std::to_string(off.back()) + ", " + std::to_string(t.all_ids().size()) + " ids, " +
                std::to_string(t.all_signs().size()) + " signs)");
      return false;
    }
    bool ok = true;
    std::vector<std::uint32_t> sorted;
    for (std::uint32_t x = 0; x < t.size() && !full(); ++x) {
      auto ids = t.ids(x);
      auto signs = t.signs(x);
      if (ids.empty()) {
        add(rank, x, "empty boundary");
        ok = false;
        continue;
      }
      bool row_ok = true;
      for (std::size_t i = 0; i < ids.size(); ++i) {
        if (ids[i] >= below) {
          add(rank, x,
              "boundary id " + std::to_string(ids[i]) + " out of range (" + std::to_string(below) +
                  " elements of rank " + std::to_string(rank - 1) + ")");
          row_ok = false;
        }
        if (signs[i] != 1 && signs[i] != -1) {
          add(rank, x, "sign is neither +1 nor -1");
          row_ok = false;
        }
      }
      sorted.assign(ids.begin(), ids.end());
      std::sort(sorted.begin(), sorted.end());
      auto dup = std::adjacent_find(sorted.begin(), sorted.end());
      if (dup != sorted.end()) {
        add(rank, x, "lists " + element_name(rank - 1, *dup) + " twice");
        row_ok = false;
      }
      if (rank == 1 && row_ok) {
        if (ids.size() != 2 || signs[0] != -1 || signs[1] != 1) {
          add(1, x, "an edge must be [tail, head] with signs [-1, +1]");
          row_ok = false;
        }
      }
      ok = ok && row_ok;
    }
    return ok;
  }

  void check_face_cycles() {
    const Incidence& t = c.boundary(2);
    std::vector<std::uint32_t> tails;
    for (std::uint32_t f = 0; f < t.size() && !full(); ++f) {
      auto ids = t.ids(f);
      auto signs = t.signs(f);
      if (ids.size() < 3) {
        add(2, f, "has " + std::to_string(ids.size()) + " edges, a face needs at least 3");
        continue;
      }
      tails.clear();
      bool closed = true;
      for (std::size_t i = 0; i < ids.size(); ++i) {
        auto e = c.edge(ids[i]);
        auto n = c.edge(ids[(i + 1) % ids.size()]);
        const std::uint32_t head = signs[i] > 0 ? e[1] : e[0];
        const std::uint32_t next_tail = signs[(i + 1) % ids.size()] > 0 ? n[0] : n[1];
        tails.push_back(signs[i] > 0 ? e[0] : e[1]);
        if (head != next_tail) closed = false;
      }
      if (!closed) {
        add(2, f, "edges do not form one closed cycle in order");
        continue;
      }
      std::sort(tails.begin(), tails.end());
      if (std::adjacent_find(tails.begin(), tails.end()) != tails.end())
        add(2, f, "cycle passes through a vertex twice");
    }
  }

  // Every (k-2)-element of a k-element's boundary is used exactly twice, with cancelling signs.
  void check_boundary_of_boundary(int rank) {
    const Incidence& t = c.boundary(rank);
    const Incidence& below = c.boundary(rank - 1);
    std::vector<std::pair<std::uint32_t, int>> acc;
    for (std::uint32_t x = 0; x < t.size() && !full(); ++x) {
      acc.clear();
      auto ids = t.ids(x);
      auto signs = t.signs(x);
      for (std::size_t i = 0; i < ids.size(); ++i) {
        auto g = below.ids(ids[i]);
        auto gs = below.signs(ids[i]);
        for (std::size_t j = 0; j < g.size(); ++j) acc.push_back({g[j], signs[i] * gs[j]});
      }
      std::sort(acc.begin(), acc.end());
      for (std::size_t i = 0; i < acc.size();) {
        std::size_t j = i;
        int sum = 0;
        while (j < acc.size() && acc[j].first == acc[i].first) sum += acc[j++].second;
        if (j - i != 2) {
          add(rank, x,
              "not closed: " + element_name(rank - 2, acc[i].first) + " is used by " +
                  std::to_string(j - i) + " of its boundary elements instead of 2");
          break;
        }
        if (sum != 0) {
          add(rank, x,
              "boundary of boundary is not zero at " + element_name(rank - 2, acc[i].first) +
                  " (inconsistent orientation signs)");
          break;
        }
        i = j;
      }
    }
  }

  void check_closed() {
    const int n = c.ambient_dim();
    const int fr = n - 1;
    if (fr < 1) return;
    if (c.count(fr) == 0) {
      add(fr, 0,
          "no facets: a closed complex in R^" + std::to_string(n) + " needs elements of rank " +
              std::to_string(fr));
      return;
    }
    const Incidence& facets = c.boundary(fr);
    std::vector<std::pair<std::uint32_t, std::pair<int, std::uint32_t>>> acc;
    for (std::uint32_t f = 0; f < facets.size(); ++f) {
      auto ids = facets.ids(f);
      auto signs = facets.signs(f);
      for (std::size_t i = 0; i < ids.size(); ++i) acc.push_back({ids[i], {signs[i], f}});
    }
    std::sort(acc.begin(), acc.end());
    for (std::size_t i = 0; i < acc.size() && !full();) {
      std::size_t j = i;
      int sum = 0;
      while (j < acc.size() && acc[j].first == acc[i].first) sum += acc[j++].second.first;
      const std::uint32_t ridge = acc[i].first;
      if (j - i != 2) {
        add(fr - 1, ridge,
            "bounds " + std::to_string(j - i) + " facets instead of 2 (surface not closed)");
      } else if (sum != 0) {
        add(fr, acc[i + 1].second.second,
            "orientation disagrees with " + element_name(fr, acc[i].second.second) + " across " +
                element_name(fr - 1, ridge));
      }
      i = j;
    }
    if (!full() && report.issues.empty()) {
      // The sign on exactly rescaled positions: coordinates of 1e200 or 1e-200 would
      // overflow or underflow the volume.
      const double scale = position_scale(c);
      // A volume within rounding of zero (a hemi-polyhedron, whose faces pass through its
      // centre, encloses none) is zero, whatever the rounding of this copy gives.
      double magnitude = 0.0;
      double vol = signed_volume(c, scale, &magnitude);
      if (std::abs(vol) <= 1e-12 * magnitude) vol = 0.0;
      if (!(vol > 0.0))
        add(fr, 0,
            vol == 0.0 ? std::string(all_vertices_coincide()
                                         ? "encloses no volume (all its vertices coincide)"
                                         : "encloses no volume (all of it lies in a hyperplane)")
                       : "facets are not oriented outward (signed volume " +
                             std::to_string(vol / std::pow(scale, n)) + ")");
    }
  }

  bool all_vertices_coincide() const {
    const auto& p = c.positions();
    for (Eigen::Index v = 1; v < p.cols(); ++v)
      if (p.col(v) != p.col(0)) return false;
    return true;
  }

  void check_planarity() {
    const int n = c.ambient_dim();
    const int fr = n - 1;
    if (fr < 2) return;
    const auto& p = c.positions();
    const double scale = position_scale(c);
    for (std::uint32_t f = 0; f < c.count(fr) && !full(); ++f) {
      Eigen::VectorXd a = facet_area_vector(c, f, scale);
      if (!(a.norm() > 0.0)) {
        add(fr, f, "degenerate (zero volume)");
        continue;
      }
      a.normalize();
      auto verts = c.vertices_of(fr, f);
      double lo = 1e300, hi = -1e300, diam = 0.0;
      for (auto v : verts) {
        const double h = a.dot(p.col(v));
        lo = std::min(lo, h);
        hi = std::max(hi, h);
        diam = std::max(diam, (p.col(v) - p.col(verts[0])).norm());
      }
      if (hi - lo > tol::planarity_rel * diam)
        add(fr, f,
            "not planar: its vertices spread " + std::to_string(hi - lo) +
                " across its hyperplane");
    }
  }

  void run() {
    const auto& p = c.positions();
    for (Eigen::Index v = 0; v < p.cols() && !full(); ++v)
      if (!p.col(v).allFinite())
        add(0, static_cast<std::uint32_t>(v), "coordinate is not a finite number");
    bool rows_ok = true;
    for (int k = 1; k <= c.top_rank(); ++k) rows_ok = check_rows(k) && rows_ok;
    if (!rows_ok || full()) return;
    if (c.top_rank() >= 2) check_face_cycles();
    for (int k = 3; k <= c.top_rank(); ++k) check_boundary_of_boundary(k);
    if (!report.issues.empty()) return;
    if (opt.require_closed) check_closed();
    if (opt.require_planar_facets && report.issues.empty()) check_planarity();
  }
};

}  // namespace

ValidationReport validate(const Complex& complex, const ValidateOptions& options) {
  Checker checker{complex, options, {}};
  checker.run();
  return std::move(checker.report);
}

void check_tables(const Complex& model) {
  for (int r = 1; r <= model.top_rank(); ++r) {
    const Incidence& t = model.boundary(r);
    auto table = [r] { return "the model's rank-" + std::to_string(r) + " boundary table"; };
    if (!t.well_formed(model.count(r - 1)))
      throw InputError(table() + " is malformed (an id beyond the " +
                       std::to_string(model.count(r - 1)) + " elements of rank " +
                       std::to_string(r - 1) +
                       ", offsets out of order, or a sign other than +1/-1); validate() names it");
    // Rows the cuts read by position: an edge's two ends, every other element's first entry.
    const std::vector<std::uint32_t>& off = t.offsets();
    unsigned bad = 0;
    if (r == 1) {
      for (std::size_t e = 0; e < off.size(); ++e)
        bad |= off[e] ^ static_cast<std::uint32_t>(2 * e);
    } else {
      for (std::size_t x = 0; x + 1 < off.size(); ++x)
        bad |= static_cast<unsigned>(off[x] == off[x + 1]);
    }
    if (bad != 0)
      throw InputError(table() +
                       (r == 1 ? " has an edge without exactly two ends"
                               : " has an element with an empty boundary") +
                       "; validate() names it");
  }
}

}  // namespace cw4d
