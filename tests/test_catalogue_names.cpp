// Every uniform polychoron of Miratope's library, built by its file's name through the model
// catalogue the CLI and Python use, against the file itself (independent data: the 4OFF files of
// tests/data/miratope, read by cw4d's OFF reader).
//
// The comparison is an explicit congruence: both vertex sets are centred at their centroids and
// scaled to edge 2, then an orthogonal map Q is found that sends the file's vertices one-to-one
// onto the built ones (fixed by four independent vertices, then checked on every vertex); under
// the vertex bijection it induces, the edges, the faces (as cyclic vertex sequences, either
// direction) and the cells (as sets of faces) of the file must be exactly those of the built
// model. That is equality as polytopes up to isometry and scale, which no spectrum of distances
// guarantees; the f-vectors and the edge lengths are compared too.
#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/wythoff.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"

using namespace cw4d;

namespace {

using FVector = std::vector<std::size_t>;

const std::filesystem::path kMiratope = std::filesystem::path(CW4D_TEST_DATA_DIR) / "miratope";

// Vertex positions centred at their centroid and scaled to edge 2; the edge lengths must agree
// (uniform: every edge the same) to 1e-9 of the edge.
Eigen::MatrixXd normalised(const Complex& c, std::string_view what) {
  INFO(what);
  REQUIRE(c.count(1) > 0);
  double lo = 1e300, hi = 0.0;
  for (std::uint32_t e = 0; e < c.count(1); ++e) {
    const auto ends = c.edge(e);
    const double l = (c.position(ends[0]) - c.position(ends[1])).norm();
    lo = std::min(lo, l);
    hi = std::max(hi, l);
  }
  CHECK((hi - lo) / hi < 1e-9);
  Eigen::MatrixXd p = c.positions();
  const Eigen::VectorXd centre = p.rowwise().mean();
  p.colwise() -= centre;
  return p * (2.0 / hi);
}

// Points found by position within `tol`: a grid of cell 4 tol, the 3^4 cells around a query.
class PointIndex {
 public:
  PointIndex(const Eigen::MatrixXd& points, double tol) : points_(points), tol_(tol) {
    for (Eigen::Index i = 0; i < points.cols(); ++i)
      cells_[key(points.col(i), {0, 0, 0, 0})].push_back(static_cast<std::uint32_t>(i));
  }
  // The unique point within tol of p, or nullopt (none, or more than one).
  std::optional<std::uint32_t> find(const Eigen::Vector4d& p) const {
    std::optional<std::uint32_t> hit;
    int found = 0;
    for (int code = 0; code < 81; ++code) {
      std::array<int, 4> shift{};
      for (int k = 0, c = code; k < 4; ++k, c /= 3) shift[k] = c % 3 - 1;
      const auto it = cells_.find(key(p, shift));
      if (it == cells_.end()) continue;
      for (std::uint32_t i : it->second)
        if ((points_.col(i) - p).norm() < tol_) {
          hit = i;
          ++found;
        }
    }
    return found == 1 ? hit : std::nullopt;
  }

