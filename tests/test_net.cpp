// Nets: unfolding the facets of closed polytopes into one hyperplane.
#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/net.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/complex/validate.hpp"

using namespace cw4d;

namespace {

double edge_length(const Complex& c) {
  const auto [t, h] = c.edge(0);
  return (c.position(h) - c.position(t)).norm();
}

Eigen::VectorXd piece_centre(const Net& net, std::uint32_t facet) {
  const auto& p = net.complex.positions();
  const auto b = net.vertex_begin[facet], e = net.vertex_begin[facet + 1];
  return p.middleCols(b, e - b).rowwise().mean();
}

// Every vertex of every facet, unfolded, lies in the root's hyperplane; the ridge a child
// shares with its parent lands on the same points from both sides; the unfolding keeps
// distances (an isometry).
void check_unfolding(const Complex& model, const Net& net) {
  const int n = model.ambient_dim(), m = n - 1;
  const double scale = max_radius(model);
  const Eigen::VectorXd nr = facet_area_vector(model, net.root).normalized();
  for (std::uint32_t f = 0; f < model.count(m); ++f) {
    const Eigen::MatrixXd& L = net.linear[f];
    CHECK((L.transpose() * L - Eigen::MatrixXd::Identity(n, n)).norm() < 1e-12);
    CHECK(L.determinant() == Approx(1.0).margin(1e-12));
    for (const auto v : model.vertices_of(m, f)) {
      const Eigen::VectorXd x = L * model.position(v) + net.translation[f];
      CHECK(std::abs(nr.dot(x - net.origin)) < 1e-9 * scale);
    }
    if (net.parent[f] < 0) continue;
    const auto p = static_cast<std::uint32_t>(net.parent[f]);
    for (const auto v : model.vertices_of(m - 1, net.hinge[f])) {
      const Eigen::VectorXd a = L * model.position(v) + net.translation[f];
      const Eigen::VectorXd b = net.linear[p] * model.position(v) + net.translation[p];
      CHECK((a - b).norm() < 1e-9 * scale);
    }
    // The child lies on the far side of the hinge from its parent (their centres on opposite
    // sides of the hinge within the root hyperplane): the centres are farther apart than
    // either is from the hinge's centre.
    Eigen::VectorXd o = Eigen::VectorXd::Zero(n);
    const auto hv = model.vertices_of(m - 1, net.hinge[f]);
    for (const auto v : hv) o += net.linear[p] * model.position(v) + net.translation[p];
    o /= static_cast<double>(hv.size());
    const Eigen::VectorXd of = net.basis.transpose() * (o - net.origin);
    const Eigen::VectorXd cf = piece_centre(net, f), cp = piece_centre(net, p);
    CHECK((cf - of).dot(cp - of) < 0.0);
  }
}

// Independent overlap oracle: points sampled strictly inside each piece (convex combinations
// of its vertices pulled towards its centre) tested against the outward face planes of every
// other piece (its facet normals, as the builder oriented them). Returns the pairs with a
// sample inside the other piece. Only for convex pieces.
std::set<std::pair<std::uint32_t, std::uint32_t>> sampled_overlaps(const Net& net, int samples) {
  const Complex& c = net.complex;
  const int m = c.ambient_dim();
  const auto& p = c.positions();
  const std::size_t np = c.count(m);
  const double scale = (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
  struct Plane {
    Eigen::VectorXd n;
    double d;
  };
  std::vector<std::vector<Plane>> planes(np);
  std::vector<Eigen::VectorXd> centre(np);
  std::vector<double> radius(np, 0.0);
  for (std::uint32_t i = 0; i < np; ++i) {
    const auto& ids = c.boundary(m).ids(i);
    for (const auto f : ids) {
      const Eigen::VectorXd nrm = facet_area_vector(c, f).normalized();
      planes[i].push_back({nrm, nrm.dot(p.col(c.first_vertex(m - 1, f)))});
    }
    const auto vs = c.vertices_of(m, i);
    centre[i] = Eigen::VectorXd::Zero(m);
    for (auto v : vs) centre[i] += p.col(v);
    centre[i] /= static_cast<double>(vs.size());
    for (auto v : vs) radius[i] = std::max(radius[i], (p.col(v) - centre[i]).norm());
  }
  std::mt19937 rng(7);
  std::set<std::pair<std::uint32_t, std::uint32_t>> out;
  for (std::uint32_t i = 0; i < np; ++i) {
    const auto vs = c.vertices_of(m, i);
    std::gamma_distribution<double> g(1.0, 1.0);  // Dirichlet weights
    for (int s = 0; s < samples; ++s) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(m);
      double total = 0.0;
      for (auto v : vs) {
        const double w = g(rng);
        x += w * p.col(v);
        total += w;
      }
      x = centre[i] + 0.999 * (x / total - centre[i]);
      for (std::uint32_t j = 0; j < np; ++j) {
        if (j == i || (x - centre[j]).norm() > radius[j]) continue;
        bool inside = true;
        for (const auto& pl : planes[j])
          if (pl.n.dot(x) - pl.d > -1e-7 * scale) {
            inside = false;
            break;
          }
        if (inside)
          out.insert({std::min(net.piece_facet[i], net.piece_facet[j]),
                      std::max(net.piece_facet[i], net.piece_facet[j])});
      }
    }
  }
  return out;
}

double total_volume(const Net& net) {
  const int m = net.complex.ambient_dim();
  double v = 0.0;
  for (std::uint32_t i = 0; i < net.complex.count(m); ++i) v += element_volume(net.complex, m, i);
  return v;
}

void check_net(const Complex& model, const Net& net, double boundary_volume) {
  const int m = model.ambient_dim() - 1;
  INFO("tree " << net_tree_name(net.tree) << " root " << net.root);
  REQUIRE(net.complex.ambient_dim() == m);
  REQUIRE(net.complex.count(m) == model.count(m));
  const ValidationReport report = validate(net.complex);
  INFO(report.summary());
  CHECK(report.ok());
  CHECK(signed_volume(net.complex) == Approx(boundary_volume).epsilon(1e-9));
  CHECK(total_volume(net) == Approx(boundary_volume).epsilon(1e-9));
  check_unfolding(model, net);
  // Piece i is model facet i (same vertex count, same m-volume).
  for (std::uint32_t i = 0; i < net.complex.count(m); ++i) {
    const auto f = net.piece_facet[i];
    CHECK(element_volume(net.complex, m, i) == Approx(element_volume(model, m, f)).epsilon(1e-9));
    CHECK(net.complex.vertices_of(m, i).size() == model.vertices_of(m, f).size());
  }
}

}  // namespace

