#!/usr/bin/env python3
"""The layer tables of docs/architecture.md ("## Layers") against the code's includes.

    tests/docs/check_layers.py SOURCE_DIR

Reads the folder table (folder, library, what it is, includes from) and the exceptions table (file, also
includes, why), then every `#include "..."` of the .h/.hpp/.c/.cpp/.cl files under the folders of code
(tests/ left out). Fails (exit 1, one line per finding) on
  - an include of a folder that the including file's row does not name (nor the exceptions table for it),
  - an include of a file that the row does not name where it allows a folder's named files only
    ("pipeline (`knobs.h` only)"),
  - a row that names a folder listed below it, or a name that is no row,
  - a source file in no row's folder (a new folder of code missing from the table),
  - an exception that no longer happens (the table says more than the code).
A file belongs to the longest folder of the table that holds it (pipeline/cpu/x.cpp: pipeline/cpu/).
"""
import os
import re
import subprocess
import sys

SOURCE = re.compile(r"\.(h|hpp|c|cpp|cl)$")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
NOT_CODE = ("tests/", "config/", "systemd/", "cross-toolchain/", "scripts/", "docs/", "build")


def cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def names(cell):
    """`core`, drivers, pipeline/cpu -> ["core/", "drivers/", "pipeline/cpu/"]; "nothing" -> []."""
    cell = re.sub(r"\([^)]*\)", "", cell).replace("`", "")
    out = []
    for word in cell.split(","):
        word = word.strip()
        if word and word != "nothing":
            out.append(word.rstrip("/") + "/")
    return out


def only(cell):
    """pipeline (`knobs.h` only: ...) -> {"pipeline/": ["pipeline/knobs.h"]}: a folder a row may include from
    for the files named alone."""
    out = {}
    for folder, files in re.findall(r"`?([\w/]+)`?\s*\(((?:`[^`]+`[,\s]*)+)only\b", cell):
        folder = folder.rstrip("/") + "/"
        out[folder] = [folder + f for f in re.findall(r"`([^`]+)`", files)]
    return out


def read_tables(doc):
    text = open(doc, encoding="utf-8").read()
    section = text.split("## Layers\n", 1)[1].split("\n## ", 1)[0]
    rows, exceptions, restricted, table = [], {}, {}, None
    for line in section.splitlines():
        if not line.startswith("|"):
            table = None if not line.strip() else table
            continue
        c = cells(line)
        if c[0] in ("folder", "file"):
            table = c[0]
            continue
        if set(c[0]) <= set("-: "):
            continue
        if table == "folder":
            rows.append((c[0].strip("`"), names(c[-1])))
            restricted[c[0].strip("`")] = only(c[-1])
        elif table == "file":
            exceptions[c[0].strip("`")] = names(c[1])
    return rows, exceptions, restricted


def folder_of(path, folders):
    best = None
    for f in folders:
        if path.startswith(f) and (best is None or len(f) > len(best)):
            best = f
    return best


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    rows, exceptions, restricted = read_tables(os.path.join(root, "docs", "architecture.md"))
    folders = [f for f, _ in rows]
    problems = []
    if len(rows) < 10:
        problems.append(f"docs/architecture.md: the layer table has {len(rows)} rows; not found or not parsed")
    for i, (folder, allowed) in enumerate(rows):
        for a in allowed:
            if a not in folders:
                problems.append(f"docs/architecture.md: row {folder}: '{a}' is not a folder of the table")
            elif folders.index(a) > i:
                problems.append(f"docs/architecture.md: row {folder} includes from {a}, which is listed below it")
    for f, extra in exceptions.items():
        for a in extra:
            if a not in folders:
                problems.append(f"docs/architecture.md: exception {f}: '{a}' is not a folder of the table")
    allowed = dict(rows)
    try:
        files = subprocess.run(["git", "ls-files"], cwd=root, check=True, capture_output=True,
                               text=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        files = [os.path.relpath(os.path.join(d, n), root) for d, _, ns in os.walk(root) for n in ns]
    used = set()
    for path in sorted(files):
        if not SOURCE.search(path) or path.startswith(NOT_CODE):
            continue
        src = folder_of(path, folders)
        if src is None:
            problems.append(f"{path}: in no folder of docs/architecture.md's layer table (add its folder's row)")
            continue
        text = open(os.path.join(root, path), encoding="utf-8", errors="replace").read()
        for m in INCLUDE.finditer(text):
            dst = folder_of(m.group(1), folders)
            files = restricted.get(src, {}).get(dst)
            if files is not None and m.group(1) not in files:
                line = text.count("\n", 0, m.start()) + 1
                problems.append(f"{path}:{line}: includes {m.group(1)}, but {src} may include only "
                                f"{', '.join(files)} of {dst} (docs/architecture.md, Layers)")
                continue
            if dst is None or dst == src or dst in allowed[src]:
                continue
            if dst in exceptions.get(path, []):
                used.add((path, dst))
                continue
            line = text.count("\n", 0, m.start()) + 1
            problems.append(f"{path}:{line}: includes {m.group(1)}, but {src} may include "
                            f"{', '.join(allowed[src]) or 'nothing of ours'} (docs/architecture.md, Layers)")
    for f, extra in exceptions.items():
        for a in extra:
            if (f, a) not in used:
                problems.append(f"docs/architecture.md: exception {f} -> {a} no longer happens: remove it")
    for p in problems:
        print(p)
    print(f"check_layers: {len(rows)} folders, {len(exceptions)} exception files, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
