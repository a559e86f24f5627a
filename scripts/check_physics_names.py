#!/usr/bin/python3
"""Checks that no physics branches on an object's kind name (issue 36).

Usage: check_physics_names.py [REPO]   (default: the repository this script lives in)

An object's kind ("rope", "virtual", "box", ...) names the generator that made
it; how contacts treat the object is its ContactRole (include/robophi/model.h),
set by that generator or builder. Only the readers that choose a generator by
the name a user wrote (src/scene/, src/build/) may compare a kind with a string.
Every other source under src/, include/ and python/src/ is searched for a
comparison of a `kind` with a string literal ('kind == "rope"', 'kind != "virtual"');
each is printed as "file:line: text" and the script exits 1 if there is any,
0 otherwise. Standard library only.
"""

import os
import re
import sys

from source_files import sources

# Readers that choose a generator (or an XML element) by its written name.
READER_DIRS = ("src/scene/", "src/build/")
COMPARISON = re.compile(r"""\bkind\s*[!=]=\s*"|"\s*[!=]=\s*\w*\.?kind\b""")


def main() -> int:
    repo = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    found = []
    for rel, path in sources(repo):
        if rel.startswith(READER_DIRS):
            continue
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                code = line.split("//", 1)[0]
                if COMPARISON.search(code):
                    found.append(f"{rel}:{number}: {line.strip()}")
    for line in found:
        print(line)
    print(f"check_physics_names: {len(found)} comparison(s) of a kind with a name outside the readers")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