TEST_CASE("tesseract: the breadth-first net is the cross of eight cubes", "[net]") {
  const Complex t = make_cube(4);
  NetOptions opt;
  opt.tree = NetTree::Bfs;
  opt.root = 0;
  const Net net = unfold(t, opt);
  check_net(t, net, 8 * 8.0);  // eight cubes of edge 2
  CHECK(net.overlaps.empty());
  CHECK(sampled_overlaps(net, 200).empty());
  // Each piece is an axis-aligned cube of edge 2 in the root's frame, up to the frame's rotation:
  // its vertices' pairwise distances are 2, 2 sqrt 2, 2 sqrt 3.
  // Positions: the root in the middle, six cubes on its faces, the eighth beyond one of them.
  const Eigen::VectorXd c0 = piece_centre(net, net.root);
  std::vector<double> dist;
  for (std::uint32_t f = 0; f < 8; ++f) dist.push_back((piece_centre(net, f) - c0).norm());
  std::vector<double> sorted = dist;
  std::sort(sorted.begin(), sorted.end());
  CHECK(sorted[0] == Approx(0.0).margin(1e-12));
  for (int k = 1; k < 7; ++k) CHECK(sorted[k] == Approx(2.0));
  CHECK(sorted[7] == Approx(4.0));
  // The far cube, its parent and the root form the column of four with the parent's opposite.
  const auto far =
      static_cast<std::uint32_t>(std::max_element(dist.begin(), dist.end()) - dist.begin());
  REQUIRE(net.parent[far] >= 0);
  const auto mid = static_cast<std::uint32_t>(net.parent[far]);
  CHECK((piece_centre(net, far) - c0 - 2.0 * (piece_centre(net, mid) - c0)).norm() < 1e-9);
  int opposite = 0;
  for (std::uint32_t f = 0; f < 8; ++f)
    if ((piece_centre(net, f) - c0 + (piece_centre(net, mid) - c0)).norm() < 1e-9) ++opposite;
  CHECK(opposite == 1);
  // Adjacency in the net: pieces whose centres are 2 apart share a face (cubes of edge 2 in a
  // grid). The root touches six; the far cube only its parent.
  auto touching = [&](std::uint32_t f) {
    int k = 0;
    for (std::uint32_t g = 0; g < 8; ++g)
      if (g != f && std::abs((piece_centre(net, g) - piece_centre(net, f)).norm() - 2.0) < 1e-9)
        ++k;
    return k;
  };
  CHECK(touching(net.root) == 6);
  CHECK(touching(far) == 1);
  CHECK(touching(mid) == 2);  // the root and the far cube
  // The column: far, mid, root, opposite on one line; the four others around the root.
  // Every piece is a cube of edge 2: bounding box in an axis frame of the root's cube.
  for (std::uint32_t f = 0; f < 8; ++f) {
    const auto b = net.vertex_begin[f], e = net.vertex_begin[f + 1];
    REQUIRE(e - b == 8);
    std::vector<double> d2;
    const auto& p = net.complex.positions();
    for (auto i = b; i < e; ++i)
      for (auto j = i + 1; j < e; ++j) d2.push_back((p.col(i) - p.col(j)).squaredNorm());
    std::sort(d2.begin(), d2.end());
    CHECK(d2.front() == Approx(4.0));
    CHECK(d2.back() == Approx(12.0));
    CHECK(std::count_if(d2.begin(), d2.end(), [](double x) { return std::abs(x - 4.0) < 1e-9; }) ==
          12);
  }
}

