#!/usr/bin/env python3
"""The layers of lib/ from its #include lines (docs/architecture.md).

    python3 scripts/include_graph.py [--root DIR]          print the Mermaid graph
    python3 scripts/include_graph.py --check [--doc FILE]  check the rules below

Every quoted include "dir/name.h" of a file in lib/dir/ is an edge; an
include of a public header "brdffit/name.h" is an edge to the layer that
implements it (PUBLIC below). The checks (exit status 1 and one line per violation when one fails):
  - no include cycle between the files of lib/;
  - no upward include: a directory includes only from itself and from
    directories of a lower layer (LAYERS below);
  - a directory's private headers (PRIVATE below) are included only by
    files of that directory;
  - with --doc, the Mermaid block of the page between the markers
    "<!-- include-graph -->" and "<!-- /include-graph -->" is the one this
    script prints, so the picture stays true.
Standard library only.
"""
import argparse
import os
import re
import sys

# Lower numbers are lower layers.
LAYERS = {"core": 0, "grid": 1, "optim": 1, "models": 2, "load": 2, "fit": 3, "image": 3}

# The layer of each public header lib/ includes.
PUBLIC = {
    "alloc.h": "core", "export.h": "core", "status.h": "core", "version.h": "core",
    "batch.h": "grid", "grid.h": "grid", "optim.h": "optim", "model.h": "models",
    "load.h": "load", "fit.h": "fit", "many.h": "fit", "image.h": "image",
}

# Headers only their own directory may include; the others of a directory
# are its interface to the layers above.
PRIVATE = {
    "models/kernel.h",
    "models/model_internal.h",
    "optim/optim_internal.h",
    "load/load_internal.h",
    "image/image_internal.h",
}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
BEGIN, END = "<!-- include-graph -->", "<!-- /include-graph -->"


def scan(lib):
    """{file: [included lib files]} for every .c and .h under lib/."""
    edges = {}
    for d in sorted(os.listdir(lib)):
        path = os.path.join(lib, d)
        if not os.path.isdir(path):
            continue
        for name in sorted(os.listdir(path)):
            if not name.endswith((".c", ".h")):
                continue
            with open(os.path.join(path, name), encoding="utf-8") as f:
                text = f.read()
            src = d + "/" + name
            targets = []
            for inc in INCLUDE.findall(text):
                if "/" not in inc:  # "core.h" beside the file
                    inc = d + "/" + inc
                if os.path.isfile(os.path.join(lib, inc)):
                    targets.append(inc)
                elif inc.startswith("brdffit/"):
                    name = inc.split("/", 1)[1]
                    targets.append(PUBLIC.get(name, "public") + "/" + inc)
            edges[src] = targets
    return edges


def find_cycle(edges):
    """One include cycle between files of lib/ as a list of files, or None
    (public headers are not followed)."""
    state = {}
    stack = []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in edges.get(node, []):
            if "/brdffit/" in nxt:
                continue
            if state.get(nxt) == 1:
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(edges):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def violations(edges):
    found = []
    cycle = find_cycle(edges)
    if cycle:
        found.append("include cycle: " + " -> ".join(cycle))
    for src in sorted(edges):
        a = src.split("/")[0]
        for t in edges[src]:
            b = t.split("/")[0]
            if a == b:
                continue
            if a not in LAYERS or b not in LAYERS:
                found.append(f"{src}: includes {t}; lib/{a if a not in LAYERS else b} has no layer "
                             "in scripts/include_graph.py")
            elif LAYERS[b] >= LAYERS[a]:
                found.append(f"{src}: upward include of {t} (layer {a} {LAYERS[a]}, "
                             f"{b} {LAYERS[b]})")
            if t in PRIVATE:
                found.append(f"{src}: includes {t}, private to lib/{b}")
    return found


def mermaid(edges):
    """The layer graph: one node per directory, ranked top (fit) to bottom
    (core), one arrow per directory pair labelled with the headers used."""
    used = {}
    for src, targets in edges.items():
        for t in targets:
            a, b = src.split("/")[0], t.split("/")[0]
            if a != b:
                used.setdefault((a, b), set()).add(t.split("/", 1)[1])
    dirs = sorted({s.split("/")[0] for s in edges}, key=lambda d: (-LAYERS.get(d, 99), d))
    lines = ["```mermaid", "graph TD"]
    for d in dirs:
        lines.append(f"    {d}[\"lib/{d}\"]")
    for (a, b) in sorted(used, key=lambda e: (-LAYERS.get(e[0], 99), e[0], e[1])):
        lines.append(f"    {a} -->|{', '.join(sorted(used[(a, b)]))}| {b}")
    lines.append("```")
    return "\n".join(lines) + "\n"


def doc_block(path):
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if BEGIN not in text or END not in text:
        return None
    return text.split(BEGIN, 1)[1].split(END, 1)[0].strip("\n") + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=os.path.join(os.path.dirname(__file__), ".."))
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--doc")
    args = ap.parse_args()
    edges = scan(os.path.join(args.root, "lib"))
    if not args.check:
        sys.stdout.write(mermaid(edges))
        return 0
    found = violations(edges)
    if args.doc:
        block = doc_block(args.doc)
        if block is None:
            found.append(f"{args.doc}: no {BEGIN} ... {END} block")
        elif block != mermaid(edges):
            found.append(f"{args.doc}: the include graph is out of date; replace the block with "
                         "the output of scripts/include_graph.py")
    for v in found:
        print("include_graph: " + v)
    n = sum(len(t) for t in edges.values())
    print(f"include_graph: {len(edges)} files, {n} includes, "
          f"{len(found)} violation(s)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
