#!/usr/bin/env python3
"""README.md runs as written.

Every fenced block of README.md is either executed or checked; a block of any other kind fails
the test, so none is skipped silently:

  ```sh       every command runs (`readme_test.py commands`) in a scratch folder arranged like
              the repository root: a symlink to each top-level entry of the source, `build` ->
              the build directory under test. A command must exit 0, and each `-o PATH` it
              names must exist afterwards (a non-empty file, or a non-empty folder), under out/
              (so no command writes into the source). `info --json` must print JSON. A
              `python3 -m http.server -d DIR --bind 127.0.0.1 PORT` line is served on a free
              port instead of PORT for as long as one fetch of its page takes. With CW4D_WEB=0
              (./setup.sh builds no viewer) that line's shape is checked and `cw4d view`
              lines are reported as not run.
  ```console  the set-up commands, which cannot run inside the test suite
              (`readme_test.py setup`): exactly `./setup.sh` and `./setup.sh test`, and
              .ci/run must run `./setup.sh test`.
  ```cmake    with ```cpp: the C++ example (`readme_test.py cpp`): the cmake block is the
              CMakeLists.txt and the cpp block main.cpp of a project built against an installed
              cw4d (find_package); the program must exit 0 and write the OBJ its code names,
              which must parse (vertices, faces with valid indices).
  ```python   the Python example: run by python/tests/test_readme.py (pytest, with the module);
              here its block is only required to exist.

Also (`readme_test.py links`): every relative link and image of README.md and docs/*.md
resolves to a file (and an #anchor to a heading of it).

usage:
  readme_test.py commands --source DIR --build DIR
  readme_test.py links    --source DIR
  readme_test.py setup    --source DIR
  readme_test.py cpp      --source DIR --prefix DIR --work DIR [--cxx C] [--cxx-flags F]
                          [--linker-flags F] [--build-type T] [--launcher L]
"""

import argparse
import json
import os
import pathlib
import re
import shlex
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

KINDS = {"sh", "console", "cmake", "cpp", "python"}


class Failure(Exception):
    pass


def blocks(readme):
    """[(kind, first line number, [lines])] of every fenced block of the file."""
    found, kind, start, body = [], None, 0, []
    for number, line in enumerate(pathlib.Path(readme).read_text(encoding="utf-8").splitlines(), 1):
        fence = re.match(r"^\s*```+\s*(\S*)", line)
        if kind is None:
            if fence:
                kind, start, body = fence.group(1), number, []
        elif fence and not fence.group(1):
            found.append((kind, start, body))
            kind = None
        else:
            body.append(line)
    if kind is not None:
        raise Failure(f"README.md:{start}: the ```{kind} block is never closed")
    for kind, start, _ in found:
        if kind not in KINDS:
            raise Failure(f"README.md:{start}: a fenced block of kind '{kind or '(none)'}': "
                          f"this test runs or checks only {sorted(KINDS)}, so this one would "
                          "be skipped; give it one of those kinds")
    return found


def of_kind(found, kind):
    return [(start, body) for k, start, body in found if k == kind]


def commands_of(start, body):
    """The commands of a shell block: continuation lines joined, blank and comment lines
    dropped; [(line number, text)]."""
    out, pending, first = [], "", 0
    for offset, line in enumerate(body):
        if not pending:
            first = start + 1 + offset
        stripped = line.rstrip()
        if stripped.endswith("\\"):
            pending += stripped[:-1] + " "
            continue
        text = (pending + stripped).strip()
        pending = ""
        if text and not text.startswith("#"):
            out.append((first, text))
    if pending:
        raise Failure(f"README.md:{first}: a command ends with a continuation backslash")
    return out


def words(text):
    lexer = shlex.shlex(text, posix=True, punctuation_chars=False)
    lexer.whitespace_split = True
    lexer.commenters = "#"
    return list(lexer)


