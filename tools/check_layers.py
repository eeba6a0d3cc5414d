#!/usr/bin/env python3
"""The layering of wiresketch's sources, checked (`make check-layers`).

usage: python3 tools/check_layers.py [ROOT]

Reads every #include "..." of nn/ and src/ (system headers <...> are not
followed) and fails (exit 1, one line per fault) when
  - a file of nn/ includes a header outside nn/: nn/ stands alone, its
    includes are relative to the including file, so it compiles without
    -Isrc (the Makefile's check-layers also compiles it that way);
  - an include names no file (src/ resolves "folder/x.h" against src/ and
    the repository root, as the Makefile's -Isrc -I. do);
  - the module graph has a cycle: a module is x.c with its x.h, and module
    A depends on B when a file of A includes x.h of B (so fit.c including
    checkpoint.h while checkpoint.c includes fit.h is a cycle, though no
    header includes itself);
  - the folder graph has a cycle (folder A depends on B when a module of A
    depends on one of B).
Then prints the folders in dependency order: each line's folders include
only folders of the lines above (and themselves). Standard library only.
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def sources(root):
    for top in ("nn", "src"):
        for d, _, files in os.walk(os.path.join(root, top)):
            for f in sorted(files):
                if f.endswith((".c", ".h")):
                    yield os.path.relpath(os.path.join(d, f), root)


def resolve(root, path, name):
    """The repository path an include of `path` names, or None."""
    here = os.path.dirname(path)
    if path.startswith("nn" + os.sep):
        candidates = [os.path.join(here, name)]
    else:
        candidates = [os.path.join(here, name), os.path.join("src", name), name]
    for c in candidates:
        c = os.path.normpath(c)
        if os.path.isfile(os.path.join(root, c)):
            return c
    return None


def cycles(graph):
    """Strongly connected components of more than one node (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def layers(graph):
    """Folders by level: 1 + the highest level of what they depend on."""
    level = {}

    def of(v):
        if v not in level:
            level[v] = 0  # no cycle here (checked first)
            level[v] = 1 + max((of(w) for w in graph[v] if w != v), default=0)
        return level[v]

    for v in graph:
        of(v)
    rows = {}
    for v, k in level.items():
        rows.setdefault(k, []).append(v)
    return [sorted(rows[k]) for k in sorted(rows)]


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    faults = []
    modules, folders = {}, {}
    for path in sources(root):
        module = os.path.splitext(path)[0]
        folder = os.path.dirname(path)
        modules.setdefault(module, set())
        folders.setdefault(folder, set())
        with open(os.path.join(root, path), encoding="utf-8") as f:
            text = f.read()
        for name in INCLUDE.findall(text):
            target = resolve(root, path, name)
            if target is None:
                faults.append('%s: includes "%s", which is %s' % (
                    path, name, "not in nn/ (nn/ stands alone: includes relative to the file)"
                    if path.startswith("nn" + os.sep) else "no file of src/ or the root"))
                continue
            if path.startswith("nn" + os.sep) and not target.startswith("nn" + os.sep):
                faults.append('%s: includes "%s" (%s): nn/ must include nothing outside nn/'
                              % (path, name, target))
            dep = os.path.splitext(target)[0]
            if dep != module:
                modules[module].add(dep)
                if os.path.dirname(target) != folder:
                    folders[folder].add(os.path.dirname(target))
    for comp in cycles(modules):
        faults.append("module cycle (x.c + x.h): " + " <-> ".join(comp))
    for comp in cycles(folders):
        faults.append("folder cycle: " + " <-> ".join(comp))
    for line in faults:
        print("check-layers: " + line)
    if faults:
        return 1
    print("check-layers: %d modules, %d folders, no cycle; nn/ includes nothing outside nn/"
          % (len(modules), len(folders)))
    print("folders in dependency order (each includes only those above it):")
    for k, row in enumerate(layers(folders), 1):
        print("  %2d  %s" % (k, "  ".join(row)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
