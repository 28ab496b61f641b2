"""`cw4d check` on real files: the Miratope polytopes shipped in tests/data (all pass), the same
files edited to carry the quirks of hand-shared files (pass, with one warning per file whose
counts disagree; refused under --strict), and two Miratope files that are not valid complexes
(fail at validation, exit 7). The f-vectors are checked against the files' own headers, the
round trip against an independent reading of the text the model writes."""

import json
import os
import re

import pytest

from conftest import REPO

DATA = REPO / "tests" / "data"
MIRATOPE = DATA / "miratope"
QUIRKS = DATA / "off-quirks"
REJECTED = DATA / "off-rejected"


def header_counts(path):
    """V F E C ... from the file's header, read here without cw4d."""
    words = []
    for line in path.read_text(encoding="utf-8-sig").splitlines():
        words += line.split("#")[0].split()
        if len(words) > 1:
            break
    dim = 3 if words[0] == "OFF" else int(words[0][:-3])
    counts = words[1:] if len(words) > 1 else []
    if not counts:
        raise AssertionError(path)
    return [int(x) for x in counts[:dim]]


def run_check(cli, tmp_path, *args):
    out = tmp_path / "report.json"
    done = cli("check", "-q", "--json", out, *args, check=False)
    return done, json.loads(out.read_text()) if out.exists() else None


def test_the_miratope_files_all_check_clean(cli, tmp_path):
    done, report = run_check(cli, tmp_path, MIRATOPE)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr
    files = sorted(p for p in MIRATOPE.rglob("*") if p.suffix.lower() in (".off", ".4off"))
    assert report["files"] == len(files) == report["passed"] and report["failed"] == 0
    assert sorted(r["file"] for r in report["reports"]) == sorted(map(str, files))
    kinds = {}
    for r in report["reports"]:
        assert r["valid"] and r["stage"] == "ok" and r["problem"] is None, r
        assert r["warning"] is None
        path = MIRATOPE / os.path.relpath(r["file"], MIRATOPE)
        h = header_counts(path)
        # Header V F E C..., cw4d's f-vector is vertices, edges, faces, cells...
        assert r["fvector"][0] == h[0] and r["fvector"][2] == h[1], r["file"]
        if len(h) > 3:
            assert r["fvector"][3:len(h)] == h[3:], r["file"]
        kinds[os.path.basename(r["file"])] = r["kind"]
    # Every one of the ten regular star polychora is star, the six convex ones convex.
    regular = {os.path.basename(p): p for p in (MIRATOPE / "regular").glob("*.off")}
    convex = {"Pentachoron.off", "Tesseract.off", "Hexadecachoron.off", "Icositetrachoron.off",
              "Hecatonicosachoron.off", "Hexacosichoron.off"}
    assert len(regular) == 16
    for name in regular:
        assert kinds[name] == ("convex" if name in convex else "star"), name
    assert kinds["Small stellated dodecahedron.off"] == "star"
    assert all(kinds[p.name] == "convex" for p in (MIRATOPE / "crf").glob("*.off"))
    # The table on stdout has one row per file and the summary line.
    assert done.stdout.count("\nok ") == len(files)
    assert re.search(rf"^{len(files)} files: {len(files)} passed, 0 failed; .* files/s$",
                     done.stdout, re.M)


def test_the_quirks_read_with_one_warning_each(cli, tmp_path):
    done, report = run_check(cli, tmp_path, QUIRKS)
    assert done.returncode == 0, done.stdout + done.stderr
    by_name = {os.path.basename(r["file"]): r for r in report["reports"]}
    assert len(by_name) == 4 and all(r["stage"] == "ok" for r in by_name.values())
    warned = {n for n, r in by_name.items() if r["warning"]}
    assert warned == {"Tesseract, counts disagree.off",
                      "Grand stellated 120-cell, counts disagree.off"}
    assert by_name["Tesseract, counts disagree.off"]["fvector"] == [16, 32, 24, 8]
    assert by_name["Grand stellated 120-cell, counts disagree.off"]["fvector"] == \
        [120, 720, 720, 120]
    assert by_name["Grand stellated 120-cell, counts disagree.off"]["kind"] == "star"
    assert by_name["Pentachoron, colours, CRLF and BOM.4OFF"]["fvector"] == [5, 10, 10, 5]
    assert by_name["Cube atop octahedron, comments and tabs.off"]["fvector"] == \
        [14, 48, 62, 28]
    # One warning line per such file on stderr.
    assert done.stderr.count("cw4d: warning: ") == 2
    assert "disagree with the body" in done.stderr