# --- commands -------------------------------------------------------------------------------------
def scratch_root(source, build, where):
    """A folder where the README's relative paths resolve as from the repository root."""
    for entry in source.iterdir():
        if entry.name in ("build", "out", ".git"):
            continue
        os.symlink(entry, where / entry.name)
    os.symlink(build, where / "build")
    # The web build is beside the source tree (./setup.sh: build-web/, or CW4D_WEB_DIR).
    web = os.environ.get("CW4D_WEB_DIR")
    if web and not (where / "build-web").exists():
        os.symlink(pathlib.Path(web).resolve(), where / "build-web")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def serve_once(line, text, root, fetch=True):
    argv = words(text)
    shape = ["python3", "-m", "http.server", "-d", None, "--bind", "127.0.0.1", None]
    if len(argv) != len(shape) or any(a != b for a, b in zip(argv, shape) if b is not None):
        raise Failure(f"README.md:{line}: a server line of another shape than "
                      f"'python3 -m http.server -d DIR --bind 127.0.0.1 PORT': {text}")
    site = root / argv[4]
    if not fetch:
        print(f"shape checked, not served (CW4D_WEB=0: no web build) README.md:{line}: {text}")
        return
    if not (site / "index.html").is_file():
        raise Failure(f"README.md:{line}: {argv[4]}/index.html does not exist (is the web "
                      "viewer built? CW4D_WEB=1 ./setup.sh builds it into build-web/)")
    port, documented = free_port(), argv[-1]
    argv[-1] = str(port)
    server = subprocess.Popen([sys.executable, *argv[1:]], cwd=root, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 20
        while True:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=5) as reply:
                    page = reply.read().decode("utf-8", "replace")
                    status = reply.status
                break
            except OSError:
                if time.monotonic() > deadline or server.poll() is not None:
                    raise Failure(f"README.md:{line}: the server did not answer: {text}")
                time.sleep(0.2)
        if status != 200 or "<html" not in page.lower():
            raise Failure(f"README.md:{line}: the served page is not the viewer (HTTP {status})")
        print(f"ok   README.md:{line}: served {argv[4]} on port {port} (README: {documented})")
    finally:
        server.terminate()
        server.wait(timeout=10)


def outputs_of(argv):
    out = []
    for i, arg in enumerate(argv):
        if arg in ("-o", "--output") and i + 1 < len(argv):
            out.append(argv[i + 1])
        elif arg.startswith("--output="):
            out.append(arg.split("=", 1)[1])
    return out


def run_commands(args):
    source, build = pathlib.Path(args.source).resolve(), pathlib.Path(args.build).resolve()
    found = blocks(source / "README.md")
    shell = of_kind(found, "sh")
    if not shell:
        raise Failure("README.md has no ```sh block")
    with tempfile.TemporaryDirectory(prefix="cw4d-readme-") as tmp:
        root = pathlib.Path(tmp)
        scratch_root(source, build, root)
        count = 0
        for start, body in shell:
            for line, text in commands_of(start, body):
                count += 1
                no_web = os.environ.get("CW4D_WEB") == "0"
                if text.startswith("python3 -m http.server"):
                    serve_once(line, text, root, fetch=not no_web)
                    continue
                argv = words(text)
                if no_web and len(argv) > 1 and argv[1] == "view":
                    print(f"not run (CW4D_WEB=0: no web build) README.md:{line}: {text}")
                    continue
                outputs = outputs_of(argv)
                for out in outputs:
                    if not out.startswith("out/"):
                        raise Failure(f"README.md:{line}: the output '{out}' is not under out/")
                began = time.monotonic()
                done = subprocess.run(["bash", "-c", text], cwd=root, capture_output=True,
                                      text=True, timeout=600)
                if done.returncode != 0:
                    raise Failure(f"README.md:{line}: exit {done.returncode}: {text}\n"
                                  f"stdout: {done.stdout.strip()[-2000:]}\n"
                                  f"stderr: {done.stderr.strip()[-2000:]}")
                for out in outputs:
                    path = root / out
                    if path.is_dir():
                        if not any(path.iterdir()):
                            raise Failure(f"README.md:{line}: the folder {out} is empty: {text}")
                    elif not path.is_file() or path.stat().st_size == 0:
                        raise Failure(f"README.md:{line}: no output {out}: {text}")
                if "--json" in argv:
                    try:
                        json.loads(done.stdout)
                    except ValueError as e:
                        raise Failure(f"README.md:{line}: --json printed no JSON ({e}): {text}")
                if not outputs and not done.stdout.strip():
                    raise Failure(f"README.md:{line}: printed nothing: {text}")
                print(f"ok   README.md:{line}: {text}  ({time.monotonic() - began:.1f} s)")
    print(f"{count} README commands ran")


