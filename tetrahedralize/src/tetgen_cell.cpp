// The only translation unit that includes TetGen.
#include "tetgen_cell.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <tetgen.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <string>

#include "cw4d/section/hyperplane.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"

namespace cw4d {

namespace {

std::string tetgen_reason(int code) {
  switch (code) {
    case 1:
      return "out of memory";
    case 2:
      return "internal error";
    case 3:
      return "the cell's boundary intersects itself";
    case 4:
      return "a very small input feature (near-degenerate boundary)";
    case 5:
      return "two boundary faces are very close";
    case 10:
      return "invalid input (e.g. an open or non-manifold boundary)";
    default:
      return "error code " + std::to_string(code);
  }
}

}  // namespace

TetgenCellResult tetgen_cell(const Complex& complex, std::uint32_t cell,
                             const std::vector<std::uint32_t>& vertices,
                             const std::vector<std::array<std::uint32_t, 3>>& boundary,
                             const Eigen::Vector4d& normal) {
  const auto& p = complex.positions();
  const Eigen::MatrixXd basis = hyperplane_basis(Eigen::VectorXd(normal));
  Eigen::Vector4d centre = Eigen::Vector4d::Zero();
  for (auto v : vertices) centre += p.col(v);
  centre /= static_cast<double>(vertices.size());
  auto local = [&](std::uint32_t v) {
    return static_cast<int>(std::lower_bound(vertices.begin(), vertices.end(), v) -
                            vertices.begin());
  };

  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(vertices.size());
  in.pointlist = new REAL[3 * vertices.size()];
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3d y = basis.transpose() * (p.col(vertices[i]) - centre);
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + static_cast<std::size_t>(k)] = y(k);
  }
  in.numberoffacets = static_cast<int>(boundary.size());
  in.facetlist = new tetgenio::facet[boundary.size()];
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    tetgenio::facet& f = in.facetlist[i];
    tetgenio::init(&f);
    f.numberofpolygons = 1;
    f.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&f.polygonlist[0]);
    f.polygonlist[0].numberofvertices = 3;
    f.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k)
      f.polygonlist[0].vertexlist[k] = local(boundary[i][static_cast<std::size_t>(k)]);
  }

  // TetGen is run in a child process: the Debian build keeps its assert()s, which abort the
  // process on some bad inputs, and it prints to stdout. The child sends back the error code,
  // the Steiner points and the tetrahedra through a pipe; a child that dies is a MeshingError.
  int fds[2];
  if (::pipe(fds) != 0)
    throw MeshingError(cell, 0,
                       "cell " + std::to_string(cell) + ": cannot create a pipe for TetGen");
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw MeshingError(cell, 0,
                       "cell " + std::to_string(cell) + ": cannot start TetGen (fork failed)");
  }
  if (pid == 0) {
    ::close(fds[0]);
    const int devnull = ::open("/dev/null", O_WRONLY);
    if (devnull >= 0) {
      ::dup2(devnull, 1);
      ::dup2(devnull, 2);
    }
    std::vector<double> msg;  // code, #steiner, #tets, steiner xyz..., tets...
    // p: a piecewise linear complex; Y: no Steiner points on the boundary; Q: quiet; z: 0-based.
    char switches[] = "pYQz";
    try {
      // d: detect self-intersections first (TetGen's -p can crash on them); the intersecting
      // faces come back as trifaces.
      {
        tetgenio check;
        char detect[] = "dQz";
        ::tetrahedralize(detect, &in, &check);
        if (check.numberoftrifaces > 0) throw 3;
      }
      ::tetrahedralize(switches, &in, &out);
      const int ns = std::max(0, out.numberofpoints - in.numberofpoints);
      const int nt = out.numberofcorners >= 4 ? out.numberoftetrahedra : 0;
      msg = {0.0, static_cast<double>(ns), static_cast<double>(nt)};
      for (int i = in.numberofpoints; i < out.numberofpoints; ++i)
        for (int k = 0; k < 3; ++k) msg.push_back(out.pointlist[3 * i + k]);
      for (int t = 0; t < nt; ++t)
        for (int k = 0; k < 4; ++k) msg.push_back(out.tetrahedronlist[t * out.numberofcorners + k]);
    } catch (int code) {
      msg = {static_cast<double>(code), 0.0, 0.0};
    } catch (...) {
      msg = {1.0, 0.0, 0.0};
    }
    const char* data = reinterpret_cast<const char*>(msg.data());
    std::size_t left = msg.size() * sizeof(double);
    while (left > 0) {
      const ssize_t n = ::write(fds[1], data, left);
      if (n <= 0) break;
      data += n;
      left -= static_cast<std::size_t>(n);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n > 0) {
      bytes.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const std::string what = "cell " + std::to_string(cell) + " cannot be tetrahedralized: ";
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.size() < 3 * sizeof(double))
    throw MeshingError(
        cell, 2,
        what + "TetGen " +
            (WIFSIGNALED(status) ? "crashed (signal " + std::to_string(WTERMSIG(status)) +
                                       "); the cell is probably degenerate"
                                 : std::string("gave no answer")));
  std::vector<double> msg(bytes.size() / sizeof(double));
  std::memcpy(msg.data(), bytes.data(), msg.size() * sizeof(double));
  const int code = static_cast<int>(msg[0]);
  if (code != 0) throw MeshingError(cell, code, what + tetgen_reason(code));
  const auto ns = static_cast<std::size_t>(msg[1]);
  const auto nt = static_cast<std::size_t>(msg[2]);
  if (msg.size() != 3 + 3 * ns + 4 * nt)
    throw MeshingError(cell, 2, what + "truncated answer from TetGen");
  if (nt == 0) throw MeshingError(cell, 0, what + "TetGen gave no tetrahedra");

  TetgenCellResult result;
  // With -Y the input points keep their indices; the points after them are interior.
  const double* q = msg.data() + 3;
  for (std::size_t i = 0; i < ns; ++i, q += 3)
    result.steiner.push_back(centre + basis * Eigen::Vector3d(q[0], q[1], q[2]));
  const std::size_t limit = vertices.size() + ns;
  for (std::size_t t = 0; t < nt; ++t, q += 4) {
    std::array<std::uint32_t, 4> tet{};
    for (std::size_t k = 0; k < 4; ++k) {
      if (!(q[k] >= 0.0) || q[k] >= static_cast<double>(limit))
        throw MeshingError(cell, 2, what + "TetGen returned an invalid vertex index");
      tet[k] = static_cast<std::uint32_t>(q[k]);
    }
    result.tets.push_back(tet);
  }
  return result;
}

TetMesh tetrahedralize(const Complex& complex, const TetOptions& options, TetStats* stats) {
  return tetrahedralize_cells(complex, options, tetgen_cell, stats);
}

}  // namespace cw4d