TEST_CASE("a unit tesseract placed anywhere unfolds into eight unit cubes", "[net]") {
  // Scaled to edge 1, turned in three planes and moved: the same cross of unit cubes.
  AffineTransform place = AffineTransform::scale(4, 0.5);
  place = AffineTransform::rotation(4, 0, 3, 0.7) * place;
  place = AffineTransform::rotation(4, 1, 2, -1.1) * place;
  place = AffineTransform::rotation(4, 2, 3, 0.3) * place;
  place = AffineTransform::translation(Eigen::Vector4d(3, -2, 1, 5)) * place;
  const Complex t = transformed(make_cube(4), place);
  NetOptions opt;
  opt.tree = NetTree::Bfs;
  const Net net = unfold(t, opt);
  check_net(t, net, 8.0);
  for (std::uint32_t i = 0; i < 8; ++i) CHECK(element_volume(net.complex, 3, i) == Approx(1.0));
  const Eigen::VectorXd c0 = piece_centre(net, net.root);
  std::vector<double> dist;
  for (std::uint32_t f = 0; f < 8; ++f) dist.push_back((piece_centre(net, f) - c0).norm());
  std::sort(dist.begin(), dist.end());
  CHECK(dist[0] == Approx(0.0).margin(1e-12));
  for (int k = 1; k < 7; ++k) CHECK(dist[k] == Approx(1.0));
  CHECK(dist[7] == Approx(2.0));
  CHECK(net.overlaps.empty());
}

