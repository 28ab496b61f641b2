// cw4d check: import, validate, cut and round-trip every nOFF (or G4MF) file of a collection, on
// every core, with a report per file (a table on stdout, --json FILE).

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <new>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <sstream>
#include <thread>

#include "cli.hpp"
#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/g4mf.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/operators.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d::cli {

namespace {

namespace fs = std::filesystem;

struct CheckSettings {
  std::vector<std::string> paths;
  std::string json;
  unsigned threads = 0;
  std::uint64_t seed = 1;
  bool strict = false;
  bool quiet = false;
};

struct FileReport {
  std::string path;
  std::vector<std::size_t> fvector;
  bool valid = false;
  std::string kind = "-";    // convex, star, non-convex ("-" when not read or not valid)
  std::string stage = "ok";  // where the first problem was found: read, validate, section,
                             // round-trip; "ok" when none
  std::string problem;       // the first problem, one line
  std::string warning;       // what the reader read differently from the header
  double seconds = 0.0;
  bool passed() const { return stage == "ok"; }
};

bool has_off_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".off" || ext == ".4off" || is_g4mf_extension(ext);
}

// The files named, and the *.off / *.4off / *.g4tf / *.g4b files (any case) under the folders
// named, in a stable order; symbolic links to folders are not followed (no loops).
std::vector<std::string> collect_files(const std::vector<std::string>& paths) {
  std::vector<std::string> files;
  for (const std::string& p : paths) {
    std::error_code ec;
    const auto status = fs::status(p, ec);
    if (ec || !fs::exists(status)) throw ParseError(p, 0, "cannot check: no such file or folder");
    if (!fs::is_directory(status)) {
      files.push_back(p);
      continue;
    }
    std::vector<std::string> found;
    fs::recursive_directory_iterator it(p, fs::directory_options::skip_permission_denied, ec), end;
    if (ec) throw ParseError(p, 0, "cannot list the folder: " + ec.message());
    for (; it != end; it.increment(ec)) {
      if (ec) throw ParseError(p, 0, "cannot list the folder: " + ec.message());
      std::error_code fe;
      if (it->is_regular_file(fe) && has_off_extension(it->path()))
        found.push_back(it->path().string());
    }
    std::sort(found.begin(), found.end());
    files.insert(files.end(), found.begin(), found.end());
  }
  return files;
}

// Orthonormal basis (columns) of the span of the points' differences from their centroid,
// at most `rank` vectors (Gram-Schmidt on the longest remaining difference each time).
Eigen::MatrixXd span_basis(const Eigen::MatrixXd& pts, int rank, Eigen::VectorXd* centroid) {
  *centroid = pts.rowwise().mean();
  Eigen::MatrixXd d = pts.colwise() - *centroid;
  Eigen::MatrixXd basis(pts.rows(), 0);
  const double scale = d.colwise().norm().maxCoeff();
  for (int r = 0; r < rank && scale > 0; ++r) {
    Eigen::Index best = 0;
    const double len = d.colwise().norm().maxCoeff(&best);
    if (len <= 1e-9 * scale) break;
    const Eigen::VectorXd u = d.col(best) / len;
    basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
    basis.col(basis.cols() - 1) = u;
    d -= u * (u.transpose() * d);
  }
  return basis;
}

// A face polygon is convex when it turns one way at every corner and goes round once.
bool face_is_convex(const Complex& c, std::uint32_t f) {
  const auto cyc = c.face_cycle(f);
  Eigen::MatrixXd pts(c.ambient_dim(), static_cast<Eigen::Index>(cyc.size()));
  for (std::size_t i = 0; i < cyc.size(); ++i)
    pts.col(static_cast<Eigen::Index>(i)) = c.position(cyc[i]);
  Eigen::VectorXd centroid;
  const Eigen::MatrixXd basis = span_basis(pts, 2, &centroid);
  if (basis.cols() < 2) return true;  // degenerate: validate() reports it
  const Eigen::MatrixXd q = basis.transpose() * (pts.colwise() - centroid);
  const Eigen::Index n = q.cols();
  int positive = 0, negative = 0;
  double turned = 0.0;
  const double scale = q.colwise().norm().maxCoeff();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d a = q.col(i), b = q.col((i + 1) % n), e = q.col((i + 2) % n);
    const double cross = (b - a).x() * (e - b).y() - (b - a).y() * (e - b).x();
    if (cross > 1e-9 * scale * scale) ++positive;
    if (cross < -1e-9 * scale * scale) ++negative;
    turned += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  }
  return (positive == 0 || negative == 0) &&
         std::abs(std::abs(turned) - 2 * std::numbers::pi) < 1e-6;
}

