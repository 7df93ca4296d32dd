#!/usr/bin/env python3
"""Every repository path that a comment or a doc names exists (issue 24).

A comment or doc that names `src/core/controller.c` or `include/popc/core/plant.h`
sends a reader there; after a move (the flat layout became one folder per
layer) such a path silently points at nothing. This test reads

  - the comments of the C sources and headers (/* */ and //), and of the
    shell, Python and Meson files (# to the end of the line), in the folders
    below, and
  - the whole text of README.md and docs/*.md,

takes every word that starts with one of the repository's top-level folders
(src/ include/ analysis/ tests/ tools/ bench/ python/ examples/ man/) and is
not the tail of a longer path (`build/src/popc`, `$tmp/tests/x`, `PREFIX/...`),
and checks that it exists under the source root. A word with a wildcard or a
placeholder (`cmd_*.c`, `include/popc/<layer>/`) must match at least one path
as a glob (the placeholder read as `*`). It also refuses a citation of the
"DESIGN" document, which is not in the repository: a comment cites the doc in
docs/ that holds the fact, or the paper and its equation.

Usage: check_paths.py SOURCE_ROOT    exit 0, or 1 listing file:line: path
       check_paths.py --self-test    the checker on a made-up tree
"""
import glob
import os
import re
import sys
import tempfile

import hygiene
from hygiene import c_tokens

TOP = ("src", "include", "analysis", "tests", "tools", "bench", "python",
       "examples", "man")
# Folders whose files' comments are read (the fuzz corpus is data, not text
# anybody reads, and holds mutated copies of comments).
SCANNED = TOP + ("data",)
SKIP_DIRS = ("tests/fuzz/corpus",)
C_EXT = (".c", ".h", ".c.in", ".h.in", ".cpp", ".def")
HASH_EXT = (".sh", ".py", ".build", ".txt", ".ini", ".scd", ".bash", ".in")
HASH_NAMES = ("meson.build", "meson_options.txt", "popc", "popc-analyze")

# A path word: a top-level folder, a slash, then path characters. What comes
# before it must not continue a path or a variable ($x/src, build/src, a.src/).
PATH_RE = re.compile(
    r"(?<![A-Za-z0-9_./$\-{}~])(?:" + "|".join(TOP) + r")/[A-Za-z0-9_./<>*+\-]*")
# Files the build writes, named in comments as what they are made from.
GENERATED = {
    "python/popc/_config.py",        # python/meson.build: configure_file
    "src/cli/popc_build_id.h",       # src/cli/popc_build_id.h.in
}
DESIGN_RE = re.compile(r"\bDESIGN\b(?:\s+(?:section\s+)?\d)")


def comments_c(text):
    """(line, comment text) of every C comment (hygiene.c_tokens)."""
    return [(line, text[start:end]) for kind, start, end, line in c_tokens(text)
            if kind == "comment"]


def comments_hash(text):
    """(line, comment text): from a # at a line's start or after a blank."""
    out = []
    for k, row in enumerate(text.split("\n"), 1):
        m = re.search(r"(?:^|\s)([#;].*)$", row)
        if m and not row.lstrip().startswith("#!"):
            out.append((k, m.group(1)))
    return out


def doc_lines(text):
    return list(enumerate(text.split("\n"), 1))


def words(chunks):
    for line, chunk in chunks:
        for m in PATH_RE.finditer(chunk):
            yield line + chunk.count("\n", 0, m.start()), m.group(0)
        for m in DESIGN_RE.finditer(chunk):
            yield line + chunk.count("\n", 0, m.start()), "DESIGN"


def built(root, word):
    """A program or folder the build makes: the nearest folder that exists
    builds it from a source of that name (bench/lib_loop from lib_loop.c) or
    names it, quoted, in its meson.build (tests/fuzz/'libfuzzer')."""
    parts = word.strip("/").split("/")
    k = len(parts)
    while k > 0 and not os.path.isdir(os.path.join(root, *parts[:k])):
        k -= 1
    if k == 0 or k == len(parts):
        return False
    folder = os.path.join(root, *parts[:k])
    name = parts[k]
    if k == len(parts) - 1 and any(os.path.exists(os.path.join(folder, name + e))
                                   for e in (".c", ".cpp")):
        return True
    build = os.path.join(folder, "meson.build")
    if os.path.exists(build):
        with open(build, encoding="utf-8") as f:
            return "'%s'" % name in f.read()
    return False


