"""Doxygen input filter: in comment lines, <name> is an average such as <kT>, not HTML.

Doxygen would take it for an (unsupported) HTML tag and drop it; escaped as \\<name\\> it
prints as written.  Code lines pass unchanged, so templates such as std::vector<double> are
still parsed as C++.
"""
import re
import sys

COMMENT_LINE = re.compile(r"^\s*(/\*\*|\*|///)")
ANGLED_NAME = re.compile(r"<([A-Za-z][A-Za-z0-9_]*)>")

with open(sys.argv[1], encoding="utf-8") as source:
    for line in source:
        if COMMENT_LINE.match(line):
            line = ANGLED_NAME.sub(r"\\<\1\\>", line)
        sys.stdout.write(line)