# --- setup ----------------------------------------------------------------------------------------
def check_setup(args):
    source = pathlib.Path(args.source).resolve()
    found = blocks(source / "README.md")
    console = of_kind(found, "console")
    if len(console) != 1:
        raise Failure(f"README.md needs exactly one ```console block (the set-up commands), "
                      f"has {len(console)}")
    start, body = console[0]
    listed = [words(text) for _, text in commands_of(start, body)]
    if listed != [["./setup.sh"], ["./setup.sh", "test"]]:
        raise Failure(f"README.md:{start}: the ```console block must hold exactly "
                      f"'./setup.sh' and './setup.sh test', holds {listed}")
    ci = (source / ".ci" / "run").read_text(encoding="utf-8")
    if not re.search(r"^\s*(exec\s+)?\./setup\.sh\s+test\s*$", ci, re.M):
        raise Failure(".ci/run does not run './setup.sh test'")
    setup = source / "setup.sh"
    if not (setup.is_file() and os.access(setup, os.X_OK)):
        raise Failure("setup.sh is missing or not executable")
    if not of_kind(found, "python"):
        raise Failure("README.md has no ```python block (python/tests/test_readme.py runs it)")
    print("ok   the set-up block is ./setup.sh and ./setup.sh test; .ci/run runs ./setup.sh test")


# --- cpp ------------------------------------------------------------------------------------------
def parse_obj(path):
    vertices = faces = 0
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            if len(parts) < 4:
                raise Failure(f"{path}:{number}: a vertex needs three coordinates")
            [float(x) for x in parts[1:4]]
            vertices += 1
        elif parts[0] == "f":
            ids = [int(p.split("/")[0]) for p in parts[1:]]
            if len(ids) < 3 or any(i < 1 or i > vertices for i in ids):
                raise Failure(f"{path}:{number}: a face with bad vertex indices: {line}")
            faces += 1
    if vertices < 4 or faces < 4:
        raise Failure(f"{path}: {vertices} vertices and {faces} faces: not a closed section")
    return vertices, faces


