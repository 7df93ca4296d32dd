#!/usr/bin/env python3
"""No call cycle between source files (issue 12: "No call cycle between
source files").

Reads the symbol tables of object files with `nm` (in static libraries, thin
or not, or given one by one), and draws the file graph: file A -> file B when
A's object has an undefined symbol that B's object defines. A cycle in that
graph (A -> B -> ... -> A) means no file of it can be read, tested or moved
without the others, and the test fails printing each cycle with the symbols
that make its edges.

    call_cycles.py [--build-root DIR [--source-root DIR]] [--nm NM] [--program PROG]...
                   [--expect-cycle A,B,...] FILE...

FILE is a static library (.a) or an object file (.o): the library. A
--program PROG (an archive or object of one program's own files) is checked
together with the library, each program on its own: programs define the same
names (main, usage), so one graph of all of them would join files that are
never linked together. With --build-root,
objects are named by their source file, read from DIR/compile_commands.json
(Meson writes it); otherwise by their object file. --expect-cycle inverts the
test, for the check that the detector works: exit 0 only when a cycle is
found through files whose names end with each of the given texts.

Exit status: 0 no cycle, 1 a cycle (or, with --expect-cycle, not the one
expected), 2 usage or nm trouble, or nothing to check.
"""

import argparse
import json
import os
import subprocess
import sys


def read_symbols(nm, path):
    """{object path: (defined set, undefined set)} for one .a or .o file.

    `nm -A -P` prints one symbol a line, POSIX format, prefixed by its file:
    "lib.a[member.o]: name T value size" or "file.o: name U"."""
    try:
        out = subprocess.run([nm, "-A", "-P", path], check=True, capture_output=True,
                             text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        sys.exit(f"call_cycles: {nm} {path}: {e}")
    objects = {}
    for line in out.splitlines():
        where, sep, rest = line.rpartition(": ")
        fields = rest.split()
        if not sep or len(fields) < 2:
            continue
        name, kind = fields[0], fields[1]
        if where.endswith("]") and "[" in where:
            # a member of an archive; a thin archive names it by its path
            member = where[where.index("[") + 1:-1]
            archive_dir = os.path.dirname(os.path.abspath(where[:where.index("[")]))
            obj = os.path.normpath(os.path.join(archive_dir, member)) if not os.path.isabs(member) \
                else os.path.normpath(member)
            # nm gives thin members relative to the working directory when the
            # archive path was relative; keep whichever exists
            if not os.path.exists(obj) and os.path.exists(member):
                obj = os.path.abspath(member)
        else:
            obj = os.path.abspath(where)
        defined, undefined = objects.setdefault(obj, (set(), set()))
        if kind in ("U", "w", "v"):
            undefined.add(name)  # a reference (weak ones too: they name a definition)
        elif kind.isupper():
            defined.add(name)    # global: T text, D/B/R data, C common, W/V weak
    return objects


def source_names(build_root, source_root=None):
    """{object path: source path relative to source_root (default: the
    directory all sources share)}, from Meson's compilation database."""
    path = os.path.join(build_root, "compile_commands.json")
    try:
        with open(path) as f:
            entries = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"call_cycles: {path}: {e}")
    names = {}
    for e in entries:
        directory = e.get("directory", build_root)
        obj = os.path.normpath(os.path.join(directory, e["output"]))
        src = os.path.normpath(os.path.join(directory, e["file"]))
        names[os.path.realpath(obj)] = src
    if not names:
        return {}
    root = source_root or os.path.commonpath(list(names.values()))
    return {o: os.path.relpath(s, root) for o, s in names.items()}


def file_graph(objects, label):
    """{file: {file it calls: sorted symbols}} over the given objects."""
    definer = {}
    for obj, (defined, _) in objects.items():
        for name in defined:
            definer.setdefault(name, set()).add(label(obj))
    graph = {label(obj): {} for obj in objects}
    for obj, (_, undefined) in objects.items():
        a = label(obj)
        for name in undefined:
            for b in definer.get(name, ()):
                if b != a:
                    graph[a].setdefault(b, set()).add(name)
    return {a: {b: sorted(s) for b, s in edges.items()} for a, edges in graph.items()}