 private:
  // The cell's coordinates mixed into one word; distinct cells that collide only cost a
  // distance test more.
  std::uint64_t key(const Eigen::Vector4d& p, const std::array<int, 4>& shift) const {
    std::uint64_t k = 0;
    for (int i = 0; i < 4; ++i) {
      const auto cell = static_cast<std::int64_t>(std::floor(p(i) / (4.0 * tol_))) + shift[i];
      k = (k ^ static_cast<std::uint64_t>(cell)) * 0x9E3779B97F4A7C15ull;
      k ^= k >> 29;
    }
    return k;
  }
  const Eigen::MatrixXd& points_;
  double tol_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

// The bijection file vertex -> built vertex of an orthogonal map sending the file's vertices
// onto the built ones, or nullopt. File vertex 0 goes to built vertex 0 (enough: a uniform
// polytope's symmetries are transitive on its vertices, so if any congruence exists, one
// composed with a symmetry does that); the images of three more file vertices, chosen as
// independent as possible, are searched among the built vertices with the same distances.
std::optional<std::vector<std::uint32_t>> congruence(const Eigen::MatrixXd& a,
                                                     const Eigen::MatrixXd& b) {
  const auto n = a.cols();
  if (b.cols() != n || a.rows() != 4 || b.rows() != 4) return std::nullopt;
  const double scale = std::max(a.colwise().norm().maxCoeff(), 1.0);
  const double tol = 1e-7 * scale;
  // Frame: vertex 0, then greedily the vertex farthest from the span of the chosen ones.
  std::vector<Eigen::Index> frame{0};
  Eigen::MatrixXd basis(4, 0);
  for (int k = 1; k < 4; ++k) {
    Eigen::Index best = -1;
    double best_residual = -1.0;
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Vector4d r = a.col(i);
      for (int j = 0; j < basis.cols(); ++j) r -= basis.col(j).dot(r) * basis.col(j);
      // Independent of vertex 0's direction too.
      const Eigen::Vector4d u0 = a.col(0).normalized();
      r -= u0.dot(r) * u0;
      if (r.norm() > best_residual) {
        best_residual = r.norm();
        best = i;
      }
    }
    if (best_residual < 1e-3 * scale) return std::nullopt;
    frame.push_back(best);
    Eigen::Vector4d r = a.col(best);
    const Eigen::Vector4d u0 = a.col(0).normalized();
    r -= u0.dot(r) * u0;
    for (int j = 0; j < basis.cols(); ++j) r -= basis.col(j).dot(r) * basis.col(j);
    basis.conservativeResize(4, basis.cols() + 1);
    basis.col(basis.cols() - 1) = r.normalized();
  }
  Eigen::Matrix4d af;
  for (int k = 0; k < 4; ++k) af.col(k) = a.col(frame[k]);
  const Eigen::Matrix4d af_inverse = af.inverse();
  const PointIndex index(b, tol);
  std::vector<std::uint32_t> image(4, 0);
  int tries = 0;
  std::optional<std::vector<std::uint32_t>> result;
  // Depth-first over the candidates of frame vertex k (same norm, same distances to the
  // images chosen so far).
  const auto search = [&](auto&& self, int k) -> bool {
    if (k == 4) {
      if (++tries > 20000) return true;  // give up: not congruent as far as we looked
      Eigen::Matrix4d bf;
      for (int j = 0; j < 4; ++j) bf.col(j) = b.col(image[j]);
      const Eigen::Matrix4d q = bf * af_inverse;
      if (!(q.transpose() * q).isApprox(Eigen::Matrix4d::Identity(), 1e-8)) return false;
      std::vector<std::uint32_t> map(static_cast<std::size_t>(n));
      std::vector<bool> used(static_cast<std::size_t>(n), false);
      for (Eigen::Index i = 0; i < n; ++i) {
        const auto hit = index.find(q * a.col(i));
        if (!hit || used[*hit]) return false;
        used[*hit] = true;
        map[static_cast<std::size_t>(i)] = *hit;
      }
      result = std::move(map);
      return true;
    }
    const Eigen::Vector4d p = a.col(frame[k]);
    for (Eigen::Index j = 0; j < n; ++j) {
      if (std::abs(b.col(j).norm() - p.norm()) > tol) continue;
      bool fits = true;
      for (int m = 0; m < k && fits; ++m)
        fits = std::abs((b.col(j) - b.col(image[m])).norm() - (p - a.col(frame[m])).norm()) < tol;
      if (!fits) continue;
      image[k] = static_cast<std::uint32_t>(j);
      if (self(self, k + 1)) return true;
    }
    return false;
  };
  if (std::abs(b.col(0).norm() - a.col(0).norm()) > tol) return std::nullopt;
  image[0] = 0;
  search(search, 1);
  return result;
}

// A face's cycle mapped through `map` and written canonically (smallest rotation of either
// direction).
std::vector<std::uint32_t> canonical_cycle(const std::vector<std::uint32_t>& cycle,
                                           const std::vector<std::uint32_t>* map) {
  std::vector<std::uint32_t> c;
  for (auto v : cycle) c.push_back(map ? (*map)[v] : v);
  std::vector<std::uint32_t> best;
  for (int dir = 0; dir < 2; ++dir) {
    for (std::size_t s = 0; s < c.size(); ++s) {
      std::vector<std::uint32_t> r(c.begin() + static_cast<std::ptrdiff_t>(s), c.end());
      r.insert(r.end(), c.begin(), c.begin() + static_cast<std::ptrdiff_t>(s));
      if (best.empty() || r < best) best = r;
    }
    std::reverse(c.begin(), c.end());
  }
  return best;
}

// The file and the built model are the same polytope up to isometry and scale.
void check_same_polytope(const Complex& built, const Complex& file) {
  REQUIRE(built.fvector() == file.fvector());
  const Eigen::MatrixXd b = normalised(built, "built");
  const Eigen::MatrixXd a = normalised(file, "file");
  const auto map = congruence(a, b);
  REQUIRE(map.has_value());
  // Edges.
  std::set<std::array<std::uint32_t, 2>> edges;
  for (std::uint32_t e = 0; e < built.count(1); ++e) {
    auto ends = built.edge(e);
    edges.insert({std::min(ends[0], ends[1]), std::max(ends[0], ends[1])});
  }
  std::size_t edges_found = 0;
  for (std::uint32_t e = 0; e < file.count(1); ++e) {
    const auto ends = file.edge(e);
    const std::uint32_t u = (*map)[ends[0]], v = (*map)[ends[1]];
    edges_found += edges.count({std::min(u, v), std::max(u, v)});
  }
  CHECK(edges_found == file.count(1));
  // Faces, as cycles; then the built face each file face is.
  std::map<std::vector<std::uint32_t>, std::uint32_t> faces;
  for (std::uint32_t f = 0; f < built.count(2); ++f)
    faces.emplace(canonical_cycle(built.face_cycle(f), nullptr), f);
  REQUIRE(faces.size() == built.count(2));
  std::vector<std::uint32_t> face_map(file.count(2), 0);
  std::size_t faces_found = 0;
  for (std::uint32_t f = 0; f < file.count(2); ++f) {
    const auto it = faces.find(canonical_cycle(file.face_cycle(f), &*map));
    if (it == faces.end()) continue;
    face_map[f] = it->second;
    ++faces_found;
  }
  REQUIRE(faces_found == file.count(2));
  // Cells, as sets of faces.
  std::multiset<std::vector<std::uint32_t>> cells;
  for (std::uint32_t k = 0; k < built.count(3); ++k) {
    const auto ids = built.boundary(3).ids(k);
    std::vector<std::uint32_t> s(ids.begin(), ids.end());
    std::sort(s.begin(), s.end());
    cells.insert(s);
  }
  std::multiset<std::vector<std::uint32_t>> file_cells;
  for (std::uint32_t k = 0; k < file.count(3); ++k) {
    std::vector<std::uint32_t> s;
    for (auto f : file.boundary(3).ids(k)) s.push_back(face_map[f]);
    std::sort(s.begin(), s.end());
    file_cells.insert(s);
  }
  CHECK(cells == file_cells);
}

std::vector<std::filesystem::path> off_files(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".off") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("every uniform polychoron of Miratope's library builds by its name and is its file",
          "[catalogue][wythoff][data]") {
  // The 4D files that are not uniform polychora, or not named ones, and why: convex
  // regular-faced but not vertex-transitive (crf/), isogonal with edges of two lengths or
  // scaliform (other/).
  const std::set<std::string> not_uniform = {
      "Biparagyrated cantellated tesseract",          // crf: two kinds of vertex
      "Castellated rhombicosidodecahedral prism",     // crf
      "Cube atop icosahedron",                        // crf: a segmentochoron
      "Digonal gyrobicupolic ring",                   // crf
      "Square magnabicupolic ring",                   // crf
      "Square orthobicupolic ring",                   // crf
      "Triangular hebesphenorotundaic rhombochoron",  // crf
      "Triangular prismic pyramid",                   // crf
      "Trigonal biantiprismatic ring",                // crf
      "Anti-du oc",                                   // other: edges of two lengths
      "Bialternatosnub 2-4 duoprism",                 // other: edges of two lengths
      "Bitruncatodecachoron",                         // other: edges of two lengths
      "Cube atop octahedron",                         // other: a segmentochoron
      "Digonal double triswirlprism",                 // other: edges of two lengths
      "Omnisnub tesseract",                           // other: edges of two lengths
      "Pyritohedral icosahedral antiprism",           // other: edges of two lengths
      "Square double antiprismoid",                   // other: edges of two lengths
      "Triangular double antiprismoid",               // other: edges of two lengths
  };
  std::map<std::string, int> covered;  // table entry -> files matched
  std::set<std::string> unnamed;
  int compared = 0;
  for (const char* folder : {"regular", "convex uniform", "nonconvex uniform", "crf", "other"}) {
    const auto files = off_files(kMiratope / folder);
    REQUIRE_FALSE(files.empty());
    for (const auto& path : files) {
      const std::string name = path.stem().string();
      INFO(folder << "/" << name);
      const auto entry = find_uniform_polychoron(name);
      if (!entry) {
        unnamed.insert(name);
        continue;
      }
      INFO("diagram " << entry->diagram);
      ++covered[entry->name];
      const Complex file = read_off_file(path.string());
      const Complex built = load_model(name, default_catalogue());
      check_same_polytope(built, file);
      // The English name builds the same (checked on the f-vector: the catalogue resolves
      // it to the same entry, below).
      CHECK(find_uniform_polychoron(english_name(*entry))->name == std::string(entry->name));
      ++compared;
    }
  }
  CHECK(unnamed == not_uniform);
  // 16 regular, 41 convex uniform, 31 non-convex uniform, and crf/'s cantellated
  // pentachoron and tesseract again.
  CHECK(compared == 16 + 41 + 31 + 2);
  // Every entry of the table is one of Miratope's files.
  for (const UniformPolychoron& p : uniform_polychora()) {
    INFO(p.name);
    CHECK(covered.count(p.name) == 1);
  }
  CHECK(covered.size() == uniform_polychora().size());
}

TEST_CASE(
    "the uniform polychora answer to every spelling, cw4d list counts them, the docs list them",
    "[catalogue][wythoff]") {
  const auto& table = uniform_polychora();
  std::set<std::string> names;
  for (const UniformPolychoron& p : table) {
    INFO(p.name);
    CHECK(names.insert(p.name).second);
    const std::string english = english_name(p);
    for (const std::string& spelling :
         {std::string(p.name), english, [&] {
            std::string s = p.name;  // Upper-case, underscores
            std::replace(s.begin(), s.end(), ' ', '_');
            for (auto& ch : s) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
            return s;
          }()}) {
      INFO(spelling);
      const auto found = find_uniform_polychoron(spelling);
      REQUIRE(found.has_value());
      CHECK(std::string(found->name) == p.name);
      CHECK(model_family(spelling, default_catalogue()).has_value());
    }
    // The convex Wythoffian ones: the OPERATION BASE names give the same diagram.
    if (p.convex && !p.spec) CHECK(uniform_polychoron_diagram(english) == std::string(p.diagram));
    // The star ones: star_polychoron agrees.
    if (!p.convex) CHECK(star_polychoron_diagram(p.name) == std::string(p.diagram));
  }
  // Miratope's spelling "icosatetrachoron", and the Greek and English bases mixed.
  CHECK(find_uniform_polychoron("quasicantitruncated icositetrachoron")->name ==
        std::string("quasicantitruncated icosatetrachoron"));
  CHECK(find_uniform_polychoron("Quasicantitruncated 24-cell").has_value());
  CHECK(find_uniform_polychoron("runcicantitruncated icosatetrachoron")->diagram ==
        std::string("x3x4x3x"));
  CHECK(find_uniform_polychoron("truncated 8-cell")->diagram == std::string("x4x3o3o"));
  CHECK(find_uniform_polychoron("small stellated 120-cell")->diagram == std::string("x5/2o5o3o"));
  CHECK_FALSE(find_uniform_polychoron("quasitruncated hexacosichoron").has_value());
  CHECK_FALSE(find_uniform_polychoron("").has_value());
  CHECK_FALSE(find_uniform_polychoron("tesseract tesseract").has_value());
  // The snub 24-cell by Miratope's name is the hull family's model.
  CHECK(load_model("Semisnub icositetrachoron", default_catalogue()).fvector() ==
        FVector{96, 432, 480, 144});
  // The core catalogue (no hull families) leaves the two hull-built ones out.
  CHECK(core_catalogue().find("semisnub icositetrachoron") == nullptr);
  CHECK(core_catalogue().find("grand antiprism") == nullptr);
  CHECK_THROWS_AS(load_model("semisnub icositetrachoron"), InputError);
  CHECK(core_catalogue().find("quasitruncated tesseract") != nullptr);
  // A misspelt name is suggested.
  CHECK_THROWS_WITH(load_model("quasitrunkated tesseract", default_catalogue()),
                    Catch::Contains("did you mean 'quasitruncated tesseract'"));

  // cw4d list: 88 uniform polychora (47 convex, 41 non-convex), as many as Miratope's files
  // of them (the test above).
  bool listed = false;
  for (const BuiltinInfo& info : builtin_list(default_catalogue()))
    if (info.spec == "UNIFORM-POLYCHORON") {
      listed = true;
      CHECK_THAT(info.description, Catch::Contains("88 uniform polychora"));
      CHECK_THAT(info.description,
                 Catch::Contains("47 convex: 6 regular, 39 Wythoffian, 2 others"));
      CHECK_THAT(info.description, Catch::Contains("41 non-convex: 10 regular star, 31 others"));
    }
  CHECK(listed);
  // docs/models.md lists every name with its diagram, on one line.
  std::ifstream docs(std::filesystem::path(CW4D_TEST_DATA_DIR) / ".." / ".." / "docs" /
                     "models.md");
  REQUIRE(docs.good());
  std::vector<std::string> lines;
  for (std::string line; std::getline(docs, line);) {
    for (auto& ch : line) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    lines.push_back(line);
  }
  for (const UniformPolychoron& p : table) {
    INFO(p.name);
    CHECK(std::any_of(lines.begin(), lines.end(), [&](const std::string& line) {
      return line.find(std::string(p.name)) != std::string::npos &&
             line.find(p.diagram) != std::string::npos;
    }));
  }
}
