#pragma once
// 4OFF / OFF / nOFF reading and writing (the format of Stella4D and Miratope).
//
//   4OFF                      header: "OFF" (3D), "4OFF", or "nOFF" for n = 3..9
//   V F E C                   counts: vertices, faces, edges, then ranks 3 .. n-1
//   x y z w                   V vertex lines, n coordinates each
//   k v0 v1 ... [color]       F faces as vertex cycles, optional trailing color (3 or 4
//                             numbers: integers are bytes 0..255, decimals 0..1)
//   k f0 f1 ... [color]       cells as lists of face indices (then higher ranks likewise)
// '#' starts a comment, anywhere on a line. The edge count is informational: edges are built
// from the face cycles. A color after a vertex's coordinates is read and ignored. Counts that
// disagree with the body (files edited by hand) are replaced by what the body holds when the
// body splits unambiguously into vertices, faces and cells (OFF and 4OFF), with one warning.
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// Where the elements of a complex read from nOFF text are, so that a validation issue (rank,
/// id) can be reported as file:line. lines[k][i] is the 1-based line of element i of rank k:
/// vertices, faces, cells and higher ranks at their own lines; an edge (not listed in nOFF) at
/// the line of the face it first appears in, which is how build_complex numbers edges.
struct OffLines {
  std::vector<std::vector<std::size_t>> lines;
  /// 0 when the element is unknown.
  std::size_t line_of(int rank, std::uint32_t id) const {
    if (rank < 0 || static_cast<std::size_t>(rank) >= lines.size()) return 0;
    return id < lines[rank].size() ? lines[rank][id] : 0;
  }
};

/// How the nOFF readers treat files whose header counts disagree with their body.
struct OffReadOptions {
  /// Refuse such a file (ParseError) instead of reading the body as it stands.
  bool strict = false;
  /// Receives the one warning per file about what was read differently from the header
  /// ("name:line: ..."); warnings are dropped when it is empty.
  std::function<void(const std::string&)> warn;
};

/// The options of the readers on the calling thread while this object lives (the model
/// catalogue reads files through read_off_file, so a command sets them once for every model it
/// loads). Nests: the previous options come back on destruction.
class ScopedOffReadOptions {
 public:
  explicit ScopedOffReadOptions(OffReadOptions options);
  ~ScopedOffReadOptions();
  ScopedOffReadOptions(const ScopedOffReadOptions&) = delete;
  ScopedOffReadOptions& operator=(const ScopedOffReadOptions&) = delete;

 private:
  OffReadOptions previous_;
};
/// The options in force on the calling thread (default: not strict, no warnings).
const OffReadOptions& off_read_options();

/// Reads a complex from a stream; `name` is used in error messages ("name:line: ...").
/// The result is built with build_complex (oriented, with facet normals) but not validated.
/// When `lines` is given it receives the line of every element.
/// Counts in the header never drive allocation before the data is seen to exist.
/// \throw ParseError with the line of the first problem.
Complex read_off(std::istream& in, const std::string& name, OffLines* lines = nullptr);
/// Reads a regular file of at most max_input_file_bytes (input_file.hpp).
/// \throw ParseError (line 0 when it cannot be opened or is not a regular file).
Complex read_off_file(const std::string& path, OffLines* lines = nullptr);

/// Writes a complex (ranks 0 .. ambient_dim - 1) as nOFF ("OFF" for 3D, "4OFF" for 4D), with
/// full double precision and the colors of faces and higher ranks when present (as decimals,
/// so that they read back on the 0..1 scale).
void write_off(std::ostream& out, const Complex& complex);
/// Writes a file through a temporary file and a rename. \throw IoError.
void write_off_file(const std::string& path, const Complex& complex);

}  // namespace cw4d
