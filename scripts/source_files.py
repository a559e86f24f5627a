"""The C++ sources the repository checks read (check_physics_names.py,
check_laws_once.py): files ending .cpp, .h, .hpp or .inl under src/, include/
and python/src/, in a fixed order, build and cache folders skipped. Standard
library only."""

import os

SEARCHED_DIRS = ("src", "include", "python/src")


def sources(repo):
    """Yields (path relative to repo with '/', path) for each source."""
    for top in SEARCHED_DIRS:
        for folder, dirs, files in os.walk(os.path.join(repo, top)):
            dirs[:] = sorted(d for d in dirs if d not in {"build", "__pycache__"})
            for name in sorted(files):
                if name.endswith((".cpp", ".h", ".hpp", ".inl")):
                    path = os.path.join(folder, name)
                    yield os.path.relpath(path, repo).replace(os.sep, "/"), path