// A 4D model's cell is convex when all its vertices lie on one side of each of its faces,
// within the cell's own hyperplane.
bool cell_is_convex(const Complex& c, std::uint32_t cell) {
  const auto verts = c.vertices_of(3, cell);
  Eigen::MatrixXd cp(c.ambient_dim(), static_cast<Eigen::Index>(verts.size()));
  for (std::size_t i = 0; i < verts.size(); ++i)
    cp.col(static_cast<Eigen::Index>(i)) = c.position(verts[i]);
  Eigen::VectorXd cc;
  const Eigen::MatrixXd cell_basis = span_basis(cp, 3, &cc);
  if (cell_basis.cols() < 3) return true;
  const double scale = (cp.colwise() - cc).colwise().norm().maxCoeff();
  for (const std::uint32_t f : c.boundary(3).ids(cell)) {
    const auto fv = c.vertices_of(2, f);
    Eigen::MatrixXd fp(c.ambient_dim(), static_cast<Eigen::Index>(fv.size()));
    for (std::size_t i = 0; i < fv.size(); ++i)
      fp.col(static_cast<Eigen::Index>(i)) = c.position(fv[i]);
    Eigen::VectorXd fc;
    const Eigen::MatrixXd fb = span_basis(fp, 2, &fc);
    if (fb.cols() < 2) continue;
    // The direction in the cell's 3-flat orthogonal to the face.
    Eigen::MatrixXd in_cell = cell_basis.transpose() * fb;  // 3 x 2
    Eigen::Vector3d m = Eigen::Vector3d(in_cell.col(0)).cross(Eigen::Vector3d(in_cell.col(1)));
    if (m.norm() < 1e-9) continue;
    const Eigen::VectorXd s = m.transpose() * (cell_basis.transpose() * (cp.colwise() - fc));
    if (s.maxCoeff() > 1e-7 * scale && s.minCoeff() < -1e-7 * scale) return false;
  }
  return true;
}

// star: self-intersecting. A 3D model is tested directly (self_intersects); a 4D one is star
// when a face or a cell is itself not convex, or a section at one of the check's planes
// self-intersects. non-convex: neither convex nor star.
std::string classify(const Complex& model, bool convex, bool section_self_intersects) {
  if (convex) return "convex";
  if (model.ambient_dim() == 3) return self_intersects(model) ? "star" : "non-convex";
  if (section_self_intersects) return "star";
  for (std::uint32_t f = 0; f < model.count(2); ++f)
    if (!face_is_convex(model, f)) return "star";
  if (model.ambient_dim() == 4)
    for (std::uint32_t c = 0; c < model.count(3); ++c)
      if (!cell_is_convex(model, c)) return "star";
  return "non-convex";
}

bool has_g4mf_extension(const std::string& path) {
  return is_g4mf_extension(lower_extension(path));
}

// The differences between a model and its nOFF text (or for a G4MF file its G4MF bytes) read
// back: "" when there is none.
std::string round_trip_problem(const Complex& a, bool g4mf) {
  Complex b;
  if (g4mf) {
    b = read_g4mf(g4mf_files(a, {}).main, "the written copy");
  } else {
    std::ostringstream out;
    write_off(out, a);
    std::istringstream in(out.str());
    b = read_off(in, "the written copy");
  }
  const int n = a.ambient_dim();
  if (b.ambient_dim() != n) return "the copy reads back in R^" + std::to_string(b.ambient_dim());
  for (int k = 0; k < n; ++k)
    if (a.count(k) != b.count(k))
      return "the copy has " + std::to_string(b.count(k)) + " " + rank_name(k, b.count(k)) +
             ", the model " + std::to_string(a.count(k));
  if (a.positions() != b.positions()) return "the copy's vertex coordinates differ";
  for (std::uint32_t f = 0; f < a.count(2); ++f)
    if (a.vertices_of(2, f) != b.vertices_of(2, f))
      return "face " + std::to_string(f) + " has other vertices in the copy";
  for (int k = 3; k < n; ++k)
    for (std::uint32_t i = 0; i < a.count(k); ++i) {
      auto x = a.boundary(k).ids(i), y = b.boundary(k).ids(i);
      std::vector<std::uint32_t> sx(x.begin(), x.end()), sy(y.begin(), y.end());
      std::sort(sx.begin(), sx.end());
      std::sort(sy.begin(), sy.end());
      if (sx != sy)
        return rank_name(k, 1) + " " + std::to_string(i) + " has other faces in the copy";
    }
  for (int k = 2; k < n; ++k) {
    const auto &ca = a.colors(k), &cb = b.colors(k);
    bool same = ca.size() == cb.size();
    for (std::size_t i = 0; same && i < ca.size(); ++i)
      same = ca[i].r == cb[i].r && ca[i].g == cb[i].g && ca[i].b == cb[i].b && ca[i].a == cb[i].a;
    if (!same) return "the colors of the " + rank_name(k, 2) + " differ in the copy";
  }
  return {};
}

