#!/usr/bin/python3
"""Checks that no function in src/collision/ is longer than 80 lines (issue 36).

Usage: check_function_length.py [REPO] [--limit N] [--folder src/collision]

A function is a brace block opened at namespace or class level after a header
with a parenthesis (a signature); its length counts its lines from the one
with its opening brace to the one with its closing brace. Lambdas and blocks
inside a function are part of it. Comments, string and character literals are
skipped. Prints every function over the limit as "file:line: N lines: header"
and exits 1 if there is any, 0 otherwise. Standard library only.
"""

import argparse
import os
import re
import sys


def code_lines(text):
    """The text with comments and literals blanked, split into lines."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out).split("\n")


def long_functions(path, limit):
    lines = code_lines(open(path, encoding="utf-8").read())
    stack = []  # (is_function, first line)
    header = ""
    found = []
    for number, line in enumerate(lines):
        for ch in line:
            if ch == "{":
                in_function = any(f for f, _ in stack)
                h = header.strip()
                typeish = re.search(r"\b(namespace|struct|class|enum|union)\b[^()]*$", h) or h.endswith("=")
                stack.append((not in_function and "(" in h and not typeish, number))
                header = ""
            elif ch == "}":
                if stack:
                    is_function, first = stack.pop()
                    if is_function and number - first + 1 > limit:
                        found.append((first + 1, number - first + 1))
                header = ""
            elif ch == ";":
                header = ""
            else:
                header += ch
        header += " "
    return found


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("repo", nargs="?", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser.add_argument("--limit", type=int, default=80)
    parser.add_argument("--folder", default="src/collision")
    args = parser.parse_args()
    folder = os.path.join(args.repo, args.folder)
    count = 0
    for name in sorted(os.listdir(folder)):
        if not name.endswith((".cpp", ".h", ".inl")):
            continue
        path = os.path.join(folder, name)
        raw = open(path, encoding="utf-8").read().split("\n")
        for line, length in long_functions(path, args.limit):
            print(f"{args.folder}/{name}:{line}: {length} lines: {raw[line - 1].strip()[:80]}")
            count += 1
    print(f"check_function_length: {count} function(s) in {args.folder} longer than {args.limit} lines")
    return 1 if count else 0


if __name__ == "__main__":
    sys.exit(main())
