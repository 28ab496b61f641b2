// Where outputs go and what errors echo: the one rule for every output path (single files,
// sweep layers, render frames), groups that appear whole or not at all, the page of cw4d view,
// file names that are not UTF-8, and error lines that stay short whatever the user typed.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/text.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "view_page.hpp"

namespace {

namespace fs = std::filesystem;
using cw4d::test::read_text;
using cw4d::test::Result;

struct TempDir : cw4d::test::TempDir {
  TempDir() : cw4d::test::TempDir("cw4d_test_outputs") {}
};

Result run(const TempDir& dir, const std::vector<std::string>& args) {
  return cw4d::test::run_program(dir, CW4D_EXE, args);
}

void check_one_error_line(const Result& r) {
  INFO("stderr: " << r.err.substr(0, 400));
  CHECK(r.err.rfind("cw4d: error: ", 0) == 0);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
}

// The names in `folder` that start with "." (staging folders, temporaries).
std::vector<std::string> hidden_entries(const fs::path& folder) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(folder))
    if (e.path().filename().string().front() == '.') out.push_back(e.path().filename().string());
  return out;
}

// A FIFO opened for reading without waiting for a writer; what a writer puts in is read back by
// drain() (the outputs of these tests fit the pipe's buffer, so the writer never blocks).
struct FifoReader {
  int fd = -1;
  explicit FifoReader(const fs::path& p) { fd = ::open(p.c_str(), O_RDONLY | O_NONBLOCK); }
  ~FifoReader() {
    if (fd >= 0) ::close(fd);
  }
  std::string drain() const {
    std::string out;
    char buf[4096];
    ssize_t n;
    while ((n = ::read(fd, buf, sizeof buf)) > 0) out.append(buf, static_cast<std::size_t>(n));
    return out;
  }
};

// One output of a group: a sweep layer or a render frame, run so that `name` is one member.
struct Group {
  std::string label;
  std::vector<std::string> args;  // writes first, name and last
  std::string first, name, last;  // three members, `name` in the middle
  std::string magic;              // how each member's content starts
};

std::vector<Group> groups() {
  return {
      {"a sweep layer",
       {"sweep", "tesseract", "--normal", "0,0,0,1", "--from", "-0.5", "--to", "0.5", "--layers",
        "3", "--format", "4off", "-o", "out"},
       "out/layer_000.4off",
       "out/layer_001.4off",
       "out/layer_002.4off",
       "OFF"},
      {"a render frame",
       {"render", "tesseract", "--mode", "frames", "--normal", "0,0,0,1", "--layers", "3", "--size",
        "8x6", "--samples", "1", "-o", "out/f.png"},
       "out/f_0000.png",
       "out/f_0001.png",
       "out/f_0002.png",
       "\x89PNG"},
  };
}

}  // namespace