// One seeded generic plane through the middle of the model's extent along its normal, and
// one degenerate plane through a vertex: both must cut without an error, the first must meet
// the model, and for a convex model its section must validate.
std::string section_problem(const Complex& model, bool convex, std::uint64_t seed,
                            bool* self_intersecting) {
  const int n = model.ambient_dim();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  Eigen::VectorXd normal(n);
  for (int i = 0; i < n; ++i) normal(i) = gauss(rng);
  normal.normalize();
  const Eigen::VectorXd along = normal.transpose() * model.positions();
  const double lo = along.minCoeff(), hi = along.maxCoeff();
  std::uniform_real_distribution<double> middle(0.4, 0.6);
  const double d = lo + middle(rng) * (hi - lo);
  const Section generic = section(model, Hyperplane::from(normal, d));
  if (generic.empty())
    return "the plane n=(" + join(std::vector<double>(normal.data(), normal.data() + n), brief) +
           "), d=" + brief(d) + " inside the model's extent misses it";
  *self_intersecting = generic.self_intersecting;
  if (convex) {
    const auto report = validate(generic.complex);
    if (!report.ok())
      return "the section at n=(" +
             join(std::vector<double>(normal.data(), normal.data() + n), brief) +
             "), d=" + brief(d) + " is not valid: " + report.summary(1);
  }
  std::uniform_int_distribution<std::size_t> pick(0, model.count(0) - 1);
  const std::uint32_t v = static_cast<std::uint32_t>(pick(rng));
  const Section through_vertex =
      section(model, Hyperplane::from(normal, normal.dot(model.position(v))));
  *self_intersecting = *self_intersecting || through_vertex.self_intersecting;
  return {};
}

