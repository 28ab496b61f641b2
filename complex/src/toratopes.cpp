#include "cw4d/complex/toratopes.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <string>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/operators.hpp"
#include "cw4d/complex/validate.hpp"

namespace cw4d {

namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

void check(const char* what, std::initializer_list<double> radii, int n) {
  for (double r : radii)
    if (!std::isfinite(r) || r <= 0.0)
      throw InputError(std::string(what) + ": radii must be positive and finite");
  if (n < 3 || n > max_toratope_resolution)
    throw InputError(std::string(what) + ": resolution must be 3.." +
                     std::to_string(max_toratope_resolution) + ", got " + std::to_string(n));
}

Complex checked(Complex c, const char* what) {
  const ValidationReport report = validate(c);
  if (!report.ok())
    throw TopologyError(report.issues.front().rank, {report.issues.front().id},
                        std::string(what) + ": result is not valid: " + report.summary());
  return c;
}

// A grid surface of rows x cols quads with vertex (i, j) at point(i, j); rows wrap around when
// `wrap_rows`, columns always wrap. Faces are the quads (i, j) (i+1, j) (i+1, j+1) (i, j+1).
ComplexSoup grid_soup(int rows, int cols, bool wrap_rows,
                      const std::function<Eigen::Vector3d(int, int)>& point) {
  const int vrows = wrap_rows ? rows : rows + 1;
  ComplexSoup soup;
  soup.ambient_dim = 3;
  soup.positions.resize(3, vrows * cols);
  auto vid = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % vrows) * cols + (j % cols));
  };
  for (int i = 0; i < vrows; ++i)
    for (int j = 0; j < cols; ++j) soup.positions.col(vid(i, j)) = point(i, j);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      soup.faces.push_back({vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)});
  return soup;
}

}  // namespace

Complex make_torus(double major, double minor, int n) {
  check("torus", {major, minor}, n);
  if (major <= minor) throw InputError("torus: needs R > r");
  // (i, j): sweep angle 2 pi i / n about z, tube angle 2 pi j / n.
  ComplexSoup soup = grid_soup(n, n, true, [&](int i, int j) {
    const double t = two_pi * i / n, p = two_pi * j / n;
    const double rho = major + minor * std::cos(p);
    return Eigen::Vector3d(rho * std::cos(t), rho * std::sin(t), minor * std::sin(p));
  });
  return checked(build_complex(soup), "torus");
}

Complex make_spheritorus(double major, double minor, int n) {
  check("spheritorus", {major, minor}, n);
  if (major <= minor) throw InputError("spheritorus: needs R > r");
  Complex ball = make_uv_sphere(minor, n);
  Eigen::MatrixXd p = ball.positions();
  p.row(0).array() += major;
  ball.set_positions(std::move(p));
  return checked(make_spin(ball, n), "spheritorus");
}

Complex make_torisphere(double major, double minor, int n) {
  check("torisphere", {major, minor}, n);
  if (major <= minor) throw InputError("torisphere: needs R > r");
  // Half of the torus about z, x >= 0 (sweep angle -pi/2 .. pi/2 in n/2 steps), closed by its
  // two tube cross-sections in the plane x = 0 (which the spin sweeps to nothing).
  const int half = std::max(2, n / 2);
  ComplexSoup soup = grid_soup(half, n, false, [&](int i, int j) {
    const double t = -std::numbers::pi / 2 + std::numbers::pi * i / half, p = two_pi * j / n;
    const double rho = major + minor * std::cos(p);
    const double x = (i == 0 || i == half) ? 0.0 : rho * std::cos(t);
    return Eigen::Vector3d(x, rho * std::sin(t), minor * std::sin(p));
  });
  for (int end : {0, half}) {
    std::vector<std::uint32_t> cap;
    for (int j = 0; j < n; ++j) cap.push_back(static_cast<std::uint32_t>(end * n + j));
    soup.faces.push_back(cap);
  }
  return checked(make_spin(build_complex(soup), n), "torisphere");
}

Complex make_ditorus(double r1, double r2, double minor, int n) {
  check("ditorus", {r1, r2, minor}, n);
  if (r2 <= minor || r1 <= r2 + minor) throw InputError("ditorus: needs R1 > R2 + r and R2 > r");
  Complex torus = make_torus(r2, minor, n);
  Eigen::MatrixXd p = torus.positions();
  p.row(0).array() += r1;
  torus.set_positions(std::move(p));
  return checked(make_spin(torus, n), "ditorus");
}

Complex make_tiger(double r1, double r2, double minor, int n) {
  check("tiger", {r1, r2, minor}, n);
  if (r1 <= minor || r2 <= minor) throw InputError("tiger: needs R1 > r and R2 > r");
  // The torus about the x axis (major R2), moved to x = R1: (x - R1)^2 + (|(y,z)| - R2)^2 <= r^2.
  ComplexSoup soup = grid_soup(n, n, true, [&](int i, int j) {
    const double t = two_pi * i / n, p = two_pi * j / n;
    const double rho = r2 + minor * std::cos(p);
    return Eigen::Vector3d(r1 + minor * std::sin(p), rho * std::cos(t), rho * std::sin(t));
  });
  return checked(make_spin(build_complex(soup), n), "tiger");
}

}  // namespace cw4d