TEST_CASE("24-cell and 120-cell: nets without overlaps", "[net]") {
  SECTION("24-cell") {
    const Complex c = load_model("24-cell");
    const double e = edge_length(c);
    const Net net = unfold(c);
    check_net(c, net, 24 * std::sqrt(2.0) / 3.0 * e * e * e);  // 24 octahedra
    CHECK(net.overlaps.empty());
    CHECK(net_overlaps(net).empty());
    CHECK(sampled_overlaps(net, 300).empty());
  }
  SECTION("120-cell") {
    const Complex c = load_model("120-cell");
    const double e = edge_length(c);
    const Net net = unfold(c);
    check_net(c, net, 120 * (15 + 7 * std::sqrt(5.0)) / 4.0 * e * e * e);  // 120 dodecahedra
    CHECK(net.overlaps.empty());
    CHECK(net_overlaps(net).empty());
    CHECK(sampled_overlaps(net, 100).empty());
  }
}

TEST_CASE("overlap test agrees with sampling on overlapping trees", "[net]") {
  // Random trees of the 120-cell overlap: whatever pair the samples find inside each other,
  // the separating-axis test flags too, and the samples find some (the oracle is exercised).
  const Complex c = load_model("120-cell");
  const double volume = 120 * (15 + 7 * std::sqrt(5.0)) / 4.0 * std::pow(edge_length(c), 3);
  std::size_t flagged = 0;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    NetOptions opt;
    opt.tree = NetTree::Random;
    opt.seed = seed;
    opt.root = 0;
    const Net net = unfold(c, opt);
    CHECK(net.tree == NetTree::Random);
    check_net(c, net, volume);
    const auto sampled = sampled_overlaps(net, 100);
    const std::set<std::pair<std::uint32_t, std::uint32_t>> sat(net.overlaps.begin(),
                                                                net.overlaps.end());
    for (const auto& pr : sampled) CHECK(sat.count(pr) == 1);
    flagged += sampled.size();
    CHECK(net_overlaps(net) == net.overlaps);
  }
  CHECK(flagged > 0);
}

TEST_CASE("greedy trees avoid the overlaps of depth-first ones", "[net]") {
  const Complex c = load_model("600-cell");
  NetOptions opt;
  opt.root = 0;
  opt.tree = NetTree::Dfs;
  const Net dfs = unfold(c, opt);
  CHECK_FALSE(dfs.overlaps.empty());
  opt.tree = NetTree::Greedy;
  const Net greedy = unfold(c, opt);
  CHECK(greedy.tree == NetTree::Greedy);
  check_net(c, greedy, 600 * std::pow(edge_length(c), 3) / (6 * std::sqrt(2.0)));
  CHECK(greedy.overlaps.empty());
  CHECK(sampled_overlaps(greedy, 20).empty());
}

TEST_CASE("auto reports when no tree it tried is free of overlaps", "[net]") {
  // A spheritorus (a sphere swept around a circle) of 256 cells overlaps itself in every
  // tree tried from one root with two random trees.
  const Complex d = load_model("spheritorus:2,0.5,8");
  NetOptions few;
  few.max_roots = 1;
  few.random_trees = 2;
  const Net best = unfold(d, few);
  CHECK_FALSE(best.overlaps.empty());
  // Real overlaps (its cells are convex): samples of one piece lie inside another.
  CHECK_FALSE(sampled_overlaps(best, 100).empty());
  CHECK(best.trees_tried == 4 + 2);  // bfs, greedy, dfs, depth-first greedy, 2 random trees
  CHECK(validate(best.complex).ok());
  // The answer is the tree with the fewest overlapping pairs: no worse than each fixed tree.
  for (const NetTree t : {NetTree::Bfs, NetTree::Dfs}) {
    NetOptions opt;
    opt.tree = t;
    opt.root = 0;
    CHECK(best.overlaps.size() <= unfold(d, opt).overlaps.size());
  }
  // A greedy tree that cannot avoid overlaps is reported as the breadth-first tree.
  NetOptions greedy;
  greedy.tree = NetTree::Greedy;
  greedy.root = 0;
  const Net g = unfold(d, greedy);
  CHECK(g.tree == NetTree::Bfs);
  CHECK_FALSE(g.overlaps.empty());
}

