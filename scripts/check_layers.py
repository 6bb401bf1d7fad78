#!/usr/bin/env python3
"""Checks every #include under host/ against the layer table host/layers.txt.

A file in host/<layer>/ may include "<layer>/...", the layers its line names, and kernels/shared
("shared/..." where its line names `shared`); <CL/...> only in the layers of the `opencl` line;
no include may climb out with "..". host/main.cpp belongs to the cli layer.

    scripts/check_layers.py [ROOT]      ROOT: the repository (default: this script's parent)

Prints every forbidden include as FILE:LINE: what, and why; exits 1 when there is one, 0 when
there is none, 2 when the table or the tree cannot be read. CTest runs it (tests/CMakeLists.txt).
"""
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def read_table(path):
    layers, opencl = {}, set()
    for number, line in enumerate(path.read_text().splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        m = re.fullmatch(r"([a-z]+):\s*(.*)", line)
        if not m:
            raise ValueError(f"{path}:{number}: expected 'layer: layers it may include', got {line!r}")
        name, deps = m.group(1), m.group(2).split()
        if name == "opencl":
            opencl = set(deps)
        else:
            layers[name] = set(deps)
    for name, deps in layers.items():
        unknown = deps - set(layers) - {"shared"}
        if unknown:
            raise ValueError(f"{path}: layer {name} names unknown layers {sorted(unknown)}")
    if opencl - set(layers):
        raise ValueError(f"{path}: the opencl line names unknown layers {sorted(opencl - set(layers))}")
    return layers, opencl


def main(argv):
    root = pathlib.Path(argv[1] if len(argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    host = root / "host"
    try:
        layers, opencl = read_table(host / "layers.txt")
    except (OSError, ValueError) as e:
        print(f"check_layers: {e}", file=sys.stderr)
        return 2
    folders = {p.name for p in host.iterdir() if p.is_dir()}
    problems, files = [], 0
    for folder in sorted(folders - set(layers)):
        problems.append(f"host/{folder}/: a folder that host/layers.txt does not name (add its line)")
    for path in sorted(host.rglob("*")):
        if path.suffix not in (".h", ".cpp") or not path.is_file():
            continue
        rel = path.relative_to(root)
        parts = path.relative_to(host).parts
        layer = "cli" if parts == ("main.cpp",) else parts[0]
        if layer not in layers:
            continue  # reported above
        files += 1
        allowed = layers[layer] | {layer}
        for number, text in enumerate(path.read_text(errors="replace").splitlines(), 1):
            m = INCLUDE.match(text)
            if not m:
                continue
            kind, name = m.groups()
            where = f"{rel}:{number}: #include {kind}{name}{'>' if kind == '<' else chr(34)}"
            if ".." in pathlib.PurePosixPath(name).parts:
                problems.append(f"{where}: climbs out with '..'; include by layer/file")
            elif kind == "<":
                if name.startswith("CL/") and layer not in opencl:
                    problems.append(f"{where}: OpenCL in layer {layer}; only {', '.join(sorted(opencl))} include it")
            else:
                target = name.split("/", 1)[0] if "/" in name else None
                if target is None:
                    problems.append(f"{where}: include by layer/file (e.g. \"{layer}/{name}\")")
                elif target not in allowed:
                    problems.append(f"{where}: layer {layer} may not include layer {target} "
                                    f"(host/layers.txt: {layer}: {' '.join(sorted(layers[layer])) or 'nothing'})")
    for p in problems:
        print(p)
    print(f"check_layers: {files} files, {len(layers)} layers, {len(problems)} forbidden include(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