TEST_CASE("every output path follows one rule: only regular files are replaced", "[outputs][cli]") {
  for (const Group& g : groups()) {
    DYNAMIC_SECTION(g.label << ": a symbolic link to a regular file is followed and kept") {
      TempDir dir;
      fs::create_directories(dir / "out");
      dir.write("real.txt", "old");
      fs::create_symlink(dir / "real.txt", dir / g.name);
      const Result r = run(dir, g.args);
      INFO(r.err);
      REQUIRE(r.code == 0);
      CHECK(fs::is_symlink(dir / g.name));
      CHECK(read_text(dir / "real.txt").rfind(g.magic, 0) == 0);
      CHECK(read_text(dir / g.first).rfind(g.magic, 0) == 0);
      CHECK(hidden_entries(dir / "out").empty());
      CHECK(hidden_entries(dir.path()).empty());
    }
    DYNAMIC_SECTION(g.label << ": a FIFO is written into, not replaced") {
      TempDir dir;
      fs::create_directories(dir / "out");
      REQUIRE(::mkfifo((dir / g.name).c_str(), 0600) == 0);
      const FifoReader reader(dir / g.name);
      REQUIRE(reader.fd >= 0);
      const Result r = run(dir, g.args);
      INFO(r.err);
      REQUIRE(r.code == 0);
      CHECK(fs::is_fifo(dir / g.name));
      CHECK(reader.drain().rfind(g.magic, 0) == 0);
      CHECK(hidden_entries(dir / "out").empty());
    }
    DYNAMIC_SECTION(g.label << ": a symbolic link to /dev/null is written through and kept") {
      TempDir dir;
      fs::create_directories(dir / "out");
      fs::create_symlink("/dev/null", dir / g.name);
      const Result r = run(dir, g.args);
      INFO(r.err);
      REQUIRE(r.code == 0);
      CHECK(fs::is_symlink(dir / g.name));
      CHECK(fs::read_symlink(dir / g.name) == "/dev/null");
      CHECK(fs::is_character_file("/dev/null"));
    }
    struct Refused {
      std::string what;
      std::function<void(const fs::path&)> make;
      std::string needle;
      std::function<bool(const fs::path&)> still;
    };
    const std::vector<Refused> refused = {
        {"a directory", [](const fs::path& p) { fs::create_directory(p); }, "it is a directory",
         [](const fs::path& p) { return fs::is_directory(fs::symlink_status(p)); }},
        {"a FIFO nobody reads", [](const fs::path& p) { ::mkfifo(p.c_str(), 0600); },
         "no process is reading it", [](const fs::path& p) { return fs::is_fifo(p); }},
        {"a symbolic link to nothing",
         [](const fs::path& p) { fs::create_symlink("nowhere/at/all", p); },
         "symbolic link to a missing file", [](const fs::path& p) { return fs::is_symlink(p); }},
    };
    for (const Refused& k : refused) {
      DYNAMIC_SECTION(g.label << ": " << k.what << " is refused and nothing moves") {
        TempDir dir;
        fs::create_directories(dir / "out");
        dir.write(g.first, "old first");
        dir.write(g.last, "old last");
        k.make(dir / g.name);
        const Result r = run(dir, g.args);
        CHECK(r.code == 4);
        check_one_error_line(r);
        CHECK(r.err.find(k.needle) != std::string::npos);
        CHECK(k.still(dir / g.name));
        // The group is all or nothing: the members around it keep their old contents.
        CHECK(read_text(dir / g.first) == "old first");
        CHECK(read_text(dir / g.last) == "old last");
        CHECK(hidden_entries(dir / "out").empty());
      }
    }
  }
  SECTION("single outputs: the same rule") {
    TempDir dir;
    dir.write("real.4off", "old");
    fs::create_symlink(dir / "real.4off", dir / "link.4off");
    const std::vector<std::string> slice = {"slice",    "tesseract", "--normal", "0,0,0,1",
                                            "--offset", "0",         "-o"};
    auto args = slice;
    args.push_back("link.4off");
    REQUIRE(run(dir, args).code == 0);
    CHECK(fs::is_symlink(dir / "link.4off"));
    CHECK(read_text(dir / "real.4off").find("OFF") != std::string::npos);
    fs::create_symlink("missing/file.4off", dir / "dangling.4off");
    args = slice;
    args.push_back("dangling.4off");
    const Result r = run(dir, args);
    CHECK(r.code == 4);
    CHECK(r.err.find("symbolic link to a missing file") != std::string::npos);
    CHECK(fs::is_symlink(dir / "dangling.4off"));
  }
}

