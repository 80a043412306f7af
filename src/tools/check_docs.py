#!/usr/bin/python3
"""Checks the package's documents (issue 61), so that they cannot grow back.

    check_docs.py [ROOT]

ROOT is the repository (default: two folders above this script). Fails,
exit status 1, with one line per problem naming the file:

- README.md longer than 300 lines, docs/PERFORMANCE.md longer than 400;
- a relative Markdown link or image in README.md, docs/*.md or
  docs/history/*.md whose file does not exist;
- such a link's #anchor that names no heading of the file it points at
  (headings turned into anchors as GitHub does).

Links in fenced code blocks and in `code spans` are not links. Python 3
standard library only; needs no build.
"""

import os
import re
import sys
import urllib.parse

LINE_LIMITS = {"README.md": 300, "docs/PERFORMANCE.md": 400}

# [text](target) and ![alt](target); the target ends at the first space
# (a title may follow) or at the closing parenthesis.
LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^\s*(```|~~~)")
# A code span may run over a line break, not over an empty line.
CODE_SPAN = re.compile(r"(`+)((?:(?!\n\s*\n).)+?)\1", re.DOTALL)
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")


def documents(root):
    """The checked documents, as paths relative to root."""
    names = ["README.md"]
    for folder in ("docs", os.path.join("docs", "history")):
        path = os.path.join(root, folder)
        if os.path.isdir(path):
            names += sorted(
                os.path.join(folder, name)
                for name in os.listdir(path)
                if name.endswith(".md")
            )
    return [name for name in names if os.path.isfile(os.path.join(root, name))]


def prose(text):
    """The text with fenced code blocks and code spans blanked (spaces),
    so that offsets and line numbers stay those of the file."""
    lines = text.split("\n")
    in_fence = False
    for i, line in enumerate(lines):
        if FENCE.match(line):
            in_fence = not in_fence
            lines[i] = ""
        elif in_fence:
            lines[i] = ""
    return CODE_SPAN.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), "\n".join(lines))


def headings(text):
    """The headings' texts outside fenced code blocks, code spans kept."""
    in_fence = False
    for line in text.split("\n"):
        if FENCE.match(line):
            in_fence = not in_fence
        elif not in_fence:
            match = HEADING.match(line)
            if match:
                yield match.group(2)


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped,
    spaces to hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # links: their text
    text = text.lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path, cache):
    if path not in cache:
        found = set()
        counts = {}
        with open(path, encoding="utf-8") as f:
            for heading in headings(f.read()):
                base = slug(heading)
                n = counts.get(base, 0)
                counts[base] = n + 1
                found.add(base if n == 0 else "%s-%d" % (base, n))
        cache[path] = found
    return cache[path]


def check(root):
    problems = []
    for name, limit in LINE_LIMITS.items():
        path = os.path.join(root, name)
        if not os.path.isfile(path):
            problems.append("%s: missing" % name)
            continue
        with open(path, encoding="utf-8") as f:
            lines = len(f.read().splitlines())
        if lines > limit:
            problems.append(
                "%s: %d lines, more than its limit of %d" % (name, lines, limit)
            )

    cache = {}
    for name in documents(root):
        path = os.path.join(root, name)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        checked = prose(text)
        for match in LINK.finditer(checked):
            number = checked.count("\n", 0, match.start()) + 1
            target = match.group(1)
            if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) or target.startswith("//"):
                continue  # http:, https:, mailto: ...
            file_part, _, fragment = target.partition("#")
            file_part = urllib.parse.unquote(file_part)
            if file_part:
                linked = os.path.normpath(
                    os.path.join(os.path.dirname(path), file_part)
                )
            else:
                linked = path
            where = "%s:%d" % (name, number)
            if not os.path.exists(linked):
                problems.append(
                    "%s: link to %s: no such file (%s)"
                    % (where, target, os.path.relpath(linked, root))
                )
                continue
            if fragment and linked.endswith(".md") and os.path.isfile(linked):
                if urllib.parse.unquote(fragment).lower() not in anchors(linked, cache):
                    problems.append(
                        "%s: link to %s: no heading with that anchor in %s"
                        % (where, target, os.path.relpath(linked, root))
                    )
    return problems


def main(argv):
    if len(argv) > 2 or (len(argv) == 2 and argv[1] in ("-h", "--help")):
        sys.stderr.write(__doc__)
        return 2
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.abspath(argv[1]) if len(argv) == 2 else os.path.dirname(os.path.dirname(here))
    problems = check(root)
    for problem in problems:
        print("docs-check: %s" % problem, file=sys.stderr)
    if problems:
        print("docs-check: FAILED (%d problems)" % len(problems), file=sys.stderr)
        return 1
    lengths = []
    for name in LINE_LIMITS:
        with open(os.path.join(root, name), encoding="utf-8") as f:
            lengths.append("%s %d lines" % (name, len(f.read().splitlines())))
    print(
        "docs-check: ok (%s; links of %d documents resolve)"
        % (", ".join(lengths), len(documents(root)))
    )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
