#pragma once
// G4MF, the Good 4D Model Format of the godot-4d project (https://github.com/godot-dimensions/
// g4mf, CC0): reading and writing a complex as one G4MF mesh, in its three containers:
//
//   .g4tf  JSON text with the buffer embedded as a base64 data URI ("data:application/
//          octet-stream;base64,...")
//   .g4tf  JSON text with the buffer in an external file (written as STEM.bin beside it)
//   .g4b   binary: a 16-byte header "G4MF", version 0, file size; then a JSON chunk and a BLOB
//          chunk, each with a 16-byte chunk header and padded to 16 bytes
//
// What is written (one mesh, one surface, a root node with one mesh-instance child):
//   mesh.vertices            float64, vectorSize n (the coordinates, bit for bit)
//   surface.edges            unsigned ints, vectorSize 2: [tail, head] of every edge, in id order
//   surface.geometry[t]      the elements of rank t + 2 as G4MF count-prefixed lists: a face as
//                            its edges in cycle order, a cell as its faces, ... (ids as in the
//                            complex; unsigned, the smallest of uint8/16/32 that holds them)
//   surface.normals          the facet normals (float64): one per facet (geometryDimension =
//                            decomposeDimension = n - 1) and per facet corner (decompose 0)
//   surface.textureMap       (optional) float32 texture coordinates per facet corner
//   material.baseColor.elementMap   the colors of every rank that has them, one per element
//                            (geometryDimension = decomposeDimension = rank), in linear RGBA
//                            (cw4d stores sRGB-encoded r, g, b: converted both ways)
//   surface.extras.cw4d.signs[t]    int8, cw4d's orientation sign of every entry of geometry[t]
//
// Orientation. G4MF has no signs: an element's orientation is defined by its first two
// boundary elements (docs/formats.md, and the spec's topology.md): a face by its first two
// edges (the walk from the first into the second), a k-cell (k >= 3) by the simplex that
// godot-4d's reader builds from its first two members (the "canonical span": for a 3-cell the
// far vertex of the edge after the shared edge in the first face, the shared edge's start and
// end, the far vertex of the edge after it in the second face), whose perpendicular vector is
// the cell's normal. The writer therefore lists every element of rank >= 3 with two members
// that share a ridge first, in the order that makes that simplex agree with the element's
// orientation (facets: its normal points outward), and keeps the remaining members in their
// order; in R^3 a face whose first corner is not convex is rotated to start at a convex one.
// Faces of 4D models are written as they are. The reader derives the signs from the same
// rules (face signs from the walk, cell signs by propagating across shared ridges and fixing
// the whole by the first two members), and uses the cw4d sign extras only for elements the
// rules cannot orient (cells whose members are not connected across ridges, degenerate first
// two members); where both exist and disagree, G4MF's rules win (with a warning).
//
// What is read: the first mesh instanced by the node tree (or mesh 0 when there are no
// nodes), in its own coordinates (node transforms are not applied); the surfaces of that mesh
// are merged (edges with the same two ends and faces with the same edges are welded). A
// surface with `geometry` is read as a complex; one with only `simplexes` is built from its
// simplices through build_complex (triangles in R^3, tetrahedra in R^4, ...; consecutive
// simplices sharing their first vertex are merged when `polytopeSimplexes` is true) and
// oriented like an nOFF file. Colors come from the material's baseColor (factor times the
// per-element values), facet normals from the normals binding when it holds a unit vector
// per facet (else they are computed). Texture maps, node transforms, materials' other
// channels, skins, blend shapes, cameras, lights, physics and textures are not read.
//
// Hostile input: every size, offset and index is checked before it is used (buffers at most
// max_input_file_bytes in all, byte ranges inside their buffers, accessor strides and
// alignment, element counts inside their accessors, ids below the counts they index); the
// JSON nests at most 64 deep; compressed (Zstd) chunks, remote URIs and absolute or
// parent-folder (..) buffer paths are refused. Every failure is a ParseError
// "FILE:0: G4MF: ...".
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// The three ways a G4MF file is stored.
enum class G4mfContainer {
  text_embedded,  ///< .g4tf, the buffer as a base64 data URI
  text_external,  ///< .g4tf + STEM.bin
  binary,         ///< .g4b
};