def exists(root, word, here):
    """here: the folder of the file that names word (a doc's relative link)."""
    if word in GENERATED:
        return True
    for base in (root, os.path.join(root, here)):
        if os.path.exists(os.path.join(base, word)):
            return True
    # placeholders: <layer>, *, an upper-case name (HARNESS, SCENE)
    pattern = re.sub(r"<[^>]*>|(?<![A-Za-z0-9])[A-Z][A-Z_]+(?![a-z0-9])", "*",
                     word)
    if (pattern != word or "*" in word) and glob.glob(os.path.join(root, pattern)):
        return True
    return built(root, word)


def files_of(root):
    for name in ("README.md",):
        yield name, "doc"
    for path in sorted(glob.glob(os.path.join(root, "docs", "*.md"))):
        yield os.path.relpath(path, root), "doc"
    for name in ("meson.build", "meson_options.txt"):
        if os.path.exists(os.path.join(root, name)):
            yield name, "hash"
    for top in SCANNED:
        for d, dirs, names in os.walk(os.path.join(root, top)):
            rel_d = os.path.relpath(d, root)
            dirs[:] = sorted(x for x in dirs
                             if os.path.join(rel_d, x) not in SKIP_DIRS)
            for name in sorted(names):
                rel = os.path.join(rel_d, name)
                if name.endswith(C_EXT):
                    yield rel, "c"
                elif name.endswith(HASH_EXT) or name in HASH_NAMES:
                    yield rel, "hash"
                elif name.endswith(".md"):
                    yield rel, "doc"


def check(root):
    bad = []
    for rel, kind in files_of(root):
        try:
            with open(os.path.join(root, rel), encoding="utf-8") as f:
                text = f.read()
        except (UnicodeDecodeError, FileNotFoundError):
            continue
        chunks = {"c": comments_c, "hash": comments_hash,
                  "doc": doc_lines}[kind](text)
        here = os.path.dirname(rel)
        for line, word in words(chunks):
            word = word.rstrip(".,:;)`'\"-")
            if word == "DESIGN":
                bad.append("%s:%d: cites DESIGN, which is not in the "
                           "repository (cite the doc in docs/ or the paper)"
                           % (rel, line))
            elif not exists(root, word, here):
                bad.append("%s:%d: %s does not exist" % (rel, line, word))
    return bad


def self_test():
    with tempfile.TemporaryDirectory() as root:
        def put(rel, text):
            path = os.path.join(root, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w") as f:
                f.write(text)
        put("src/core/plant.c", "/* see src/core/plant.c and src/plant.c */\n"
            "static const char *s = \"src/gone.c\"; // include/popc/x.h\n")
        put("src/meson.build", "# tests/a.sh, $tmp/tests/b, build/src/popc\n"
            "x = 'src/nope.c'\n")
        put("tests/a.sh", "#!/bin/sh\n# src/core/*.c and src/<layer>/ and "
            "src/zzz/*.c; DESIGN section 4\n")
        put("README.md", "`src/core/plant.c`, src/gone/, (tools/x.sh).\n")
        put("docs/A.md", "see analysis/common.c, [f](bench/f.png), "
            "bench/prog, bench/made/, bench/none, tests/CASE.sh\n")
        put("docs/bench/f.png", "")
        put("bench/prog.c", "")
        put("bench/meson.build", "x = 'made'\n")
        got = sorted(check(root))
        want = sorted([
            "src/core/plant.c:1: src/plant.c does not exist",
            "src/core/plant.c:2: include/popc/x.h does not exist",
            "tests/a.sh:2: src/zzz/*.c does not exist",
            "tests/a.sh:2: cites DESIGN, which is not in the repository "
            "(cite the doc in docs/ or the paper)",
            "README.md:1: src/gone/ does not exist",
            "README.md:1: tools/x.sh does not exist",
            "docs/A.md:1: analysis/common.c does not exist",
            "docs/A.md:1: bench/none does not exist",
        ])
        if got != want:
            print("self-test: got\n  " + "\n  ".join(got) +
                  "\nwant\n  " + "\n  ".join(want))
            return 1
    print("self-test: ok")
    return 0


def main(argv):
    return hygiene.main(argv, __doc__, check, self_test,
                        "%d path(s) named in comments or docs do not exist",
                        "every path named in a comment or doc exists")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