FileReport check_file(const std::string& path, const CheckSettings& s) {
  FileReport r;
  r.path = path;
  const auto start = std::chrono::steady_clock::now();
  std::string warning;
  OffReadOptions options;
  options.strict = s.strict;
  options.warn = [&warning](const std::string& w) {
    if (warning.empty()) warning = w;
  };
  ScopedOffReadOptions scoped(options);
  auto stop = [&](const std::string& stage, const std::string& problem) {
    r.stage = stage;
    r.problem = one_line(problem);
  };
  try {
    Complex model;
    try {
      model = has_g4mf_extension(path) ? read_g4mf_file(path) : read_off_file(path);
    } catch (const Error& e) {
      stop("read", e.what());
    }
    r.warning = one_line(warning);
    if (r.passed()) {
      r.fvector = model.fvector();
      const ValidationReport report = validate(model);
      r.valid = report.ok();
      if (!r.valid) stop("validate", report.summary(1));
    }
    if (r.passed()) {
      const bool convex = is_convex(model);
      bool self_intersecting = false;
      try {
        const std::string p = section_problem(model, convex, s.seed, &self_intersecting);
        if (!p.empty()) stop("section", p);
      } catch (const Error& e) {
        stop("section", e.what());
      }
      r.kind = classify(model, convex, self_intersecting);
    }
    if (r.passed()) {
      try {
        const std::string p = round_trip_problem(model, has_g4mf_extension(path));
        if (!p.empty()) stop("round-trip", p);
      } catch (const Error& e) {
        stop("round-trip", e.what());
      }
    }
  } catch (const std::bad_alloc&) {
    stop("internal", "out of memory");
  } catch (const std::exception& e) {
    stop("internal", std::string("internal error: ") + e.what());
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::string fvector_text(const std::vector<std::size_t>& f) {
  std::string out;
  for (auto x : f) out += (out.empty() ? "" : " ") + std::to_string(x);
  return out.empty() ? "-" : out;
}

void run_check(const CheckSettings& s) {
  CheckSettings settings = s;
  settings.strict = s.strict || off_read_options().strict;  // also `cw4d --strict check`
  const std::vector<std::string> files = collect_files(s.paths);
  if (files.empty())
    throw ParseError(s.paths.front(), 0, "no .off, .4off, .g4tf or .g4b file to check");
  std::vector<FileReport> reports(files.size());
  const unsigned threads =
      std::max(1u, std::min<unsigned>(s.threads ? s.threads : std::thread::hardware_concurrency(),
                                      static_cast<unsigned>(files.size())));
  ProgressBar progress("check", "files", files.size(), !s.quiet);
  std::atomic<std::size_t> next{0}, done{0};
  const auto start = std::chrono::steady_clock::now();
  auto worker = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < files.size();) {
      reports[i] = check_file(files[i], settings);
      progress.step(done.fetch_add(1) + 1);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::size_t passed = 0;
  std::map<std::string, std::size_t> failed_at;
  for (const auto& r : reports) {
    if (r.passed())
      ++passed;
    else
      ++failed_at[r.stage];
    if (!r.warning.empty()) std::cerr << "cw4d: warning: " << bounded_message(r.warning) << '\n';
  }
  std::printf("%-10s %-10s %-24s %9s  %s\n", "status", "kind", "f-vector", "ms", "file");
  for (const auto& r : reports) {
    std::printf("%-10s %-10s %-24s %9.1f  %s\n", r.passed() ? "ok" : r.stage.c_str(),
                r.kind.c_str(), fvector_text(r.fvector).c_str(), r.seconds * 1e3, r.path.c_str());
    if (!r.passed()) std::printf("    %s\n", bounded_message(r.problem).c_str());
  }
  std::string failures;
  for (const auto& [stage, count] : failed_at)
    failures += (failures.empty() ? " (" : ", ") + std::to_string(count) + " at " + stage;
  if (!failures.empty()) failures += ")";
  std::printf("%zu files: %zu passed, %zu failed%s; %.1f s on %u threads, %.1f files/s\n",
              files.size(), passed, files.size() - passed, failures.c_str(), seconds, threads,
              seconds > 0 ? static_cast<double>(files.size()) / seconds : 0.0);
  std::fflush(stdout);

  if (!s.json.empty()) {
    nlohmann::ordered_json j;
    j["files"] = files.size();
    j["passed"] = passed;
    j["failed"] = files.size() - passed;
    j["seconds"] = seconds;
    j["threads"] = threads;
    j["seed"] = s.seed;
    j["strict"] = s.strict;
    auto& list = j["reports"] = nlohmann::ordered_json::array();
    for (const auto& r : reports) {
      nlohmann::ordered_json e;
      e["file"] = r.path;
      e["passed"] = r.passed();
      e["fvector"] = r.fvector;
      e["valid"] = r.valid;
      e["kind"] = r.kind;
      e["seconds"] = r.seconds;
      e["stage"] = r.stage;
      e["problem"] =
          r.problem.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(r.problem);
      e["warning"] =
          r.warning.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(r.warning);
      list.push_back(std::move(e));
    }
    prepare_output_directory(s.json);
    // Names of files are bytes: anything that is not UTF-8 is replaced, not refused.
    write_file_atomically(
        s.json, j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n");
  }
  if (passed != files.size())
    throw CheckFailed(std::to_string(files.size() - passed) + " of " +
                      std::to_string(files.size()) + " files failed the check" + failures);
}

}  // namespace

void add_check_command(CLI::App& app, Commands& commands) {
  auto s = std::make_shared<CheckSettings>();
  auto* cmd = app.add_subcommand(
      "check", "Import, validate, cut and round-trip every nOFF or G4MF file of a collection.");
  cmd->add_option("PATH", s->paths,
                  "Files, or folders searched for *.off, *.4off, *.g4tf and *.g4b (any case)")
      ->required();
  cmd->add_option("--json", s->json, "Also write the per-file report as JSON to FILE");
  cmd->add_option("-j,--threads", s->threads, "Worker threads (default: every core)")
      ->check(CLI::Range(1u, 1024u));
  cmd->add_option("--seed", s->seed, "Seed of the generic planes (default 1)");
  cmd->add_flag("--strict", s->strict, "Refuse files whose header counts disagree with their body");
  cmd->add_flag("-q,--quiet", s->quiet, "No progress bar");
  cmd->footer(
      "For each file: read it (header counts that disagree with the body are a warning, an\n"
      "error with --strict), validate it, classify it (convex; star: self-intersecting;\n"
      "non-convex: neither), cut it with a seeded generic plane through the middle of its\n"
      "extent (it must meet the model; for a convex model the section must validate) and with\n"
      "a plane through one of its vertices, then write it as nOFF (a G4MF file: as G4MF) and\n"
      "read that back (same counts, coordinates, faces, cells and colors). The first problem\n"
      "found is reported.\n"
      "Exit codes: 0 when every file passes, 7 when any fails, 2 when a PATH does not exist\n"
      "or holds no file; see 'cw4d --help'.");
  commands.push_back({cmd, [s] { run_check(*s); }});
}

}  // namespace cw4d::cli