def test_strict_refuses_counts_that_disagree(cli, tmp_path):
    for args in (("check", "--strict"), ("--strict", "check")):
        out = tmp_path / "strict.json"
        done = cli(*args, "-q", "--json", out, QUIRKS, check=False)
        assert done.returncode == 7, done.stderr
        report = json.loads(out.read_text())
        failed = {os.path.basename(r["file"]): r for r in report["reports"] if not r["passed"]}
        assert set(failed) == {"Tesseract, counts disagree.off",
                               "Grand stellated 120-cell, counts disagree.off"}
        for r in failed.values():
            assert r["stage"] == "read" and "strict" in r["problem"]
            assert "\n" not in r["problem"]
    # Other commands take the global --strict too: one error line, exit 2.
    bad = QUIRKS / "Tesseract, counts disagree.off"
    done = cli("--strict", "info", bad, check=False)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and "disagree with the body" in done.stderr
    done = cli("info", bad, "--json", check=False)
    assert done.returncode == 0 and json.loads(done.stdout)["fvector"] == [16, 32, 24, 8]
    assert done.stderr.count("cw4d: warning: ") == 1


def test_invalid_files_fail_at_validation(cli, tmp_path):
    done, report = run_check(cli, tmp_path, REJECTED)
    assert done.returncode == 7
    assert report["failed"] == 2 and report["passed"] == 0
    for r in report["reports"]:
        assert r["stage"] == "validate" and not r["valid"] and r["problem"]
    assert "2 of 2 files failed the check (2 at validate)" in done.stderr


def test_paths_that_hold_nothing(cli, tmp_path):
    assert cli("check", tmp_path / "missing", check=False).returncode == 2
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "notes.txt").write_text("4OFF\n")
    (empty / "folder.off").mkdir()  # a folder named like a file is not a file
    os.mkfifo(empty / "pipe.off")   # nor is a FIFO: skipped, never opened (no hang)
    done = cli("check", empty, check=False)
    assert done.returncode == 2 and "no .off, .4off, .g4tf or .g4b file" in done.stderr


def test_hostile_files_are_reported_not_fatal(cli, tmp_path):
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "empty.off").write_text("")
    (bad / "binary.4off").write_bytes(bytes(range(256)) * 4)
    (bad / "huge counts.off").write_text("4OFF\n4000000000 4000000000 0 4000000000\n0 0 0 0\n")
    (bad / "self loop.off").write_text("4OFF\n5 1 0 1\n" + "0 0 0 0\n" * 5 + "3 0 0 0\n2 0 0\n")
    good = MIRATOPE / "regular" / "Tesseract.off"
    (bad / "good.OFF").write_text(good.read_text())
    done, report = run_check(cli, tmp_path, bad)
    assert done.returncode == 7
    by_name = {os.path.basename(r["file"]): r for r in report["reports"]}
    assert by_name["good.OFF"]["passed"]
    for name in ("empty.off", "binary.4off", "huge counts.off", "self loop.off"):
        assert by_name[name]["stage"] == "read", by_name[name]


def test_threads_do_not_change_the_report(cli, tmp_path):
    one = tmp_path / "one.json"
    many = tmp_path / "many.json"
    cli("check", "-q", "-j", "1", "--json", one, MIRATOPE / "crf", QUIRKS)
    cli("check", "-q", "-j", "4", "--json", many, MIRATOPE / "crf", QUIRKS)
    strip = lambda rep: [{k: v for k, v in r.items() if k != "seconds"}
                         for r in json.loads(rep.read_text())["reports"]]
    assert strip(one) == strip(many)
