#!/usr/bin/python3
"""Checks that every "MODEL §N[.M]" citation in the repository resolves in docs/model.md.

Usage: check_model_refs.py [REPO]   (default: the repository this script lives in)

A citation is "MODEL §3.3" (or "MODEL.md §3.3"), followed by any further
numbers listed with it ("MODEL §4, §6.6", "MODEL §5 and §6"); a range
("MODEL §1–§3") cites every section in it. The search covers
src/, include/, apps/, tests/, bench/, docs/ and scenes/ (docs/model.md itself
excepted). A number resolves when docs/model.md has a Markdown heading whose
first "§" token is that number, e.g. "## §3.3 Friction" (headings inside fenced
code blocks do not count). Prints every unresolved citation as
"file:line: MODEL §x.y not found in docs/model.md" and a one-line count; exits
1 if any citation is unresolved (or docs/model.md is missing), 0 otherwise.
Standard library only.
"""

import os
import re
import sys

SEARCHED_DIRS = ("src", "include", "apps", "tests", "bench", "docs", "scenes")
MODEL_DOC = os.path.join("docs", "model.md")
SKIPPED_DIRS = {".git", "node_modules", "build", "__pycache__"}

NUMBER = r"\d+(?:\.\d+)*"
# "MODEL §1", "MODEL.md §3.2", then more numbers listed with it: ", §6.6",
# " and §6", " & §2", "/§3", or a range "–§3" / "-§3" / " to §3".
SEPARATOR = r"(?:,|and|&|/|–|—|-|to)"
CITATION = re.compile(
    r"\bMODEL(?:\.md)?\s+§(" + NUMBER + r")((?:\s*" + SEPARATOR + r"\s*§" + NUMBER + r")*)"
)
FOLLOWING = re.compile(r"\s*(" + SEPARATOR + r")\s*§(" + NUMBER + r")")
SECTION = re.compile(r"§(" + NUMBER + r")")
RANGE_SEPARATORS = {"–", "—", "-", "to"}
HEADING = re.compile(r"^ {0,3}#{1,6}\s+(.*)$")
FENCE = re.compile(r"^ {0,3}(```|~~~)")


def heading_numbers(path):
    """The § numbers that headings of the Markdown file at `path` carry."""
    numbers = set()
    in_fence = False
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            if FENCE.match(line):
                in_fence = not in_fence
                continue
            if in_fence:
                continue
            m = HEADING.match(line)
            if not m:
                continue
            first = SECTION.search(m.group(1))
            if first:
                numbers.add(first.group(1))
    return numbers


def text_files(root):
    """Files under the searched folders, in a stable order, as (relative path, text)."""
    for top in SEARCHED_DIRS:
        base = os.path.join(root, top)
        if not os.path.isdir(base):
            continue
        for folder, dirs, files in os.walk(base):
            dirs[:] = sorted(d for d in dirs if d not in SKIPPED_DIRS and not d.startswith("."))
            for name in sorted(files):
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, root)
                if os.path.normpath(rel) == os.path.normpath(MODEL_DOC):
                    continue
                try:
                    with open(path, "rb") as f:
                        data = f.read()
                except OSError:
                    continue
                if b"\0" in data:  # binary (an image, an object file)
                    continue
                yield rel.replace(os.sep, "/"), data.decode("utf-8", errors="replace")


def expand_range(first, last):
    """The sections from `first` to `last` ("1", "3" -> 1, 2, 3; "3.1", "3.4" ->
    3.1 .. 3.4); just the two ends when they are not siblings in order."""
    a, b = first.split("."), last.split(".")
    if len(a) == len(b) and a[:-1] == b[:-1] and int(a[-1]) <= int(b[-1]) <= int(a[-1]) + 50:
        prefix = ".".join(a[:-1])
        return [(prefix + "." if prefix else "") + str(k) for k in range(int(a[-1]), int(b[-1]) + 1)]
    return [first, last]


def citations(text):
    """(line number, section number) for every citation in `text`."""
    for number, line in enumerate(text.splitlines(), start=1):
        if "MODEL" not in line:
            continue
        for m in CITATION.finditer(line):
            previous = m.group(1)
            cited = [previous]
            for extra in FOLLOWING.finditer(m.group(2)):
                separator, section = extra.group(1), extra.group(2)
                if separator in RANGE_SEPARATORS:
                    cited.extend(expand_range(previous, section)[1:])
                else:
                    cited.append(section)
                previous = section
            for section in cited:
                yield number, section


def main(argv):
    if len(argv) > 2:
        print("usage: check_model_refs.py [REPO]", file=sys.stderr)
        return 2
    default_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    root = os.path.abspath(argv[1]) if len(argv) == 2 else default_root
    if not os.path.isdir(root):
        print(f"check_model_refs: {root} is not a folder", file=sys.stderr)
        return 2

    doc = os.path.join(root, MODEL_DOC)
    sections = heading_numbers(doc) if os.path.isfile(doc) else set()
    if not os.path.isfile(doc):
        print(f"check_model_refs: {MODEL_DOC} not found in {root}")

    total = 0
    files = set()
    cited = set()
    unresolved = 0
    for rel, text in text_files(root):
        for line, number in citations(text):
            total += 1
            files.add(rel)
            cited.add(number)
            if number not in sections:
                unresolved += 1
                print(f"{rel}:{line}: MODEL §{number} not found in {MODEL_DOC}")

    if unresolved:
        print(
            f"check_model_refs: {unresolved} of {total} MODEL § citations "
            f"in {len(files)} files do not resolve in {MODEL_DOC}"
        )
        return 1
    print(
        f"check_model_refs: all {total} MODEL § citations in {len(files)} files "
        f"({len(cited)} distinct sections) resolve in {MODEL_DOC}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
