// Nets of closed polytopes (see net.hpp).
#include "cw4d/complex/net.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <random>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/text.hpp"

namespace cw4d {

const char* net_tree_name(NetTree tree) {
  switch (tree) {
    case NetTree::Bfs:
      return "bfs";
    case NetTree::Dfs:
      return "dfs";
    case NetTree::Greedy:
      return "greedy";
    case NetTree::Random:
      return "random";
    case NetTree::Auto:
      return "auto";
  }
  return "auto";
}

NetTree parse_net_tree(const std::string& name) {
  for (NetTree t : {NetTree::Bfs, NetTree::Dfs, NetTree::Greedy, NetTree::Random, NetTree::Auto})
    if (name == net_tree_name(t)) return t;
  throw InputError("unknown net tree " + quote_user_text(name) +
                   ": choose auto, bfs, dfs, greedy or random");
}

bool interiors_overlap(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                       const std::vector<Eigen::VectorXd>& axes, double tol) {
  for (const auto& axis : axes) {
    const Eigen::RowVectorXd pa = axis.transpose() * a, pb = axis.transpose() * b;
    if (pa.maxCoeff() - pb.minCoeff() <= tol || pb.maxCoeff() - pa.minCoeff() <= tol) return false;
  }
  return true;
}

namespace {

// A facet placed in the net: its vertices in net coordinates and its separating-axis candidates.
struct Piece {
  Eigen::MatrixXd points;                // m x k
  std::vector<Eigen::VectorXd> normals;  // unit facet normals of the piece
  std::vector<Eigen::VectorXd> edges;    // unit edge directions (m = 3)
  Eigen::VectorXd centre;
  double radius = 0.0;
  bool convex = true;  // no facet plane has vertices on both sides
};

bool separated(const Piece& a, const Piece& b, const Eigen::VectorXd& axis, double tol) {
  const Eigen::RowVectorXd pa = axis.transpose() * a.points, pb = axis.transpose() * b.points;
  return pa.maxCoeff() - pb.minCoeff() <= tol || pb.maxCoeff() - pa.minCoeff() <= tol;
}

// The normal of `normals` that points most along `towards` (the first on ties), or -1.
int most_aligned(const std::vector<Eigen::VectorXd>& normals, const Eigen::VectorXd& towards) {
  int best = -1;
  double best_dot = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double d = normals[i].dot(towards);
    if (d > best_dot) {
      best_dot = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

bool pieces_overlap(const Piece& a, const Piece& b, double tol) {
  const Eigen::VectorXd towards_b = b.centre - a.centre;
  if (towards_b.norm() >= a.radius + b.radius - tol) return false;
  // Pieces that are apart are nearly always split by the facet of one that faces the other:
  // those two axes are tried first, so a pair of many-sided pieces costs a pass over the
  // normals instead of a projection of every point per normal. (Only the order of the
  // separating-axis tests changes, not the answer.)
  if (const int i = most_aligned(a.normals, towards_b);
      i >= 0 && separated(a, b, a.normals[i], tol))
    return false;
  if (const int i = most_aligned(b.normals, -towards_b);
      i >= 0 && separated(a, b, b.normals[i], tol))
    return false;
  for (const auto& n : a.normals)
    if (separated(a, b, n, tol)) return false;
  for (const auto& n : b.normals)
    if (separated(a, b, n, tol)) return false;
  if (a.points.rows() == 3) {
    for (const auto& ea : a.edges)
      for (const auto& eb : b.edges) {
        const Eigen::Vector3d x = Eigen::Vector3d(ea).cross(Eigen::Vector3d(eb));
        const double len = x.norm();
        if (len < 1e-9) continue;  // parallel edges: covered by the facet normals
        if (separated(a, b, Eigen::VectorXd(x / len), tol)) return false;
      }
  }
  return true;
}

class Unfolder {
 public:
  Unfolder(const Complex& model, const NetOptions& opt) : c_(model), opt_(opt) {
    n_ = model.ambient_dim();
    if (n_ != 3 && n_ != 4)
      throw InputError("nets unfold closed complexes in R^3 or R^4; this one lives in R^" +
                       std::to_string(n_));
    m_ = n_ - 1;
    if (model.top_rank() < m_ || model.count(m_) == 0)
      throw InputError("the model has no facets (elements of rank " + std::to_string(m_) +
                       ") to unfold");
    nf_ = static_cast<std::uint32_t>(model.count(m_));
    if (opt.root >= static_cast<long long>(nf_) || opt.root < -1)
      throw InputError("--root " + std::to_string(opt.root) + ": the model has facets 0.." +
                       std::to_string(nf_ - 1));
    build_adjacency();
    build_geometry();
  }

  Net run() {
    std::vector<std::uint32_t> roots;
    if (opt_.root >= 0) {
      roots.push_back(static_cast<std::uint32_t>(opt_.root));
    } else {
      const std::uint32_t count = opt_.tree == NetTree::Auto
                                      ? std::min<std::uint32_t>(nf_, std::max(1, opt_.max_roots))
                                      : 1;
      for (std::uint32_t r = 0; r < count; ++r) roots.push_back(r);
    }
    int tried = 0;
    Net best;
    bool have_best = false;
    auto consider = [&](Net net) {
      ++tried;
      if (!have_best || net.overlaps.size() < best.overlaps.size()) {
        best = std::move(net);
        have_best = true;
      }
      return best.overlaps.empty();
    };
    // A tree with as many overlaps as the best one so far is not counted to the end.
    auto enough = [&]() -> std::size_t {
      return have_best && !best.overlaps.empty() ? best.overlaps.size() - 1
                                                 : std::numeric_limits<std::size_t>::max();
    };
    for (const std::uint32_t root : roots) {
      if (opt_.tree != NetTree::Auto) {
        std::vector<long long> parent;
        std::vector<std::uint32_t> hinge;
        NetTree used = opt_.tree;
        if (opt_.tree == NetTree::Greedy) {
          if (!greedy_tree(root, parent, hinge)) {
            // No overlap-free placement: report the breadth-first tree's overlaps instead.
            bfs_tree(root, false, parent, hinge);
            used = NetTree::Bfs;
          }
        } else if (opt_.tree == NetTree::Random) {
          random_tree(root, opt_.seed, parent, hinge);
        } else {
          bfs_tree(root, opt_.tree == NetTree::Dfs, parent, hinge);
        }
        consider(make_net(root, parent, hinge, used, opt_.seed));
        break;
      }
      std::vector<long long> parent;
      std::vector<std::uint32_t> hinge;
      bfs_tree(root, false, parent, hinge);
      if (consider(make_net(root, parent, hinge, NetTree::Bfs, 0, enough()))) break;
      // Non-convex cells: the overlap test only clears pieces that a plane separates, which
      // star cells rarely allow; only the greedy trees (which fail fast) are tried.
      const bool quick = nonconvex_;
      if (greedy_tree(root, parent, hinge)) {
        if (consider(make_net(root, parent, hinge, NetTree::Greedy, 0, enough()))) break;
      } else {
        ++tried;
      }
      if (!quick) {
        bfs_tree(root, true, parent, hinge);
        if (consider(make_net(root, parent, hinge, NetTree::Dfs, 0, enough()))) break;
      }
      if (greedy_tree(root, parent, hinge, true)) {
        if (consider(make_net(root, parent, hinge, NetTree::Greedy, 0, enough()))) break;
      } else {
        ++tried;
      }
      if (quick) break;
      bool done = false;
      for (int k = 0; k < opt_.random_trees && !done; ++k) {
        random_tree(root, opt_.seed + k, parent, hinge);
        done = consider(make_net(root, parent, hinge, NetTree::Random, opt_.seed + k, enough()));
      }
      if (done) break;
    }
    best.trees_tried = tried;
    return best;
  }

 private:
  const Complex& c_;
  const NetOptions& opt_;
  int n_ = 4, m_ = 3;
  std::uint32_t nf_ = 0;
  double tol_ = 0.0;
  mutable bool nonconvex_ = false;  // set by make_net when a piece is not convex
  // Per facet: its (neighbour, ridge) pairs in boundary order.
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> nbr_;
  // Per facet: sorted vertex ids, vertex centroid, unit outward normal, the cycles of its own
  // facets (m = 3: the faces of the cell; m = 2: the polygon itself) and its edges.
  std::vector<std::vector<std::uint32_t>> verts_;
  std::vector<Eigen::VectorXd> centroid_, normal_;
  std::vector<std::vector<std::vector<std::uint32_t>>> cycles_;
  std::vector<std::vector<std::array<std::uint32_t, 2>>> edges_;

  void build_adjacency() {
    const Incidence& facets = c_.boundary(m_);
    const std::size_t nr = c_.count(m_ - 1);
    std::vector<std::vector<std::uint32_t>> of_ridge(nr);
    for (std::uint32_t f = 0; f < nf_; ++f)
      for (const std::uint32_t r : facets.ids(f)) of_ridge[r].push_back(f);
    for (std::uint32_t r = 0; r < nr; ++r)
      if (of_ridge[r].size() != 2)
        throw TopologyError(m_ - 1, {r},
                            "cannot unfold: ridge " + std::to_string(r) + " bounds " +
                                std::to_string(of_ridge[r].size()) +
                                " facets instead of 2 (the model is not closed)");
    nbr_.assign(nf_, {});
    for (std::uint32_t f = 0; f < nf_; ++f)
      for (const std::uint32_t r : facets.ids(f)) {
        const auto& two = of_ridge[r];
        nbr_[f].push_back({two[0] == f ? two[1] : two[0], r});
      }
    // Connected?
    std::vector<char> seen(nf_, 0);
    std::vector<std::uint32_t> stack{0};
    seen[0] = 1;
    std::size_t reached = 1;
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      for (const auto& [g, r] : nbr_[f])
        if (!seen[g]) {
          seen[g] = 1;
          ++reached;
          stack.push_back(g);
        }
    }
    if (reached != nf_)
      throw TopologyError(m_, {0},
                          "cannot unfold: the facets form more than one connected piece (" +
                              std::to_string(reached) + " of " + std::to_string(nf_) +
                              " reached from facet 0)");
  }

  void build_geometry() {
    const auto& p = c_.positions();
    const double diameter = (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
    tol_ = opt_.overlap_tol_rel * diameter;
    verts_.resize(nf_);
    centroid_.resize(nf_);
    normal_.resize(nf_);
    cycles_.resize(nf_);
    edges_.resize(nf_);
    for (std::uint32_t f = 0; f < nf_; ++f) {
      verts_[f] = c_.vertices_of(m_, f);
      Eigen::VectorXd sum = Eigen::VectorXd::Zero(n_);
      for (const auto v : verts_[f]) sum += p.col(v);
      centroid_[f] = sum / static_cast<double>(verts_[f].size());
      const Eigen::VectorXd a = facet_area_vector(c_, f, position_scale(c_));
      if (!(a.norm() > 0.0))
        throw TopologyError(
            m_, {f}, "cannot unfold: facet " + std::to_string(f) + " is degenerate (no normal)");
      normal_[f] = a.normalized();
      std::vector<std::uint32_t> edge_ids;
      if (m_ == 3) {
        for (const std::uint32_t face : c_.boundary(3).ids(f)) {
          cycles_[f].push_back(c_.face_cycle(face));
          for (const std::uint32_t e : c_.boundary(2).ids(face)) edge_ids.push_back(e);
        }
      } else {
        cycles_[f].push_back(c_.face_cycle(f));
        for (const std::uint32_t e : c_.boundary(2).ids(f)) edge_ids.push_back(e);
      }
      std::sort(edge_ids.begin(), edge_ids.end());
      edge_ids.erase(std::unique(edge_ids.begin(), edge_ids.end()), edge_ids.end());
      for (const auto e : edge_ids) edges_[f].push_back(c_.edge(e));
    }
  }

  // The rotation of R^n about the ridge r shared by facets p and ch that takes ch into p's
  // hyperplane on the far side of r: x -> L x + t.
  void hinge_rotation(std::uint32_t p, std::uint32_t ch, std::uint32_t r, Eigen::MatrixXd& L,
                      Eigen::VectorXd& t) const {
    const auto& pos = c_.positions();
    const auto rv = c_.vertices_of(m_ - 1, r);
    Eigen::VectorXd o = Eigen::VectorXd::Zero(n_);
    for (const auto v : rv) o += pos.col(v);
    o /= static_cast<double>(rv.size());
    Eigen::MatrixXd D(n_, rv.size());
    for (std::size_t i = 0; i < rv.size(); ++i) D.col(i) = pos.col(rv[i]) - o;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(D, Eigen::ComputeThinU);
    const Eigen::MatrixXd U = svd.matrixU().leftCols(n_ - 2);  // the ridge's directions
    auto inward = [&](std::uint32_t f) {
      Eigen::VectorXd w = centroid_[f] - o;
      w -= U * (U.transpose() * w);
      w -= normal_[f] * normal_[f].dot(w);
      return Eigen::VectorXd(w.normalized());
    };
    const Eigen::VectorXd a = -inward(p);  // where the child must point to
    Eigen::VectorXd b = normal_[p];
    b -= a * a.dot(b);
    b.normalize();
    const Eigen::VectorXd uc = inward(ch);
    const double theta = std::atan2(b.dot(uc), a.dot(uc));
    const double cs = std::cos(theta), sn = -std::sin(theta);  // rotate by -theta
    L = Eigen::MatrixXd::Identity(n_, n_) + (cs - 1.0) * (a * a.transpose() + b * b.transpose()) +
        sn * (b * a.transpose() - a * b.transpose());
    t = o - L * o;
  }

  Eigen::MatrixXd root_basis(std::uint32_t root) const {
    const Eigen::VectorXd nr = normal_[root];
    const Eigen::MatrixXd column = nr;
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(column);
    Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(n_, n_);
    Eigen::MatrixXd B = Q.rightCols(n_ - 1);
    Eigen::MatrixXd F(n_, n_);
    F.col(0) = nr;
    F.rightCols(n_ - 1) = B;
    if (F.determinant() < 0.0) B.col(n_ - 2) *= -1.0;  // det(N, basis) > 0: outward stays outward
    return B;
  }

  Piece make_piece(std::uint32_t f, const Eigen::MatrixXd& L, const Eigen::VectorXd& t,
                   const Eigen::VectorXd& origin, const Eigen::MatrixXd& B) const {
    Piece pc;
    const auto& pos = c_.positions();
    const auto& vs = verts_[f];
    pc.points.resize(m_, vs.size());
    for (std::size_t i = 0; i < vs.size(); ++i)
      pc.points.col(i) = B.transpose() * (L * pos.col(vs[i]) + t - origin);
    auto local = [&](std::uint32_t v) {
      return pc.points.col(std::lower_bound(vs.begin(), vs.end(), v) - vs.begin());
    };
    if (m_ == 3) {
      for (const auto& cyc : cycles_[f]) {
        Eigen::Vector3d nn = Eigen::Vector3d::Zero();  // Newell normal
        for (std::size_t i = 0; i < cyc.size(); ++i) {
          const Eigen::Vector3d a = local(cyc[i]), b = local(cyc[(i + 1) % cyc.size()]);
          nn += a.cross(b);
        }
        if (nn.norm() > 0.0) pc.normals.push_back(nn.normalized());
      }
      for (const auto& e : edges_[f]) {
        const Eigen::VectorXd d = local(e[1]) - local(e[0]);
        if (d.norm() > 0.0) pc.edges.push_back(d.normalized());
      }
    } else {
      for (const auto& e : edges_[f]) {
        const Eigen::Vector2d d = local(e[1]) - local(e[0]);
        if (d.norm() > 0.0) pc.normals.push_back(Eigen::Vector2d(-d.y(), d.x()).normalized());
      }
    }
    pc.centre = pc.points.rowwise().mean();
    for (Eigen::Index i = 0; i < pc.points.cols(); ++i)
      pc.radius = std::max(pc.radius, (pc.points.col(i) - pc.centre).norm());
    // Convex when every facet plane (through the facet's first vertex) has all vertices on
    // one side.
    auto both_sides = [&](const Eigen::VectorXd& n, const Eigen::VectorXd& at) {
      const Eigen::RowVectorXd h = n.transpose() * (pc.points.colwise() - at);
      return h.minCoeff() < -tol_ && h.maxCoeff() > tol_;
    };
    if (m_ == 3) {
      std::size_t k = 0;
      for (const auto& cyc : cycles_[f]) {
        if (k >= pc.normals.size()) break;
        if (both_sides(pc.normals[k++], local(cyc[0]))) pc.convex = false;
      }
    } else {
      std::size_t k = 0;
      for (const auto& e : edges_[f]) {
        if (k >= pc.normals.size()) break;
        if (both_sides(pc.normals[k++], local(e[0]))) pc.convex = false;
      }
    }
    return pc;
  }

  void bfs_tree(std::uint32_t root, bool depth_first, std::vector<long long>& parent,
                std::vector<std::uint32_t>& hinge) const {
    parent.assign(nf_, -2);
    hinge.assign(nf_, 0);
    parent[root] = -1;
    if (!depth_first) {
      std::deque<std::uint32_t> queue{root};
      while (!queue.empty()) {
        const std::uint32_t f = queue.front();
        queue.pop_front();
        for (const auto& [g, r] : nbr_[f])
          if (parent[g] == -2) {
            parent[g] = f;
            hinge[g] = r;
            queue.push_back(g);
          }
      }
      return;
    }
    // Depth first: follow the first unvisited neighbour, back up when there is none.
    std::vector<std::pair<std::uint32_t, std::size_t>> stack{{root, 0}};
    while (!stack.empty()) {
      auto& [f, next] = stack.back();
      if (next == nbr_[f].size()) {
        stack.pop_back();
        continue;
      }
      const auto [g, r] = nbr_[f][next++];
      if (parent[g] != -2) continue;
      parent[g] = f;
      hinge[g] = r;
      stack.push_back({g, 0});
    }
  }

  void random_tree(std::uint32_t root, std::uint64_t seed, std::vector<long long>& parent,
                   std::vector<std::uint32_t>& hinge) const {
    struct Link {
      std::uint32_t a, b, r;
      double w;
    };
    std::vector<Link> links;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::uint32_t f = 0; f < nf_; ++f)
      for (const auto& [g, r] : nbr_[f])
        if (f < g) links.push_back({f, g, r, 0.0});
    for (auto& l : links) l.w = unit(rng);
    std::sort(links.begin(), links.end(), [](const Link& x, const Link& y) { return x.w < y.w; });
    std::vector<std::uint32_t> up(nf_);
    std::iota(up.begin(), up.end(), 0u);
    auto find = [&](std::uint32_t x) {
      while (up[x] != x) x = up[x] = up[up[x]];
      return x;
    };
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> tree(nf_);
    for (const auto& l : links) {
      const auto ra = find(l.a), rb = find(l.b);
      if (ra == rb) continue;
      up[ra] = rb;
      tree[l.a].push_back({l.b, l.r});
      tree[l.b].push_back({l.a, l.r});
    }
    parent.assign(nf_, -2);
    hinge.assign(nf_, 0);
    parent[root] = -1;
    std::vector<std::uint32_t> stack{root};
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      for (const auto& [g, r] : tree[f])
        if (parent[g] == -2) {
          parent[g] = f;
          hinge[g] = r;
          stack.push_back(g);
        }
    }
  }

  // Breadth first, attaching a facet only where it overlaps nothing placed.
  bool greedy_tree(std::uint32_t root, std::vector<long long>& parent,
                   std::vector<std::uint32_t>& hinge, bool depth_first = false) const {
    parent.assign(nf_, -2);
    hinge.assign(nf_, 0);
    std::vector<Eigen::MatrixXd> L(nf_);
    std::vector<Eigen::VectorXd> T(nf_);
    std::vector<Piece> pieces(nf_);
    std::vector<std::uint32_t> placed;
    const Eigen::VectorXd origin = centroid_[root];
    const Eigen::MatrixXd B = root_basis(root);
    L[root] = Eigen::MatrixXd::Identity(n_, n_);
    T[root] = Eigen::VectorXd::Zero(n_);
    pieces[root] = make_piece(root, L[root], T[root], origin, B);
    parent[root] = -1;
    placed.push_back(root);
    struct Candidate {
      std::uint32_t child, parent, ridge;
    };
    std::deque<Candidate> queue, deferred;
    for (const auto& [g, r] : nbr_[root]) queue.push_back({g, root, r});
    bool progress = false;
    while (true) {
      if (queue.empty()) {
        if (deferred.empty() || !progress) break;
        queue.swap(deferred);
        progress = false;
      }
      const Candidate cand = depth_first ? queue.back() : queue.front();
      if (depth_first)
        queue.pop_back();
      else
        queue.pop_front();
      if (parent[cand.child] != -2) continue;
      Eigen::MatrixXd Lr;
      Eigen::VectorXd tr;
      hinge_rotation(cand.parent, cand.child, cand.ridge, Lr, tr);
      const Eigen::MatrixXd Lc = L[cand.parent] * Lr;
      const Eigen::VectorXd tc = L[cand.parent] * tr + T[cand.parent];
      Piece pc = make_piece(cand.child, Lc, tc, origin, B);
      bool clash = false;
      for (const auto q : placed)
        if (pieces_overlap(pc, pieces[q], tol_)) {
          clash = true;
          break;
        }
      if (clash) {
        deferred.push_back(cand);
        continue;
      }
      parent[cand.child] = cand.parent;
      hinge[cand.child] = cand.ridge;
      L[cand.child] = Lc;
      T[cand.child] = tc;
      pieces[cand.child] = std::move(pc);
      placed.push_back(cand.child);
      progress = true;
      for (const auto& [g, r] : nbr_[cand.child])
        if (parent[g] == -2) queue.push_back({g, cand.child, r});
    }
    return placed.size() == nf_;
  }

  // The net of a tree. Counting overlaps stops once there are more than `enough` (the caller
  // discards such a net: it is no better than one it has).
  Net make_net(std::uint32_t root, const std::vector<long long>& parent,
               const std::vector<std::uint32_t>& hinge, NetTree tree, std::uint64_t seed,
               std::size_t enough = std::numeric_limits<std::size_t>::max()) const {
    Net net;
    net.root = root;
    net.parent = parent;
    net.hinge = hinge;
    net.tree = tree;
    net.seed = seed;
    net.origin = centroid_[root];
    net.basis = root_basis(root);
    net.linear.assign(nf_, Eigen::MatrixXd());
    net.translation.assign(nf_, Eigen::VectorXd());
    // Transforms in tree order (parents before children).
    std::vector<std::vector<std::uint32_t>> children(nf_);
    for (std::uint32_t f = 0; f < nf_; ++f)
      if (parent[f] >= 0) children[parent[f]].push_back(f);
    net.linear[root] = Eigen::MatrixXd::Identity(n_, n_);
    net.translation[root] = Eigen::VectorXd::Zero(n_);
    std::deque<std::uint32_t> queue{root};
    while (!queue.empty()) {
      const std::uint32_t f = queue.front();
      queue.pop_front();
      for (const auto g : children[f]) {
        Eigen::MatrixXd Lr;
        Eigen::VectorXd tr;
        hinge_rotation(f, g, hinge[g], Lr, tr);
        net.linear[g] = net.linear[f] * Lr;
        net.translation[g] = net.linear[f] * tr + net.translation[f];
        queue.push_back(g);
      }
    }
    // The complex: every piece with its own vertices.
    const auto& pos = c_.positions();
    ComplexSoup soup;
    soup.ambient_dim = m_;
    std::size_t total = 0;
    for (const auto& vs : verts_) total += vs.size();
    soup.positions.resize(m_, static_cast<Eigen::Index>(total));
    std::vector<Piece> pieces(nf_);
    net.vertex_begin.push_back(0);
    for (std::uint32_t f = 0; f < nf_; ++f) {
      pieces[f] = make_piece(f, net.linear[f], net.translation[f], net.origin, net.basis);
      if (!pieces[f].convex) nonconvex_ = true;
      const std::uint32_t base = net.vertex_begin.back();
      soup.positions.middleCols(base, pieces[f].points.cols()) = pieces[f].points;
      const auto& vs = verts_[f];
      auto local = [&](std::uint32_t v) {
        return base +
               static_cast<std::uint32_t>(std::lower_bound(vs.begin(), vs.end(), v) - vs.begin());
      };
      std::vector<std::uint32_t> face_ids;
      for (const auto& cyc : cycles_[f]) {
        std::vector<std::uint32_t> mapped;
        for (const auto v : cyc) mapped.push_back(local(v));
        face_ids.push_back(static_cast<std::uint32_t>(soup.faces.size()));
        soup.faces.push_back(std::move(mapped));
      }
      if (m_ == 3) {
        if (soup.higher.empty()) soup.higher.resize(1);
        soup.higher[0].push_back(face_ids);
      }
      net.vertex_begin.push_back(base + static_cast<std::uint32_t>(vs.size()));
    }
    (void)pos;
    const auto& colors = c_.colors(m_);
    if (colors.size() == nf_) {
      if (m_ == 3)
        soup.higher_colors = {colors};
      else
        soup.face_colors = colors;
    }
    net.complex = build_complex(soup);
    auto piece_of_vertex = [&](std::uint32_t v) {
      return static_cast<std::uint32_t>(
          std::upper_bound(net.vertex_begin.begin(), net.vertex_begin.end(), v) -
          net.vertex_begin.begin() - 1);
    };
    for (std::uint32_t i = 0; i < net.complex.count(m_); ++i)
      net.piece_facet.push_back(piece_of_vertex(net.complex.first_vertex(m_, i)));
    for (std::uint32_t i = 0; i < net.complex.count(m_ - 1); ++i)
      net.boundary_facet.push_back(piece_of_vertex(net.complex.first_vertex(m_ - 1, i)));
    // The pieces' faces carry their cell's color too (what OBJ materials and pictures read).
    if (m_ == 3 && colors.size() == nf_) {
      auto& fc = net.complex.colors_mut(2);
      fc.resize(net.complex.count(2));
      for (std::size_t i = 0; i < fc.size(); ++i) fc[i] = colors[net.boundary_facet[i]];
    }
    // Overlaps.
    for (std::uint32_t a = 0; a < nf_ && net.overlaps.size() <= enough; ++a)
      for (std::uint32_t b = a + 1; b < nf_ && net.overlaps.size() <= enough; ++b)
        if (pieces_overlap(pieces[a], pieces[b], tol_)) net.overlaps.push_back({a, b});
    return net;
  }
};

}  // namespace

Net unfold(const Complex& model, const NetOptions& options) {
  return Unfolder(model, options).run();
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> net_overlaps(const Net& net, double tol_rel) {
  const Complex& c = net.complex;
  const int m = c.ambient_dim();
  const auto& p = c.positions();
  const double diameter = p.cols() ? (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm() : 0.0;
  const double tol = tol_rel * diameter;
  const std::size_t np = c.count(m);
  std::vector<Piece> pieces(np);
  for (std::uint32_t i = 0; i < np; ++i) {
    Piece& pc = pieces[net.piece_facet[i]];
    const auto vs = c.vertices_of(m, i);
    pc.points.resize(m, vs.size());
    for (std::size_t k = 0; k < vs.size(); ++k) pc.points.col(k) = p.col(vs[k]);
    std::vector<std::uint32_t> edge_ids;
    if (m == 3) {
      for (const auto face : c.boundary(3).ids(i)) {
        const auto cyc = c.face_cycle(face);
        Eigen::Vector3d nn = Eigen::Vector3d::Zero();
        for (std::size_t k = 0; k < cyc.size(); ++k)
          nn += Eigen::Vector3d(p.col(cyc[k]))
                    .cross(Eigen::Vector3d(p.col(cyc[(k + 1) % cyc.size()])));
        if (nn.norm() > 0.0) pc.normals.push_back(nn.normalized());
        for (const auto e : c.boundary(2).ids(face)) edge_ids.push_back(e);
      }
    } else {
      for (const auto e : c.boundary(2).ids(i)) edge_ids.push_back(e);
    }
    std::sort(edge_ids.begin(), edge_ids.end());
    edge_ids.erase(std::unique(edge_ids.begin(), edge_ids.end()), edge_ids.end());
    for (const auto e : edge_ids) {
      const auto [t, h] = c.edge(e);
      const Eigen::VectorXd d = p.col(h) - p.col(t);
      if (!(d.norm() > 0.0)) continue;
      if (m == 3)
        pc.edges.push_back(d.normalized());
      else
        pc.normals.push_back(Eigen::Vector2d(-d(1), d(0)).normalized());
    }
    pc.centre = pc.points.rowwise().mean();
    for (Eigen::Index k = 0; k < pc.points.cols(); ++k)
      pc.radius = std::max(pc.radius, (pc.points.col(k) - pc.centre).norm());
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (std::uint32_t a = 0; a < np; ++a)
    for (std::uint32_t b = a + 1; b < np; ++b)
      if (pieces_overlap(pieces[a], pieces[b], tol)) out.push_back({a, b});
  return out;
}

}  // namespace cw4d
