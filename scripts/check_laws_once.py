#!/usr/bin/python3
"""Checks that the contact laws are written once (issue 36; STYLE 21).

Usage: check_laws_once.py [REPO]   (default: the repository this script lives in)

The contact law (MODEL §3.1), the friction laws (§3.3), the contacts'
stability rates and their sums (§3.7) and the material combination rule live
in one place each: src/collision/contact_law.inl (included for doubles by
contact_law.h and for AVX2 lanes by pair_lanes.cpp) and combineMaterials
(src/model/model.cpp). For each law the script counts, over every source
under src/, include/ and python/src/:
- definitions: a line that starts at column 0 (not a comment, not a
  declaration ending in ";") and names the function followed by "(";
- written-out copies of its arithmetic: the patterns below (a spring's load
  from a depth, a lane's product of a stiffness or a damping, a rate summed, a
  series combination, a geometric mean of friction coefficients).
It prints each finding as "file:line: text" and exits 1 unless every law is
defined exactly once and no copy is found outside its home. Standard library
only.
"""

import os
import re
import sys

from source_files import sources

LAW_HOME = "src/collision/contact_law.inl"
MATERIAL_HOME = "src/model/model.cpp"

# Law -> the file that must define it.
DEFINED_ONCE = {
    "normalLaw": LAW_HOME,
    "tangentialDamping": LAW_HOME,
    "stabilityRates": LAW_HOME,
    "anchorLoads": LAW_HOME,
    "heldFriction": LAW_HOME,
    "slidingCoefficient": LAW_HOME,
    "slidingFriction": LAW_HOME,
    "combineMaterials": MATERIAL_HOME,
}

# Arithmetic that would be a second copy of a law, with the file allowed to hold it.
COPIES = [
    (re.compile(r"tiffness\s*\*\s*\w*[dD]epth\b"), LAW_HOME, "a spring's load from a depth"),
    (re.compile(r"\bmul\([^)]*(tiffness|amping)"), LAW_HOME,
     "a lane's product of a stiffness or damping"),
    (re.compile(r"\b(rates?\.)?(stiffness|damping)\s*\+=\s*\w+\.(stiffness|damping)"), LAW_HOME,
     "a contact's rate summed"),
    (re.compile(r"\*\s*\w+\s*/\s*\(\s*\w+\s*\+\s*\w+\s*\)"), MATERIAL_HOME, "a series combination"),
    (re.compile(r"sqrt\(\s*\w+\.(static|kinetic)Friction\s*\*"), MATERIAL_HOME,
     "a geometric mean of friction coefficients"),
]


def main() -> int:
    repo = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    definitions = {name: [] for name in DEFINED_ONCE}
    copies = []
    for rel, path in sources(repo):
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                text = line.rstrip("\n")
                if text.lstrip().startswith("//"):
                    continue
                for name in DEFINED_ONCE:
                    if (text[:1].strip() and not text.rstrip().endswith(";")
                            and re.search(r"\b" + name + r"\(", text)):
                        definitions[name].append(f"{rel}:{number}: {text.strip()}")
                for pattern, home, what in COPIES:
                    if rel != home and pattern.search(text):
                        copies.append(f"{rel}:{number}: {what}: {text.strip()}")
    failures = 0
    for name, found in definitions.items():
        home = DEFINED_ONCE[name]
        if len(found) != 1 or not found[0].startswith(home + ":"):
            failures += 1
            print(f"{name}: expected one definition, in {home}; found {len(found)}")
            for where in found:
                print(f"  {where}")
    for where in copies:
        print(where)
    failures += len(copies)
    print(f"check_laws_once: {len(DEFINED_ONCE)} laws, {failures} problem(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
