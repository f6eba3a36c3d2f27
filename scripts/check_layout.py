#!/usr/bin/env python3
"""The layout rules anyone can check: no platform code finds out which integrator
it was given by casting, no function in platforms/ is longer than 70 lines, the
pair formulas (the weights wR = 1 - r/rc and wD, and the noise amplitude sqrt(2 gamma kT))
are written only in PairFormulas.h, which the host and the GPU kernels both compile, and
nothing that a GPU build links (platforms/core, platforms/common) reads the Reference
platform's data.

    /usr/bin/python3 scripts/check_layout.py        # exit status 1 and a list if broken

A function is a brace block at namespace or class level whose header ends in ')' (plus
qualifiers); its length counts the lines from its header to its closing brace.
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
MAX_LINES = 70
CAST = re.compile(r"dynamic_cast<const .*Integrator")
FORMULAS = "PairFormulas.h"
# A weight or noise amplitude written out again: 1 - r/rc, wR * wR, sqrt(2 gamma kT).
FORMULA_COPY = re.compile(r"\b1\s*-\s*r\s*/|\bwR\s*\*\s*wR\b|sqrt\(\s*2\s*\*\s*gamma")
REFERENCE_DATA = re.compile(r'#include\s+"Reference|ReferencePlatform::PlatformData')
DEVICE_LINKED = ("core", "common")


def strip(text):
    """The source without comments and string literals (they may hold braces)."""
    text = re.sub(r"//[^\n]*|/\*.*?\*/", lambda m: re.sub(r"[^\n]", " ", m.group()), text, flags=re.S)
    return re.sub(r'"(\\.|[^"\\\n])*"', '""', text)


def long_functions(path):
    text = strip(path.read_text())
    depth, stack, found = 0, [], []
    for match in re.finditer(r"[{}]", text):
        if match.group() == "{":
            header = text[:match.start()].rstrip()
            is_function = re.search(r"\)\s*(const|override|noexcept|final|\s)*$", header) is not None
            line = text.count("\n", 0, match.start()) + 1
            start = line - (header[header.rfind(";") + 1:].strip().count("\n") if is_function else 0)
            stack.append((is_function and not any(f for f, _ in stack), start))
            depth += 1
        elif stack:
            is_function, start = stack.pop()
            end = text.count("\n", 0, match.start()) + 1
            if is_function and end - start + 1 > MAX_LINES:
                found.append((start, end - start + 1))
    return found


def main():
    problems = []
    for path in sorted((ROOT / "platforms").rglob("*")):
        if path.suffix not in (".cpp", ".h", ".cc"):
            continue
        rel = path.relative_to(ROOT)
        code = strip(path.read_text()).splitlines()
        for n, line in enumerate(path.read_text().splitlines(), 1):
            if CAST.search(line):
                problems.append(f"{rel}:{n}: casts an integrator: {line.strip()}")
            if path.name != FORMULAS and FORMULA_COPY.search(code[n - 1]):
                problems.append(f"{rel}:{n}: writes a pair formula of {FORMULAS} again: {line.strip()}")
            if rel.parts[1] in DEVICE_LINKED and REFERENCE_DATA.search(line):
                problems.append(f"{rel}:{n}: reads the Reference platform's data, which a GPU build does not have: {line.strip()}")
        for start, length in long_functions(path):
            problems.append(f"{rel}:{start}: a function of {length} lines (limit {MAX_LINES})")
    print("\n".join(problems) if problems else
          f"layout: no integrator casts, no function over 70 lines, no pair formula outside {FORMULAS} in platforms/, "
          "no Reference platform data in what a GPU build links")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
