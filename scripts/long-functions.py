#!/usr/bin/env python3
"""Lists the functions of the libraries and the program longer than 80 lines and fails when there
is one: CI runs it (.ci/run). Declarative tables (parameter catalogues) are allowed by name.
A function is found by its definition line at the start of a line (a return type or a class
qualifier, a name and '(') and measured to its matching closing brace."""
import re
import subprocess
import sys
from pathlib import Path

LIMIT = 80
TABLES = {"physiology_catalog"}  # one catalogue line per key: a table, not logic
root = Path(__file__).resolve().parent.parent
files = subprocess.run(["git", "ls-files", "*.cpp"], cwd=root, capture_output=True, text=True,
                       check=True).stdout.split()
definition = re.compile(r"^(?:[A-Za-z_][\w:<>,\s*&]*?\s)?[*&]?([A-Za-z_~][\w:~]*)\(")
files = [f for f in files if not f.startswith(("tests/", "fuzz/", "bench/"))]
long_ones = []
for f in files:
    lines = (root / f).read_text().split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        m = definition.match(line)
        if m and not line.startswith(("return", "if", "for", "while", "#", "//")) \
                and not line.rstrip().endswith(";"):
            j = i
            while j < len(lines) and "{" not in lines[j] and not lines[j].rstrip().endswith(";"):
                j += 1
            if j < len(lines) and "{" in lines[j]:
                depth, k = 0, j
                while k < len(lines):
                    depth += lines[k].count("{") - lines[k].count("}")
                    if depth <= 0:
                        break
                    k += 1
                n = k - i + 1
                if n > LIMIT and m.group(1) not in TABLES:
                    long_ones.append((n, m.group(1), f"{f}:{i + 1}"))
                i = k
        i += 1
for n, name, where in sorted(long_ones, reverse=True):
    print(f"{n:4d} lines: {name} ({where})")
if long_ones:
    print(f"long-functions: {len(long_ones)} functions over {LIMIT} lines; split them")
    sys.exit(1)
print(f"long-functions: no function over {LIMIT} lines in {len(files)} files")