TEST_CASE("render --mode frames: a failed run leaves nothing new", "[outputs][cli]") {
  TempDir dir;
  // An old set of three frames; the new run's second frame cannot be written (a directory is
  // in its place). The old frames stay as they were and no staging folder is left.
  for (const std::string name : {"f_0000.png", "f_0002.png"}) dir.write(name, "old");
  fs::create_directory(dir / "f_0001.png");
  const Result r = run(dir, {"render", "tesseract", "--mode", "frames", "--normal", "0,0,0,1",
                             "--layers", "3", "--size", "8x6", "--samples", "1", "-o", "f.png"});
  CHECK(r.code == 4);
  check_one_error_line(r);
  CHECK(read_text(dir / "f_0000.png") == "old");
  CHECK(read_text(dir / "f_0002.png") == "old");
  CHECK(hidden_entries(dir.path()).empty());
  SECTION("and a good run replaces the whole set") {
    fs::remove(dir / "f_0001.png");
    const Result ok = run(dir, {"render", "tesseract", "--mode", "frames", "--normal", "0,0,0,1",
                                "--layers", "3", "--size", "8x6", "--samples", "1", "-o", "f.png"});
    REQUIRE(ok.code == 0);
    for (const std::string name : {"f_0000.png", "f_0001.png", "f_0002.png"})
      CHECK(read_text(dir / name).rfind("\x89PNG", 0) == 0);
    CHECK(hidden_entries(dir.path()).empty());
  }
}

TEST_CASE("a staging folder is removed when SIGTERM or SIGINT ends the process",
          "[outputs][signals]") {
  for (const int sig : {SIGTERM, SIGINT}) {
    DYNAMIC_SECTION("signal " << sig) {
      TempDir dir;
      const pid_t child = ::fork();
      REQUIRE(child >= 0);
      if (child == 0) {
        ::signal(SIGTERM, SIG_DFL);  // (the test framework catches them)
        ::signal(SIGINT, SIG_DFL);
        cw4d::StagedFiles staged(dir.path().string(), "f");
        cw4d::write_file_atomically(staged.staged("f_0000.png"), "frame 0");
        cw4d::write_file_atomically(staged.staged("f_0001.png"), "frame 1");
        ::raise(sig);
        ::_exit(0);  // not reached
      }
      int status = 0;
      REQUIRE(::waitpid(child, &status, 0) == child);
      CHECK(WIFSIGNALED(status));
      CHECK(dir.entries() == 0);
    }
  }
}

