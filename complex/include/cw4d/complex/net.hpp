#pragma once
// Nets: the facets of a closed polytope unfolded into the hyperplane of one of them.
//
// The facets of a closed complex in R^n (the cells of a 4D polytope, the faces of a 3D one) are
// adjacent across their ridges (the faces of the cells, the edges of the faces). A spanning tree
// of that adjacency graph, rooted at one facet, unfolds the polytope: each child is rotated about
// the ridge it shares with its parent into the parent's hyperplane, on the far side of that
// ridge, and the rotations compose down the tree, so every facet lands in the root's hyperplane
// with the ridges of the tree shared exactly by the two pieces they join. The result is a
// complex in R^(n-1): one solid (a polyhedron for a 4D model, a polygon for a 3D one) per facet,
// in the coordinates of an orthonormal basis of the root's hyperplane.
//
// A net is wanted without overlapping pieces. Whether one exists for every convex polytope is
// open even in 3D (Duerer's problem; see O'Rourke, "How to Fold It", 2011); unfold() tries a
// sequence of trees (NetTree::Auto) and reports when none it tried is free of overlaps.
//
// Overlap of two pieces is decided by the separating-axis theorem: two convex polytopes in R^m
// have disjoint interiors exactly when some facet normal of either (and, for m = 3, some cross
// product of an edge of one with an edge of the other) separates their vertex sets. Pieces that
// only touch (a shared ridge, a shared vertex, coplanar faces) do not overlap: a separation
// within `overlap_tol_rel` times the polytope's diameter counts as a separation. For non-convex
// pieces the same axes are tried on their vertex sets: a separating axis proves the pieces
// disjoint, but finding none only shows that their convex hulls meet, so the test is
// conservative there (a net reported free of overlaps is; a reported overlap may be false).
#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// How the spanning tree of the facet-adjacency graph is chosen.
enum class NetTree {
  /// Breadth first from the root, neighbours in the order of the facet's boundary list: the
  /// most compact tree (the tesseract's cross of eight cubes).
  Bfs,
  /// Depth first from the root, same neighbour order: long chains.
  Dfs,
  /// Breadth first, but a facet is only attached where it overlaps no facet placed before it;
  /// a facet that fits nowhere when its turn comes is retried after the others, and the tree
  /// fails when a full pass places nothing (unfold then returns the Bfs tree, overlaps and all).
  Greedy,
  /// A random spanning tree (random edge weights, Kruskal), seeded by NetOptions::seed.
  Random,
  /// The first tree without overlaps among: Bfs, Greedy, Dfs and Greedy in depth-first order
  /// (the candidates taken last in, first out: long strips) from the root, then
  /// NetOptions::random_trees Random trees (seeds seed, seed + 1, ...); when no root is given,
  /// the same again from every other facet in id order, up to NetOptions::max_roots roots.
  /// When none is free of overlaps, the tried tree with the fewest overlapping pairs. When a
  /// facet is not convex (star cells), only Bfs and the two Greedy trees from the root are
  /// tried: the conservative overlap test rarely clears such pieces.
  Auto,
};

/// "bfs", "dfs", "greedy", "random", "auto".
const char* net_tree_name(NetTree tree);
/// The tree named `name`. \throw InputError for an unknown name.
NetTree parse_net_tree(const std::string& name);

struct NetOptions {
  /// The facet whose hyperplane the net lies in; -1: facet 0 (Auto: then also the others).
  long long root = -1;
  NetTree tree = NetTree::Auto;
  std::uint64_t seed = 1;
  int random_trees = 16;  ///< Auto: random trees tried per root
  int max_roots = 8;      ///< Auto without a root: roots tried
  /// Pieces whose separation exceeds -overlap_tol_rel * diameter do not overlap.
  double overlap_tol_rel = 1e-9;
};

struct Net {
  /// In R^(n-1): one closed piece per facet of the model (pieces share no vertices; along the
  /// ridges of the tree their vertices coincide), the pieces as elements of rank n-1 with the
  /// model facets' colors.
  Complex complex{3};
  /// Model facet of each piece (element of rank n-1 of `complex`): piece i is facet i.
  std::vector<std::uint32_t> piece_facet;
  /// Model facet of each element of rank n-2 of `complex` (the faces of the polyhedra of a 4D
  /// net, the edges of the polygons of a 3D one).
  std::vector<std::uint32_t> boundary_facet;
  /// Per model facet: its parent in the tree (-1 for the root) and the ridge shared with it.
  std::vector<long long> parent;
  std::vector<std::uint32_t> hinge;
  std::uint32_t root = 0;
  NetTree tree = NetTree::Bfs;  ///< the strategy that produced this tree
  std::uint64_t seed = 0;       ///< for NetTree::Random
  int trees_tried = 0;
  /// Pairs of model facets (a < b) whose pieces overlap; empty for a net without overlaps.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> overlaps;
  /// Per model facet, the isometry of R^n that unfolds it: x -> linear * x + translation.
  std::vector<Eigen::MatrixXd> linear;
  std::vector<Eigen::VectorXd> translation;
  /// The root's hyperplane: net coordinates y = basis^T (x - origin), basis n x (n-1)
  /// orthonormal, orthogonal to the root's outward normal.
  Eigen::VectorXd origin;
  Eigen::MatrixXd basis;
  /// Number of vertex ids of each piece in `complex`: piece i owns the vertices from
  /// vertex_begin[i] to vertex_begin[i + 1].
  std::vector<std::uint32_t> vertex_begin;
};

/// Unfolds a closed complex in R^3 or R^4 (each ridge bounding exactly two facets).
/// \throw InputError for another dimension or a bad root; TopologyError when a ridge does not
///        bound exactly two facets or the adjacency graph is not connected.
Net unfold(const Complex& model, const NetOptions& options = {});

/// Whether two convex point sets in R^2 or R^3 have overlapping interiors, by separating axes:
/// the candidate axes are `axes` (facet normals of both and, in R^3, the edge cross products,
/// supplied by the caller), a separation larger than -tol counts as disjoint.
bool interiors_overlap(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                       const std::vector<Eigen::VectorXd>& axes, double tol);

/// The overlapping pairs of pieces of a net (a < b, in model facet ids), recomputed from the
/// net's complex alone: separating axes from each pair's facet normals and edge cross
/// products, with a tolerance of tol_rel times the net's diameter.
std::vector<std::pair<std::uint32_t, std::uint32_t>> net_overlaps(const Net& net,
                                                                  double tol_rel = 1e-9);

}  // namespace cw4d