def strongly_connected(graph):
    """Tarjan's algorithm (iterative): the components with more than one file,
    each sorted, in sorted order."""
    index, low, on_stack, stack, comps = {}, {}, set(), [], []
    counter = 0
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, it = work[-1]
            advanced = False
            for nxt in it:
                if nxt not in index:
                    index[nxt] = low[nxt] = counter
                    counter += 1
                    stack.append(nxt)
                    on_stack.add(nxt)
                    work.append((nxt, iter(sorted(graph[nxt]))))
                    advanced = True
                    break
                if nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
            if advanced:
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                comp = []
                while True:
                    top = stack.pop()
                    on_stack.discard(top)
                    comp.append(top)
                    if top == node:
                        break
                if len(comp) > 1:
                    comps.append(sorted(comp))
    return sorted(comps)


def shortest_cycle(graph, comp, start):
    """The shortest path start -> ... -> start inside one component (BFS)."""
    members = set(comp)
    prev = {}
    frontier = [start]
    while frontier:
        nxt_frontier = []
        for node in frontier:
            for nxt in sorted(graph[node]):
                if nxt not in members:
                    continue
                if nxt == start:
                    path = [node]
                    while path[-1] != start:
                        path.append(prev[path[-1]])
                    return list(reversed(path)) + [start]
                if nxt not in prev:
                    prev[nxt] = node
                    nxt_frontier.append(nxt)
        frontier = nxt_frontier
    return [start]


def describe(graph, comps):
    lines = []
    for comp in comps:
        lines.append(f"call cycle between {len(comp)} files: {', '.join(comp)}")
        # one cycle through each file of the component, so that every edge
        # to cut shows up
        seen = set()
        for start in comp:
            cycle = shortest_cycle(graph, comp, start)
            key = frozenset(zip(cycle, cycle[1:]))
            if key in seen:
                continue
            seen.add(key)
            lines.append("  " + cycle[0])
            for a, b in zip(cycle, cycle[1:]):
                syms = graph[a][b]
                shown = ", ".join(syms[:6]) + (f", ... ({len(syms)} symbols)" if len(syms) > 6 else "")
                lines.append(f"    -> {b}   ({a} calls {shown})")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build-root", help="name objects by source file (compile_commands.json)")
    ap.add_argument("--source-root", help="name sources relative to this directory")
    ap.add_argument("--nm", default=os.environ.get("NM", "nm"))
    ap.add_argument("--program", action="append", default=[],
                    help="one program's objects, checked with the library (repeatable)")
    ap.add_argument("--expect-cycle", help="comma-separated file name endings (detector check)")
    ap.add_argument("files", nargs="+")
    args = ap.parse_args()

    def load(paths):
        objects = {}
        for path in paths:
            for obj, (defined, undefined) in read_symbols(args.nm, path).items():
                d, u = objects.setdefault(obj, (set(), set()))
                d |= defined
                u |= undefined
        return objects

    names = source_names(args.build_root, args.source_root) if args.build_root else {}

    def label(obj):
        return names.get(os.path.realpath(obj), os.path.relpath(obj))

    library = load(args.files)
    # the library alone, then the library with each program
    units = [library] + [{**library, **load([p])} for p in args.program]
    graph, comps = {}, set()
    for objects in units:
        g = file_graph(objects, label)
        for a, edges in g.items():
            graph.setdefault(a, {}).update(edges)
        comps.update(tuple(c) for c in strongly_connected(g))
    comps = sorted(list(c) for c in comps)
    n_edges = sum(len(e) for e in graph.values())
    # a graph without edges checks nothing: wrong arguments, not a pass
    if len(graph) < 2 or n_edges == 0:
        print(f"call_cycles: {len(graph)} files, {n_edges} calls between them: nothing to check",
              file=sys.stderr)
        return 2

    if args.expect_cycle:
        want = [w for w in args.expect_cycle.split(",") if w]
        for comp in comps:
            if all(any(f.endswith(w) for f in comp) for w in want):
                print(describe(graph, [comp]))
                print(f"call_cycles: the expected cycle ({', '.join(want)}) is found")
                return 0
        print(f"call_cycles: no cycle through {', '.join(want)} among {len(graph)} files",
              file=sys.stderr)
        return 1

    if comps:
        print(describe(graph, comps))
        print(f"call_cycles: {len(comps)} call cycle(s) among {len(graph)} files "
              f"({n_edges} file-to-file calls): cut one edge of each (move a function, "
              "or split a file)", file=sys.stderr)
        return 1
    print(f"call_cycles: {len(graph)} files, {n_edges} file-to-file calls, no cycle")
    return 0


if __name__ == "__main__":
    sys.exit(main())