def run_cpp(args):
    source = pathlib.Path(args.source).resolve()
    found = blocks(source / "README.md")
    cpp, cmake = of_kind(found, "cpp"), of_kind(found, "cmake")
    if len(cpp) != 1 or len(cmake) != 1:
        raise Failure(f"README.md needs one ```cpp and one ```cmake block, has {len(cpp)} and "
                      f"{len(cmake)}")
    code = "\n".join(cpp[0][1]) + "\n"
    written = re.findall(r'write_obj_file\(\s*"([^"]+)"', code)
    if not written:
        raise Failure(f"README.md:{cpp[0][0]}: the C++ example writes no OBJ (write_obj_file)")
    work = pathlib.Path(args.work).resolve()
    shutil.rmtree(work, ignore_errors=True)
    (work / "src").mkdir(parents=True)
    (work / "src" / "CMakeLists.txt").write_text("\n".join(cmake[0][1]) + "\n", encoding="utf-8")
    sources = re.findall(r"add_executable\(\s*(\S+)\s+([^)]+)\)", "\n".join(cmake[0][1]))
    if not sources:
        raise Failure(f"README.md:{cmake[0][0]}: the cmake block adds no executable")
    target, files = sources[0][0], sources[0][1].split()
    if len(files) != 1:
        raise Failure(f"README.md:{cmake[0][0]}: the example is one source file, got {files}")
    (work / "src" / files[0]).write_text(code, encoding="utf-8")
    configure = ["cmake", "-S", str(work / "src"), "-B", str(work / "build"), "-G", "Ninja",
                 f"-DCMAKE_PREFIX_PATH={args.prefix}"]
    for name, value in (("CMAKE_CXX_COMPILER", args.cxx), ("CMAKE_CXX_FLAGS", args.cxx_flags),
                        ("CMAKE_EXE_LINKER_FLAGS", args.linker_flags),
                        ("CMAKE_BUILD_TYPE", args.build_type),
                        ("CMAKE_CXX_COMPILER_LAUNCHER", args.launcher)):
        if value:
            configure.append(f"-D{name}={value}")
    for step in (configure, ["cmake", "--build", str(work / "build")]):
        done = subprocess.run(step, capture_output=True, text=True)
        if done.returncode != 0:
            raise Failure(f"README.md:{cpp[0][0]}: the C++ example does not build "
                          f"({' '.join(step[:2])}):\n{done.stdout[-4000:]}\n{done.stderr[-4000:]}")
    run_dir = work / "run"
    run_dir.mkdir()
    done = subprocess.run([str(work / "build" / target)], cwd=run_dir, capture_output=True,
                          text=True, timeout=300)
    if done.returncode != 0:
        raise Failure(f"README.md:{cpp[0][0]}: the C++ example exited {done.returncode}:\n"
                      f"{done.stdout}\n{done.stderr}")
    for name in written:
        path = run_dir / name
        if not path.is_file():
            raise Failure(f"README.md:{cpp[0][0]}: the C++ example did not write {name}")
        vertices, faces = parse_obj(path)
        print(f"ok   the C++ example wrote {name}: {vertices} vertices, {faces} faces")
    print(f"the C++ example printed: {done.stdout.strip()}")


# --- links ----------------------------------------------------------------------------------------
def slug(heading):
    """GitHub's anchor of a heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def anchors(path):
    text = path.read_text(encoding="utf-8")
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    return {slug(m.group(1)) for m in re.finditer(r"^#+\s+(.*)$", text, re.M)}


def check_links(args):
    """Every relative link and image of README.md and docs/*.md names a file of the source
    tree (and a heading of it, for #anchors)."""
    source = pathlib.Path(args.source).resolve()
    pages = [source / "README.md", *sorted((source / "docs").glob("*.md"))]
    bad, count = [], 0
    for page in pages:
        text = page.read_text(encoding="utf-8")
        text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
        for match in re.finditer(r"!?\[[^\]]*\]\(([^)\s]+)\)", text):
            target = match.group(1)
            if re.match(r"^[a-z]+:", target):
                continue
            count += 1
            name, _, anchor = target.partition("#")
            path = (page.parent / name).resolve() if name else page
            if not path.exists():
                bad.append(f"{page.relative_to(source)}: {target}: no such file")
            elif anchor and path.suffix == ".md" and anchor not in anchors(path):
                bad.append(f"{page.relative_to(source)}: {target}: no such heading")
    if bad:
        raise Failure("links that resolve to nothing:\n  " + "\n  ".join(bad))
    print(f"ok   {count} links and images of README.md and docs/*.md resolve")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("what", choices=["commands", "setup", "cpp", "links"])
    parser.add_argument("--source", required=True)
    parser.add_argument("--build")
    parser.add_argument("--prefix")
    parser.add_argument("--work")
    parser.add_argument("--cxx", default="")
    parser.add_argument("--cxx-flags", default="")
    parser.add_argument("--linker-flags", default="")
    parser.add_argument("--build-type", default="")
    parser.add_argument("--launcher", default="")
    args = parser.parse_args()
    try:
        if args.what == "commands":
            if not args.build:
                parser.error("commands needs --build")
            run_commands(args)
        elif args.what == "setup":
            check_setup(args)
        elif args.what == "links":
            check_links(args)
        else:
            if not args.prefix or not args.work:
                parser.error("cpp needs --prefix and --work")
            run_cpp(args)
    except Failure as failure:
        print(f"FAIL {failure}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
