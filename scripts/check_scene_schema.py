#!/usr/bin/env python3
"""Checks scene files against docs/scene.schema.json with a real JSON Schema validator
(Debian's python3-jsonschema; scripts/install-deps.sh installs it).

Usage: check_scene_schema.py REPO [--reject FILE ...]

Checks the schema itself (Draft 2020-12 meta-schema), every shipped scene
(scenes/*.json), every scene in docs/*.md (```json blocks holding "objects" or
"robophi"), which must be valid, and every FILE after --reject, which must be
rejected, and that docs/scene-format.md names every key of the schema.
Scene files may hold // and /* */ comments (as robophi's loader
allows); they are removed before validation. Exits 1 naming every problem.
"""
import glob
import json
import os
import re
import sys

import jsonschema


def strip_comments(text):
    """The text without // and /* */ comments outside strings (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            out.append("\n" * text.count("\n", i, n if j < 0 else j))
            i = n if j < 0 else j + 2
        else:
            out.append(c)
            i += 1
    return "".join(out)


def docs_scenes(repo):
    """(label, scene) of every docs example that is a whole scene."""
    found = []
    for path in sorted(glob.glob(os.path.join(repo, "docs", "*.md"))):
        text = open(path, encoding="utf-8").read()
        for m in re.finditer(r"```json\n(.*?)```", text, re.S):
            line = text.count("\n", 0, m.start()) + 2
            try:
                value = json.loads(strip_comments(m.group(1)))
            except json.JSONDecodeError:
                continue  # a fragment (with "..."), not a scene
            if isinstance(value, dict) and "objects" in value:
                found.append((f"{os.path.relpath(path, repo)}:{line}", value))
    return found


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    repo = argv[1]
    reject = argv[argv.index("--reject") + 1:] if "--reject" in argv else []
    schema = json.load(open(os.path.join(repo, "docs", "scene.schema.json"), encoding="utf-8"))
    validator_class = jsonschema.validators.validator_for(schema)
    validator_class.check_schema(schema)
    validator = validator_class(schema)
    problems = []
    scenes = []
    for path in sorted(glob.glob(os.path.join(repo, "scenes", "*.json"))):
        text = open(path, encoding="utf-8").read()
        scenes.append((os.path.relpath(path, repo), json.loads(strip_comments(text))))
    scenes += docs_scenes(repo)
    for label, scene in scenes:
        for error in validator.iter_errors(scene):
            where = "/" + "/".join(str(p) for p in error.absolute_path)
            problems.append(f"{label}: {where}: {error.message}")
    for path in reject:
        scene = json.loads(strip_comments(open(path, encoding="utf-8").read()))
        if validator.is_valid(scene):
            problems.append(f"{path}: accepted by the schema, but it is a broken scene")
    # docs/scene-format.md names every key of the schema.
    doc = open(os.path.join(repo, "docs", "scene-format.md"), encoding="utf-8").read()
    keys = set()

    def collect(node):
        if isinstance(node, dict):
            if isinstance(node.get("properties"), dict):
                keys.update(node["properties"])
            for value in node.values():
                collect(value)
        elif isinstance(node, list):
            for value in node:
                collect(value)

    collect(schema)
    for key in sorted(keys):
        if f"`{key}`" not in doc and f'"{key}"' not in doc:
            problems.append(f"docs/scene-format.md: the schema's key '{key}' is not documented")
    for p in problems:
        print(p, file=sys.stderr)
    print(f"scene schema: {len(scenes)} scenes checked ({len(reject)} broken ones rejected), "
          f"{len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