/// True for ".g4tf" and ".g4b" (lower case, with the dot).
bool is_g4mf_extension(std::string_view lower_extension);

struct G4mfWriteOptions {
  G4mfContainer container = G4mfContainer::text_embedded;
  /// The model's name (a spec or a file name); item names are made from it, with the characters
  /// G4MF forbids in names replaced by '_'. Empty: "model".
  std::string name;
  /// Stored as asset.extras.description (e.g. the model and the plane of a section).
  std::string description;
  /// Texture coordinates of the facet corners: texture_dim > 0 and texture(facet, vertex, out)
  /// writes texture_dim floats for the corner `vertex` of facet `facet`.
  int texture_dim = 0;
  std::function<void(std::uint32_t facet, std::uint32_t vertex, float* out)> texture;
};

/// The files of a G4MF output: the main file's bytes and, for text_external, the buffer's
/// (written to `buffer_name`, the name the JSON refers to).
struct G4mfFiles {
  std::string main;
  std::string buffer;
  std::string buffer_name;
};

/// Encodes `complex` (ambient dimension 2 .. 16, tables well formed). `buffer_name` is the
/// file name the JSON of text_external refers to (ignored otherwise).
/// \throw InputError for a complex G4MF (or this writer) cannot hold.
G4mfFiles g4mf_files(const Complex& complex, const G4mfWriteOptions& options,
                     const std::string& buffer_name = "model.bin");

/// Writes `path` (and for text_external STEM.bin beside it, written first) through temporary
/// files and renames. \return the paths written (the .bin first). \throw InputError, IoError.
std::vector<std::string> write_g4mf_file(const std::string& path, const Complex& complex,
                                         const G4mfWriteOptions& options);

/// A mesh of simplices for G4MF's ready-to-render `simplexes` (godot-4d's tetrahedral meshes):
/// triangles in R^2, n vertices per simplex in R^n.
struct G4mfSimplexMesh {
  Eigen::MatrixXd positions;  ///< n x V
  /// The vertex ids of each simplex, oriented as G4MF reads them: the perpendicular of
  /// (v1 - v0, ..., v(n-1) - v0) points out of the solid.
  std::vector<std::uint32_t> simplexes;
  std::vector<std::uint32_t> simplex_cell;  ///< the model cell of each simplex
  Eigen::MatrixXd cell_normals;             ///< n x C unit normals; 0 columns: none
  Eigen::MatrixXf corner_texture;           ///< d x (corners of all simplices); 0 columns: none
  std::vector<Rgba> cell_colors;  ///< C colors (sRGB-encoded as cw4d stores them); or none
};

/// Encodes a simplex mesh: `simplexes`, the normals of the source cells per corner and per
/// simplex (`simplexes` and `perSimplex` of the normals binding), the corner texture coordinates,
/// and the cells' colors per simplex (the base color's `perSimplex`), as godot-4d reads them.
/// \throw InputError when the arrays do not fit together.
G4mfFiles g4mf_simplex_files(const G4mfSimplexMesh& mesh, const G4mfWriteOptions& options,
                             const std::string& buffer_name = "model.bin");
/// Writes them as write_g4mf_file does. \throw InputError, IoError.
std::vector<std::string> write_g4mf_simplex_file(const std::string& path,
                                                 const G4mfSimplexMesh& mesh,
                                                 const G4mfWriteOptions& options);

struct G4mfReadOptions {
  /// Folder that relative buffer URIs are resolved against; empty: external buffers are
  /// refused (the fuzz target reads bytes only).
  std::string base_directory;
  bool allow_external = true;
};

/// Reads a complex from the bytes of a .g4tf or .g4b file (told apart by the "G4MF" magic);
/// `name` is used in messages. \throw ParseError; InputError when the model is beyond
/// max_orientation_work (builder.hpp).
Complex read_g4mf(std::string_view bytes, const std::string& name,
                  const G4mfReadOptions& options = {});
/// Reads a regular file of at most max_input_file_bytes (input_file.hpp); external buffers
/// are resolved against its folder. \throw ParseError, InputError.
Complex read_g4mf_file(const std::string& path);

}  // namespace cw4d
