#!/usr/bin/env python3
"""Import circles between the modules (files) of each crate: `crate::a::b` paths, `use super::`
and `use self::` resolved to files. A module and the modules inside it are one unit: a parent's
`mod child;` and a child's `super::Item` are not edges. Prints each circle
found and exits 1 when there is one. Usage: tools/module_cycles.py [crates-dir]"""
import os, re, sys

def module_files(src):
    mods = {}
    for root, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs"):
                continue
            p = os.path.join(root, f)
            rel = os.path.relpath(p, src)[:-3].split(os.sep)
            if rel[-1] in ("mod", "lib", "main"):
                rel = rel[:-1]
            mods[tuple(rel)] = p
    return mods

def resolve(mods, path):
    """The longest module prefix of `path` that is a file."""
    for n in range(len(path), -1, -1):
        if tuple(path[:n]) in mods:
            return tuple(path[:n])
    return None

def strip_tests(text):
    # Tests may import anything; circles through #[cfg(test)] modules are not structure.
    i = text.find("#[cfg(test)]\nmod tests")
    return text if i < 0 else text[:i]

def edges(mods):
    out = {m: set() for m in mods}
    for m, p in mods.items():
        text = strip_tests(open(p).read())
        text = re.sub(r"//[^\n]*", "", text)
        is_dir_mod = os.path.basename(p) in ("mod.rs", "lib.rs", "main.rs")
        here = list(m) if is_dir_mod else list(m[:-1])
        for kw, tail in re.findall(r"\b(crate|super|self)((?:::\w+)+)", text):
            parts = tail.strip(":").split("::")
            if kw == "crate":
                base = []
            elif kw == "self":
                base = list(m)
            else:
                base = here[:-1] if is_dir_mod else here
                while parts and parts[0] == "super":
                    parts = parts[1:]
                    base = base[:-1]
            # `use crate::a::{b, c}`: the brace part is not followed here; the prefix is.
            target = resolve(mods, base + parts)
            if target is not None and target != m and target != ():
                out[m].add(target)
        # Brace groups: `use crate::a::{b::X, c}`.
        for kw, head, group in re.findall(r"\b(crate|super)((?:::\w+)*)::\{([^}]*)\}", text):
            base = [] if kw == "crate" else (here[:-1] if is_dir_mod else here)
            head = [h for h in head.strip(":").split("::") if h]
            for item in group.split(","):
                item = item.strip().split(" as ")[0]
                if not item:
                    continue
                target = resolve(mods, base + head + item.split("::"))
                if target is not None and target != m and target != ():
                    out[m].add(target)
    return out

def related(a, b):
    """One module contains the other: a module and its children are one unit (a parent's
    `mod child;` and a child's `super::Item` are containment, not a circle)."""
    n = min(len(a), len(b))
    return a[:n] == b[:n]

def cycles(graph):
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(10000)
    def visit(v):
        index[v] = low[v] = counter[0]; counter[0] += 1
        stack.append(v); on.add(v)
        for w in graph[v]:
            if related(v, w):
                continue
            if w not in index:
                visit(w); low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop(); on.discard(w); comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))
    for v in graph:
        if v not in index:
            visit(v)
    return found

def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "crates"
    bad = 0
    for crate in sorted(os.listdir(root)):
        src = os.path.join(root, crate, "src")
        if not os.path.isdir(src):
            continue
        for comp in cycles(edges(module_files(src))):
            bad += 1
            print(f"{crate}: " + " <-> ".join("/".join(m) for m in comp))
    print(f"{bad} import circle(s)")
    sys.exit(1 if bad else 0)

main()
