"""The Markdown of README.md and docs/ says what it means: a line of inline maths that starts
with "+ " or "- " is read by Markdown as a new list item, which cuts the equation in two and
shows its TeX source on the page; and no TeX command has lost its backslash to a string escape
when the page was written by a program (\rho, \nu, \ne become a line break, \text a tab)."""
import os
import re

from test_readme import ROOT, documents

SINGLE_DOLLAR = re.compile(r"(?<![\\$])\$(?!\$)")
LIST_MARKER = re.compile(r"\s*[-+*] ")
CONTROL = re.compile(r"[\t\r\f\v\a\b]")
# What is left of \rho, \rangle, \rightarrow, \nu, \ne, \nabla, \neq at the start of a line of maths.
LOST_ESCAPE = re.compile(r"(ho|angle|ightarrow|abla)\b|ho_|(u|eq)[ _=^)}$]|e [a-z]")


def lines_opening_a_list_inside_maths(path, opens=LIST_MARKER.match):
    found, in_maths, in_fence = [], False, False
    with open(os.path.join(ROOT, path)) as f:
        for number, line in enumerate(f.read().split("\n"), 1):
            if line.startswith("```"):
                in_fence = not in_fence
            if in_fence or line.strip() == "$$":
                continue
            if in_maths and opens(line):
                found.append(f"{path}:{number}: {line.strip()[:60]}")
            if not line.strip():
                in_maths = False  # a paragraph ends any inline maths
            elif len(SINGLE_DOLLAR.findall(line)) % 2:
                in_maths = not in_maths
    return found


def test_no_inline_equation_is_cut_by_a_list_marker():
    found = [hit for path in documents() for hit in lines_opening_a_list_inside_maths(path)]
    assert not found, "move the + or - to the end of the line before:\n" + "\n".join(found)


def test_no_tex_command_lost_its_backslash():
    found = [hit for path in documents() for hit in lines_opening_a_list_inside_maths(path, LOST_ESCAPE.match)]
    with_controls = [f"{path}:{number}" for path in documents()
                     for number, line in enumerate(open(os.path.join(ROOT, path), newline="").read().split("\n"), 1)
                     if CONTROL.search(line)]
    assert not found + with_controls, "a backslash went missing:\n" + "\n".join(found + with_controls)
