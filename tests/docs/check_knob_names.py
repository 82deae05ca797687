#!/usr/bin/env python3
"""Knob names are written once: in pipeline/knobs.h's key table (issue 54).

    tests/docs/check_knob_names.py SOURCE_DIR

Reads the names of kKnobKeys and kIterationsKnob from pipeline/knobs.h, then every .h/.hpp/.cpp outside tests/
and the build folders, and fails (exit 1, one line per finding) on a string literal that is exactly a knob
name ("csr", "pd0", ...) anywhere else: code that parses or writes a knob by name takes the name from the
table (KnobKey::name, knobKey(&Knobs::csr), forEachKnobField). Prose that mentions a knob ("csr=2 ..." in a
help text, "\\"csr\\"" in a message's example, a comment) is not a literal of the name alone and is left alone.
"""
import os
import re
import sys

TABLE = "pipeline/knobs.h"
SKIP = ("tests/", "build", "cross-toolchain/", "docs/", ".git")


def table_names(path):
    text = open(path, encoding="utf-8").read()
    rows = text.split("kKnobKeys[] = {", 1)
    if len(rows) != 2:
        return []
    body = rows[1].split("};", 1)[0]
    names = re.findall(r'^\s*\{"([a-z0-9_]+)",', body, re.M)
    names += re.findall(r'kIterationsKnob\s*=\s*"([a-z0-9_]+)"', text)
    return names


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    names = table_names(os.path.join(root, TABLE))
    problems = []
    if len(names) < 6:
        problems.append(f"{TABLE}: found {len(names)} knob names in kKnobKeys and kIterationsKnob; not parsed")
    literal = re.compile(r'(?<![\\\w])"(' + "|".join(map(re.escape, names or ["\0"])) + r')"')
    for base, dirs, files in os.walk(root):
        rel = os.path.relpath(base, root)
        rel = "" if rel == "." else rel + "/"
        dirs[:] = sorted(d for d in dirs if not (rel + d + "/").startswith(SKIP) and not d.startswith("build"))
        for f in sorted(files):
            path = rel + f
            if not re.search(r"\.(h|hpp|cpp)$", f) or path == TABLE:
                continue
            for n, line in enumerate(open(os.path.join(root, path), encoding="utf-8", errors="replace"), 1):
                for m in literal.finditer(line):
                    if "//" in line[: m.start()]:
                        continue  # a comment's example
                    problems.append(f"{path}:{n}: the knob name \"{m.group(1)}\" written out; take it from "
                                    f"{TABLE}'s key table (knobKey, iterationsKey, forEachKnobField)")
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