TEST_CASE("nets keep the cells' colors", "[net]") {
  Complex t = make_cube(4);
  auto& colors = t.colors_mut(3);
  for (std::uint32_t c = 0; c < 8; ++c) colors.push_back({c / 8.0f, 1.0f - c / 8.0f, 0.5f, 1.0f});
  const Net net = unfold(t);
  REQUIRE(net.complex.colors(3).size() == 8);
  for (std::uint32_t i = 0; i < 8; ++i)
    CHECK(net.complex.colors(3)[i] == colors[net.piece_facet[i]]);
  REQUIRE(net.complex.colors(2).size() == net.complex.count(2));
  for (std::uint32_t f = 0; f < net.complex.count(2); ++f)
    CHECK(net.complex.colors(2)[f] == colors[net.boundary_facet[f]]);
  // Each face of the net belongs to the piece of its cell.
  for (std::uint32_t i = 0; i < 8; ++i)
    for (const auto f : net.complex.boundary(3).ids(i))
      CHECK(net.boundary_facet[f] == net.piece_facet[i]);
}

TEST_CASE("separating axes: touching is not overlapping", "[net]") {
  Eigen::MatrixXd a(2, 4), b(2, 4);
  a << 0, 1, 1, 0, 0, 0, 1, 1;
  b = a;
  b.row(0).array() += 1.0;  // shares the edge x = 1
  const std::vector<Eigen::VectorXd> axes{Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)};
  CHECK_FALSE(interiors_overlap(a, b, axes, 1e-12));
  b.row(0).array() -= 1e-6;
  CHECK(interiors_overlap(a, b, axes, 1e-12));
}

TEST_CASE("polyhedra: nets of faces", "[net]") {
  SECTION("cube: six squares") {
    const Complex cube = make_cube(3);
    NetOptions opt;
    opt.tree = NetTree::Bfs;
    const Net net = unfold(cube, opt);
    check_net(cube, net, 6 * 4.0);
    CHECK(net.complex.count(2) == 6);
    CHECK(net.overlaps.empty());
    CHECK(sampled_overlaps(net, 200).empty());
  }
  SECTION("dodecahedron") {
    const Complex d = load_model("wythoff:x5o3o");
    const double e = edge_length(d);
    const Net net = unfold(d);
    check_net(d, net, 3 * std::sqrt(25 + 10 * std::sqrt(5.0)) * e * e);
    CHECK(net.overlaps.empty());
    CHECK(sampled_overlaps(net, 200).empty());
  }
}

TEST_CASE("nets: bad input is refused", "[net]") {
  CHECK_THROWS_AS(unfold(make_polygon(5)), InputError);  // a polygon: nothing to unfold into
  CHECK_THROWS_AS(unfold(make_cube(5)), InputError);
  NetOptions opt;
  opt.root = 8;
  CHECK_THROWS_AS(unfold(make_cube(4), opt), InputError);
  CHECK_THROWS_AS(parse_net_tree("spiral"), InputError);
  // An open surface: a cube without its top face.
  ComplexSoup soup;
  soup.ambient_dim = 3;
  const Complex cube = make_cube(3);
  soup.positions = cube.positions();
  for (std::uint32_t f = 0; f + 1 < cube.count(2); ++f) soup.faces.push_back(cube.face_cycle(f));
  BuildOptions bo;
  bo.orient = false;
  CHECK_THROWS_AS(unfold(build_complex(soup, bo)), TopologyError);
}
