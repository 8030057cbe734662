#!/usr/bin/env python3
"""Fails when the module graph of a crate has an import cycle.

Reads the DOT graph that `cargo modules dependencies --no-owns ...` prints (the "uses" edges
between a crate's modules, resolved by rust-analyzer) on stdin. A module and its own
submodules are one unit (a type split over files, its tests beside it), so edges between a
module and its ancestors are left out; every other cycle is reported, at every depth of the
module tree (top-level modules, then their submodules, ...). Exit 1 and the cycles on a cycle.

cargo-modules' own `--acyclic` is not used: it checks the graph of items (a type and each of
its methods that mention `Self` form a "cycle"), not of modules.
"""
import re
import sys

EDGE = re.compile(r'^\s*"([^"]+)"\s*->\s*"([^"]+)"\s*\[label="uses"')


def components(nodes, edges):
    """Strongly connected components with more than one node (Tarjan, iterative)."""
    index, low, on, stack, out, counter = {}, {}, set(), [], [], [0]
    for root in sorted(nodes):
        if root in index:
            continue
        work = [(root, iter(sorted(edges.get(root, ()))))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
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
    return out


def related(a, b):
    return a == b or a.startswith(b + "::") or b.startswith(a + "::")


def main():
    crate = sys.argv[1]
    text = sys.stdin.read()
    if "digraph" not in text:
        print(f"{crate}: no module graph on stdin (cargo-modules failed?)", file=sys.stderr)
        return 2
    pairs = [m.groups() for m in map(EDGE.match, text.splitlines()) if m]
    depth = max((n.count("::") for pair in pairs for n in pair), default=0)
    found = False
    for d in range(1, depth + 1):
        cut = lambda n: "::".join(n.split("::")[: d + 1])
        edges, nodes = {}, set()
        for a, b in pairs:
            a, b = cut(a), cut(b)
            if related(a, b):
                continue
            edges.setdefault(a, set()).add(b)
            nodes.update((a, b))
        for comp in components(nodes, edges):
            found = True
            print(f"{crate}: import cycle between modules (depth {d}):")
            for a in comp:
                print(f"  {a} -> {', '.join(sorted(b for b in edges[a] if b in comp))}")
    if not found:
        print(f"{crate}: no import cycle ({len(pairs)} uses edges, module depth {depth})")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
