#!/usr/bin/env python3
"""The documents' links and section references, checked against the tree (issue 54).

    check_links.py REPO

Checks, in every tracked Markdown file: each relative link [text](path#anchor) names a file or folder that
exists, and its anchor a heading of that file (GitHub's anchors: lower case, punctuation dropped, spaces as
hyphens). In every tracked file: each quoted section reference of the form README "title" names a heading of
README.md that starts with that title (the README is the manual the code points into). Prints one line per
broken link (file, line, what is missing) and exits 1 when there is one.
"""
import os
import re
import subprocess
import sys

LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
SECTION = re.compile(r"(?<![/\w])(README)(?:\.md)?,? \"([A-Z][^\"]{2,80})\"")
CODE_SPAN = re.compile(r"`[^`]*`")


def headings(path, cache={}):
    if path not in cache:
        titles = []
        fence = False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if line.startswith("```"):
                    fence = not fence
                elif not fence and re.match(r"#{1,6} ", line):
                    titles.append(line.lstrip("#").strip())
        cache[path] = titles
    return cache[path]


def anchor(title):
    slug = re.sub(r"[^\w\- ]", "", title.lower().replace("`", ""))
    return slug.replace(" ", "-")


def main(repo):
    listed = subprocess.run(["git", "-C", repo, "ls-files"], capture_output=True, text=True)
    if listed.returncode == 0:
        files = listed.stdout.split()
    else:  # not a checkout (an unpacked source tree): every file but build outputs
        files = [os.path.relpath(os.path.join(d, n), repo) for d, dirs, names in os.walk(repo) for n in names
                 if not os.path.relpath(d, repo).split(os.sep)[0].startswith(("build", "."))]
    broken = []
    for rel in files:
        path = os.path.join(repo, rel)
        if not os.path.isfile(path) or rel.endswith((".png", ".jpg", ".bag", ".gz")):
            continue
        try:
            with open(path, encoding="utf-8") as f:
                lines = f.readlines()
        except UnicodeDecodeError:
            continue
        for number, line in enumerate(lines, 1):
            where = f"{rel}:{number}"
            if rel.endswith(".md"):
                for target in LINK.findall(CODE_SPAN.sub("", line)):
                    if re.match(r"[a-z]+:", target):
                        continue  # http:, https:, mailto:
                    file_part, _, frag = target.partition("#")
                    dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
                    if not os.path.exists(dest):
                        broken.append(f"{where}: link to '{target}': no file {os.path.relpath(dest, repo)}")
                    elif frag and dest.endswith(".md") and frag not in {anchor(h) for h in headings(dest)}:
                        broken.append(f"{where}: link to '{target}': no heading with anchor #{frag}")
            for name, title in SECTION.findall(line):
                dest = os.path.join(repo, "README.md")
                if not any(h.startswith(title) for h in headings(dest)):
                    broken.append(f"{where}: section {name} \"{title}\": no such heading in {os.path.relpath(dest, repo)}")
    for line in broken:
        print(line)
    return 1 if broken else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1]))
