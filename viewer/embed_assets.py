#!/usr/bin/env python3
"""Builds the replay page template into a C++ header (viewer/CMakeLists.txt runs this).

The page is one HTML file that opens from disk with no server and no network, so
three.js and OrbitControls travel inside it: each becomes a data: URL in an import
map, and the module that imported "./three.core.min.js" imports "three/core"
instead. The viewer's own CSS and JS are inlined as they are. What is left for the
C++ writer (src/output/replay_html.cpp) is the run's series (binary, in <script>
elements) between kPageHead and kPageMiddle, and its data object between
kPageMiddle and kPageTail.
"""

import argparse
import base64
import pathlib
import sys

# GCC's -Woverlength-strings (on with -Wpedantic) flags literals past 65535 chars.
CHUNK_CHARS = 16000
SERIES_MARKER = "@RUN_SERIES@"
DATA_MARKER = "@RUN_DATA@"


def data_url(source: str) -> str:
    encoded = base64.b64encode(source.encode("utf-8")).decode("ascii")
    return "data:text/javascript;base64," + encoded


def c_literal(text: str) -> str:
    out = ['"']
    for byte in text.encode("utf-8"):
        ch = chr(byte)
        if ch == "\\":
            out.append("\\\\")
        elif ch == '"':
            out.append('\\"')
        elif ch == "\n":
            out.append("\\n")
        elif ch == "?":
            out.append("\\?")  # no trigraphs
        elif 0x20 <= byte < 0x7F:
            out.append(ch)
        else:
            out.append("\\%03o" % byte)  # octal: at most three digits, never runs on
    out.append('"')
    return "".join(out)


def chunks(text: str):
    return [text[i:i + CHUNK_CHARS] for i in range(0, len(text), CHUNK_CHARS)] or [""]


def emit_array(name: str, text: str) -> str:
    lines = [f"inline constexpr std::string_view {name}[] = {{"]
    # With its length given: GCC would count the characters at compile time, and
    # its constexpr operation limit is shared by the whole file.
    lines += [f"    std::string_view{{{c_literal(piece)}, {len(piece.encode('utf-8'))}}},"
              for piece in chunks(text)]
    lines.append("};")
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--three-dir", required=True, help="node_modules/three")
    parser.add_argument("--template", required=True)
    parser.add_argument("--js", required=True)
    parser.add_argument("--css", required=True)
    parser.add_argument("--live-js", required=True, help="the live view's module (viewer/live.js)")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()

    three = pathlib.Path(args.three_dir)
    core = (three / "build/three.core.min.js").read_text(encoding="utf-8")
    module = (three / "build/three.module.min.js").read_text(encoding="utf-8")
    orbit = (three / "examples/jsm/controls/OrbitControls.js").read_text(encoding="utf-8")
    # The live view's part of the page (docs/viewer.md "Live view"), loaded only
    # when the data object says "live".
    live = pathlib.Path(args.live_js).read_text(encoding="utf-8")
    version = __import__("json").loads((three / "package.json").read_text())["version"]

    # three.module.min.js imports its core by a relative path, which a data: URL
    # cannot resolve; name it through the import map instead.
    for quote in ('"', "'"):
        module = module.replace(f"from{quote}./three.core.min.js{quote}", f"from{quote}three/core{quote}")
        module = module.replace(f"from {quote}./three.core.min.js{quote}", f"from {quote}three/core{quote}")
    if "./three.core.min.js" in module:
        sys.exit("embed_assets.py: three.module.min.js imports ./three.core.min.js in an unknown form")

    # The loaders of the robots' meshes (docs/viewer.md "Robots as they look"); a
    # loader's relative import of another loader goes through the import map too.
    loaders = {}
    for name in ("STLLoader", "OBJLoader", "MTLLoader", "ColladaLoader", "TGALoader"):
        source = (three / f"examples/jsm/loaders/{name}.js").read_text(encoding="utf-8")
        for other in ("TGALoader",):
            for quote in ('"', "'"):
                source = source.replace(f"from {quote}../loaders/{other}.js{quote}",
                                        f"from {quote}three/addons/loaders/{other}.js{quote}")
        if "from '../" in source or 'from "../' in source:
            sys.exit(f"embed_assets.py: {name}.js imports a relative path this script does not map")
        loaders[name] = source

    import_map = ('{"imports":{'
                  f'"three/core":"{data_url(core)}",'
                  f'"three":"{data_url(module)}",'
                  f'"three/addons/controls/OrbitControls.js":"{data_url(orbit)}",'
                  f'"robophi/live.js":"{data_url(live)}"'
                  + "".join(f',"three/addons/loaders/{name}.js":"{data_url(source)}"'
                            for name, source in loaders.items()) +
                  '}}')

    page = pathlib.Path(args.template).read_text(encoding="utf-8")
    js = pathlib.Path(args.js).read_text(encoding="utf-8")
    css = pathlib.Path(args.css).read_text(encoding="utf-8")
    if "</script" in js.lower():
        sys.exit("embed_assets.py: replay.js must not contain '</script'")
    for marker, value in (("@THREE_IMPORT_MAP@", import_map), ("@REPLAY_CSS@", css),
                          ("@REPLAY_JS@", js), ("@THREE_VERSION@", version)):
        if marker not in page:
            sys.exit(f"embed_assets.py: {args.template} lacks {marker}")
        page = page.replace(marker, value)
    for marker in (SERIES_MARKER, DATA_MARKER):
        if page.count(marker) != 1:
            sys.exit(f"embed_assets.py: {args.template} must hold {marker} exactly once")
    head, rest = page.split(SERIES_MARKER)
    middle, tail = rest.split(DATA_MARKER)
    if middle.count("<") != 1 or not middle.strip().startswith("<script"):
        sys.exit(f"embed_assets.py: {args.template}: only the data element may stand between "
                 f"{SERIES_MARKER} and {DATA_MARKER}")

    header = "\n".join([
        "#pragma once",
        "// Generated by viewer/embed_assets.py from viewer/replay.html.in, replay.js,",
        f"// replay.css and three.js {version} (npm). Do not edit.",
        "#include <string_view>",
        "",
        "namespace robophi::replay_assets {",
        "",
        f'inline constexpr std::string_view kThreeVersion = "{version}";',
        "/// The page up to the run's series, in pieces (concatenate them in order).",
        emit_array("kPageHead", head),
        "/// Between the series and the run's data object (the data element's start tag).",
        emit_array("kPageMiddle", middle),
        "/// The page after the run's data object.",
        emit_array("kPageTail", tail),
        "",
        "}  // namespace robophi::replay_assets",
        "",
    ])
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(header, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