TEST_CASE("cw4d view: a hostile name cannot break the page", "[outputs][cli][view]") {
  TempDir dir;
  // A name that would open a comment and a script inside the page's script element, close it,
  // and carry the line terminators of old JavaScript, an ampersand and a byte that is not UTF-8.
  const std::string name = "a<!--<script>\"'&\xE2\x80\xA8\xE2\x80\xA9<\\script>\xFF.off";
  cw4d::write_off_file((dir / name).string(), cw4d::load_model("tesseract"));
  dir.write("page.html",
            "<!doctype html><html><body><p>x</p><script type=\"module\">\nstart(null, "
            "/*cw4d:config*/{});\n</script></body></html>\n");
  const Result r = run(dir, {"view", name, "--normal", "0,0,0,1", "--offset", "0.25", "--template",
                             "page.html", "-o", "out.html"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string page = read_text(dir / "out.html");
  const std::size_t open = page.find("<script type=\"module\">");
  const std::size_t close = page.find("</script");
  REQUIRE(open != std::string::npos);
  const std::string script = page.substr(open + 22, close - open - 22);
  CHECK(script.find("<!--") == std::string::npos);
  CHECK(script.find("<script") == std::string::npos);
  CHECK(page.find("</script", close + 1) == std::string::npos);  // the template's one only
  // An independent reader: Python's HTML parser finds the script, its JSON parser the name.
  dir.write("check.py",
            "import html.parser, json, sys\n"
            "class P(html.parser.HTMLParser):\n"
            "  scripts = []\n"
            "  def handle_starttag(self, tag, a):\n"
            "    self.inside = tag == 'script'\n"
            "  def handle_data(self, d):\n"
            "    if getattr(self, 'inside', False): self.scripts.append(d)\n"
            "  def handle_endtag(self, tag):\n"
            "    self.inside = False\n"
            "p = P()\n"
            "p.feed(open('out.html', encoding='utf-8').read())\n"
            "assert len(p.scripts) == 1, p.scripts\n"
            "s = p.scripts[0].strip()\n"
            "assert s.startswith('start(null, ') and s.endswith(');'), s[:80]\n"
            "config = json.loads(s[len('start(null, '):-2])\n"
            "expected = bytes.fromhex(sys.argv[1]).decode('utf-8', 'replace')\n"
            "assert config['name'] == expected + ' identity', ascii(config['name'])\n"
            "assert config['n'] == '0,0,0,1' and config['d'] == '0.25', config\n"
            "assert config['off'].startswith('4OFF')\n"
            "print('ok')\n");
  std::string hex;
  for (unsigned char c : name) {
    char b[3];
    std::snprintf(b, sizeof b, "%02x", c);
    hex += b;
  }
  const Result py = cw4d::test::run_program(dir, "/usr/bin/python3", {"check.py", hex});
  INFO(py.err);
  CHECK(py.code == 0);
  CHECK(py.out == "ok\n");
}

TEST_CASE("cw4d view: the page's size is bounded before it is built", "[outputs][view]") {
  for (const std::string spec : {"tesseract", "120-cell", "duoprism:7,9", "24-cell"}) {
    INFO(spec);
    const cw4d::Complex model = cw4d::load_model(spec);
    const std::string templ = "<script>start(/*cw4d:config*/{});</script>";
    cw4d::cli::ViewPageOptions o;
    o.name = spec + " <&>\xE2\x80\xA8";
    o.normal = "0,0,0,1";
    o.offset = "-0.125";
    const std::size_t bound = cw4d::cli::view_page_size_bound(templ, model, o);
    const std::string page = cw4d::cli::view_page(templ, model, o);
    CHECK(page.size() <= bound);
    CHECK(bound < 2 * page.size() + 1024);  // an estimate, not a wild guess
    o.max_bytes = page.size() / 2;
    CHECK_THROWS_AS(cw4d::cli::view_page(templ, model, o), cw4d::InputError);
  }
  SECTION("JSON for a script element") {
    using cw4d::cli::script_json_string;
    CHECK(script_json_string("</script><!--") == "\"\\u003c/script\\u003e\\u003c!--\"");
    CHECK(script_json_string("\xE2\x80\xA8\xE2\x80\xA9") == "\"\\u2028\\u2029\"");
    CHECK(script_json_string("\xC3\xA9\xFF\xC0\xAF") == "\"\xC3\xA9\\ufffd\\ufffd\\ufffd\"");
    CHECK(nlohmann::json::parse(script_json_string(std::string("a\0b\"\\\n", 6))) ==
          std::string("a\0b\"\\\n", 6));
  }
}

TEST_CASE("cw4d view refuses non-finite offsets and templates that are not files",
          "[outputs][cli][view]") {
  TempDir dir;
  dir.write("page.html", "<script>start(/*cw4d:config*/{});</script>");
  for (const std::string offset : {"nan", "inf", "-inf"}) {
    INFO(offset);
    const Result r = run(dir, {"view", "tesseract", "--normal", "0,0,0,1", "--offset", offset,
                               "--template", "page.html", "-o", "out.html"});
    CHECK(r.code == 1);
    check_one_error_line(r);
    CHECK(r.err.find("--offset must be a finite number") != std::string::npos);
    CHECK_FALSE(dir.exists("out.html"));
  }
  REQUIRE(::mkfifo((dir / "fifo.html").c_str(), 0600) == 0);
  const Result r = run(dir, {"view", "tesseract", "--normal", "0,0,0,1", "--template", "fifo.html",
                             "-o", "out.html"});
  CHECK(r.code == 1);
  check_one_error_line(r);
  CHECK(r.err.find("not a regular file") != std::string::npos);
  CHECK(r.err.find("missing") == std::string::npos);
}

TEST_CASE("file names that are not UTF-8 give valid JSON and glTF", "[outputs][cli][utf8]") {
  TempDir dir;
  const std::string name = "t\xFF\xFEx.off";
  cw4d::write_off_file((dir / name).string(), cw4d::load_model("tesseract"));
  const std::string shown = "t\xEF\xBF\xBD\xEF\xBF\xBDx.off";  // each stray byte as U+FFFD
  SECTION("info --json") {
    const Result r = run(dir, {"info", name, "--json"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j.at("model") == shown);
  }
  SECTION("a glTF section") {
    const Result r =
        run(dir, {"slice", name, "--normal", "0,0,0,1", "--offset", "0", "-o", "s.gltf"});
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto j = nlohmann::json::parse(read_text(dir / "s.gltf"));
    bool named = false;
    for (const auto& node : j.at("nodes")) named = named || node.value("name", "") == shown;
    CHECK(named);
    const Result glb =
        run(dir, {"slice", name, "--normal", "0,0,0,1", "--offset", "0", "-o", "s.glb"});
    CHECK(glb.code == 0);
  }
  SECTION("view") {
    dir.write("page.html", "<script>start(/*cw4d:config*/{});</script>");
    const Result r = run(
        dir, {"view", name, "--normal", "0,0,0,1", "--template", "page.html", "-o", "out.html"});
    INFO(r.err);
    CHECK(r.code == 0);
  }
}

TEST_CASE("error lines echo at most about 100 bytes of what the user typed",
          "[outputs][cli][messages]") {
  TempDir dir;
  SECTION("the helper") {
    CHECK(cw4d::quote_user_text("slice") == "'slice'");
    const std::string cut = cw4d::quote_user_text(std::string(6'000'000, 'x'));
    CHECK(cut == "'" + std::string(100, 'x') + "...' (6000000 bytes)");
    // A cut never splits a character: "é" is two bytes, the 100th byte is in the middle of one.
    std::string accents = "a";
    for (int i = 0; i < 100; ++i) accents += "\xC3\xA9";
    const std::string quoted = cw4d::quote_user_text(accents);
    CHECK(cw4d::to_valid_utf8(quoted) == quoted);
    CHECK(quoted.find("...' (201 bytes)") != std::string::npos);
    CHECK(cw4d::quote_user_text("two\nlines") == "'two lines'");
  }
  SECTION("a long spec on the command line") {
    const Result r = run(dir, {"info", std::string(100'000, 'q')});
    CHECK(r.code == 1);
    check_one_error_line(r);
    CHECK(r.err.size() < 1000);
    CHECK(r.err.find("(100000 bytes)") != std::string::npos);
  }
  SECTION("a 6 MB spec in a scene") {
    dir.write("big.json", "{\"objects\": [{\"model\": \"" + std::string(6'000'000, 'q') + "\"}]}");
    const Result r =
        run(dir, {"slice", "--scene", "big.json", "--normal", "0,0,0,1", "-o", "a.obj"});
    CHECK(r.code != 0);
    check_one_error_line(r);
    CHECK(r.err.size() < 1000);
  }
  SECTION("long option values") {
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"slice", "tesseract", "--normal", std::string(50'000, '7') + "x",
                                   "-o", "a.obj"},
          std::vector<std::string>{"slice", "tesseract", "--normal", "0,0,0,1", "--rotate",
                                   "xw:" + std::string(50'000, '1') + "y", "-o", "a.obj"},
          std::vector<std::string>{"slice", "tesseract", "--normal", "0,0,0,1", "-o",
                                   std::string(50'000, 'o') + ".xyz"}}) {
      const Result r = run(dir, args);
      CHECK(r.code == 1);
      check_one_error_line(r);
      CHECK(r.err.size() < 1000);
    }
  }
}
