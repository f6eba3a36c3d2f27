"""Every tracked text file speaks of the project alone: no planning labels (a numbered stop or
issue, a "definition" of being done), no absolute paths of the machine a file was written on,
and no citation of a design page or paper that the repository does not hold.  Theory lives in
docs/theory/, the scenes in docs/guide/, and papers are cited by authors and year
(docs/theory/references.md).

Runs on the files `git ls-files` lists, from the checkout this file is in; skipped outside a
git checkout (an installed or unpacked copy)."""
import functools
import os
import re
import subprocess

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))

# (name, pattern, what it means).  This file is left out of the scan; its examples below are
# split into adjacent literals so that its own source holds none of what the rules catch.
RULES = [
    ("numbered stop", re.compile(r"\bstop\s+\d+\b(?!\s*(?:steps?|times?|particles?|ps|fs|nm|%))", re.I),
     "a planning step's number; say what the code does"),
    ("numbered issue", re.compile(r"\bissues?\s+#?\d+", re.I),
     "an issue number of a tracker the repository does not have; say what is checked"),
    ("being-done label", re.compile(r"\bdefinition\s+of\s+done\b", re.I),
     "state the requirement itself (\"X must hold within 1 %\")"),
    ("absolute machine path", re.compile(r"(?<![\w.:/~$-])/(?:work|root|home)/"),
     "a path on the machine a file was written on; use a path relative to the repository"),
    ("paper by number", re.compile(r"\bpapers?\s+0\d\d\b", re.I),
     "cite the paper by authors and year (docs/theory/references.md)"),
]

# Citations of files by name: each must name a file the repository holds, relative to the
# repository root or to the citing file's folder (a link between docs pages).
CITED_FILES = re.compile(r"[\w./-]*\b(?:algorithms|scenes)\.md\b")


def repository_root():
    try:
        result = subprocess.run(["git", "-C", HERE, "rev-parse", "--show-toplevel"],
                                capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.SubprocessError):
        return None
    return result.stdout.strip() if result.returncode == 0 and result.stdout.strip() else None


@functools.lru_cache(maxsize=None)
def tracked_text_files():
    """(root, {path relative to the root: its lines}) for every tracked file that is text (no
    NUL byte, valid UTF-8) and present in the working tree, but this one; None outside a git
    checkout."""
    root = repository_root()
    if root is None:
        return None
    listed = subprocess.run(["git", "-C", root, "ls-files", "-z"], capture_output=True, check=True, timeout=60).stdout
    files = {}
    for name in listed.decode("utf-8", "surrogateescape").split("\0"):
        path = os.path.join(root, name)
        if not name or not os.path.isfile(path) or os.path.islink(path):
            continue
        with open(path, "rb") as f:
            data = f.read()
        if b"\0" in data:
            continue
        try:
            files[name] = data.decode("utf-8").splitlines()
        except UnicodeDecodeError:
            continue
    files.pop(os.path.relpath(os.path.abspath(__file__), root).replace(os.sep, "/"), None)
    return root, files


def scan():
    scanned = tracked_text_files()
    if scanned is None:
        pytest.skip("not in a git checkout: no list of tracked files")
    return scanned


def test_the_scan_sees_the_repository():
    root, files = scan()
    assert {"CMakeLists.txt", "README.md"} <= set(files) and any(name.startswith("docs/") for name in files)
    assert os.path.isfile(os.path.join(root, "CMakeLists.txt"))
    assert not any(name.endswith(".png") for name in files)  # binary files are left out


@pytest.mark.parametrize("name, pattern, meaning", RULES, ids=[rule[0] for rule in RULES])
def test_no_tracked_file_has(name, pattern, meaning):
    _, files = scan()
    hits = [f"{path}:{number}: {line.strip()[:160]}"
            for path, lines in sorted(files.items())
            for number, line in enumerate(lines, 1) if pattern.search(line)]
    assert not hits, f"{name} ({meaning}) in {len(hits)} lines:\n" + "\n".join(hits)


def test_cited_design_pages_are_in_the_repository():
    root, files = scan()
    hits = []
    for path, lines in sorted(files.items()):
        folder = os.path.dirname(path)
        for number, line in enumerate(lines, 1):
            for cited in CITED_FILES.findall(line):
                candidates = [os.path.normpath(cited.lstrip("/")), os.path.normpath(os.path.join(folder, cited))]
                if not any(candidate in files for candidate in candidates):
                    hits.append(f"{path}:{number}: {cited}: {line.strip()[:160]}")
    assert not hits, (f"{len(hits)} citations of files the repository does not hold (the theory is in "
                      "docs/theory/, the scenes in docs/guide/scenes.md):\n" + "\n".join(hits))


@pytest.mark.parametrize("text, rule", [
    ("after stop" " 46 the pair pass", "numbered stop"),
    ("as issue" " 16 asks", "numbered issue"),
    ("issue" " #3", "numbered issue"),
    ("the Definition of" " Done says", "being-done label"),
    ("see /wo" "rk/shared/openmm-8.5", "absolute machine path"),
    ('path = "/ho' 'me/me/x"', "absolute machine path"),
    ("(paper" " 000 Table III)", "paper by number"),
])
def test_the_rules_catch_what_they_are_for(text, rule):
    assert [name for name, pattern, _ in RULES if pattern.search(text)] == [rule]


@pytest.mark.parametrize("text", [
    "the sentinel stops the run at step 3",
    "stop" " 3 steps before the end",
    "https://example.org/ho" "me/page",
    "$HOME/wo" "rk/x",
    "examples/paper000.py writes docs/results/paper000/",
    "Nikunen et al. 2003, Table III",
])
def test_the_rules_leave_ordinary_text_alone(text):
    assert not [name for name, pattern, _ in RULES if pattern.search(text)]


def test_a_cited_page_resolves_from_the_root_or_the_citing_folder():
    cited = CITED_FILES.findall("see docs/guide/scenes.md, [scenes](scenes.md) and design/scenes.md")
    assert cited == ["docs/guide/scenes.md", "scenes.md", "design/scenes.md"]
    assert CITED_FILES.findall("algorithms.md section 8") == ["algorithms.md"]
