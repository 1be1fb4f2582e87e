#!/usr/bin/env python3
"""Import circles between the modules (files) of each crate: `crate::a::b` paths, `use super::`
and `use self::`, braced and glob imports, and bare paths to a child module (`child::f()`),
resolved to the file that defines what they name: `pub use` re-exports, globs too, are followed
(`super::Balancer` re-exported from `policy` is an edge to `policy`, not to the parent). A parent
and its children count as any two modules: a parent using a child's items while the child uses
items the parent defines is a circle. A module's `mod child;` and its tests (`#[cfg(test)] mod
tests`) are not edges. Prints each circle found and exits 1 when there is one.
Usage: tools/module_cycles.py [crates-dir]"""
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

REEXPORTS = {}

def resolve(mods, path, depth=0):
    """The module that defines what `path` names: the longest module prefix of `path` that is
    a file, followed through that module's `pub use` re-exports of the next name."""
    for n in range(len(path), -1, -1):
        if tuple(path[:n]) in mods:
            k = tuple(path[:n])
            if n < len(path) and depth < 8:
                table = REEXPORTS.get(k, {})
                target = table.get(path[n])
                if target is None:
                    # `pub use child::*`: the glob's module, when it defines the name.
                    for glob in table.get("*", []):
                        g = tuple(glob)
                        if g in mods and defines(mods[g], path[n]):
                            target = glob + [path[n]]
                            break
                if target is not None:
                    return resolve(mods, target + list(path[n + 1:]), depth + 1) or k
            return k
    return None

DEFINED = {}

def defines(path, name):
    """Whether the file at `path` defines a public item `name` (what a glob re-export carries)."""
    if path not in DEFINED:
        text = open(path).read()
        DEFINED[path] = set(re.findall(
            r"\bpub(?:\([\w ]+\))?\s+(?:unsafe\s+)?(?:struct|enum|fn|const|static|trait|type|mod|union)\s+(\w+)",
            text))
    return name in DEFINED[path]

def expand_use(tree):
    """`a::{b, c::{d, e as f}}` -> [(["a","b"], "b"), (["a","c","d"], "d"), (["a","c","e"], "f")]."""
    tree = re.sub(r"\s*(::|\{|\}|,)\s*", r"\1", tree.strip())
    def split_top(s):
        parts, depth, cur = [], 0, ""
        for ch in s:
            if ch == "," and depth == 0:
                parts.append(cur); cur = ""
                continue
            depth += ch == "{"; depth -= ch == "}"
            cur += ch
        if cur:
            parts.append(cur)
        return parts
    out = []
    def walk(prefix, s):
        i = s.find("{")
        if i < 0:
            m = re.fullmatch(r"([\w:*]+)(?:\s+as\s+(\w+))?", s.strip())
            path = [p for p in (m.group(1) if m else s).split("::") if p]
            if path:
                out.append((prefix + path, (m.group(2) if m and m.group(2) else path[-1])))
            return
        head = [p for p in s[:i].split("::") if p]
        inner = s[i + 1:s.rfind("}")]
        for part in split_top(inner):
            walk(prefix + head, part)
    walk([], tree)
    return out

def reexports(mods):
    """Each module's `pub use` names: name -> the absolute path it stands for."""
    for m, p in mods.items():
        text = re.sub(r"//[^\n]*", "", open(p).read())
        children = {k[len(m)] for k in mods if len(k) == len(m) + 1 and k[:len(m)] == m}
        table = {}
        for tree in re.findall(r"\bpub(?:\([\w ]+\))?\s+use\s+([^;]+);", text):
            for path, name in expand_use(tree):
                if name == "self":
                    continue
                if path[0] == "crate":
                    absolute = path[1:]
                elif path[0] == "self":
                    absolute = list(m) + path[1:]
                elif path[0] == "super":
                    base = list(m[:-1])
                    rest = path[1:]
                    while rest and rest[0] == "super":
                        rest = rest[1:]; base = base[:-1]
                    absolute = base + rest
                elif path[0] in children:
                    absolute = list(m) + path
                else:
                    continue
                if name == "*":
                    table.setdefault("*", []).append(absolute[:-1])
                else:
                    table[name] = absolute
        REEXPORTS[m] = table

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
        for kw, tail in re.findall(r"\b(crate|super|self)((?:::\w+)+)\b(?!::)", text):
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
            # A whole path only: `crate::a::{b, c}` (the brace groups below resolve each name)
            # and `crate::a::*` (below) are not edges to their prefixes.
            target = resolve(mods, base + parts)
            if target is not None and target != m and target != ():
                out[m].add(target)
        # Globs: `use crate::a::*` depends on a.
        for kw, tail in re.findall(r"\b(crate|super|self)((?:::\w+)+)::\*", text):
            parts = tail.strip(":").split("::")
            base = [] if kw == "crate" else (list(m) if kw == "self" else (here[:-1] if is_dir_mod else here))
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
        # Bare paths to a child module: `child::f()`, `use child::X;`, `pub use child::{X, Y}`.
        children = {k[len(m)] for k in mods if len(k) == len(m) + 1 and k[:len(m)] == m}
        for name, tail in re.findall(r"(?<![:\w])(\w+)((?:::\w+)*)::", text):
            if name in children:
                target = resolve(mods, list(m) + [name] + [t for t in tail.split("::") if t])
                if target is not None and target != m:
                    out[m].add(target)
        for name, group in re.findall(r"(?<![:\w])(\w+)::\{([^}]*)\}", text):
            if name in children:
                out[m].add(tuple(list(m) + [name]))
    return out

def cycles(graph):
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(10000)
    def visit(v):
        index[v] = low[v] = counter[0]; counter[0] += 1
        stack.append(v); on.add(v)
        for w in graph[v]:
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
        mods = module_files(src)
        REEXPORTS.clear()
        reexports(mods)
        for comp in cycles(edges(mods)):
            bad += 1
            print(f"{crate}: " + " <-> ".join("/".join(m) for m in comp))
    print(f"{bad} import circle(s)")
    sys.exit(1 if bad else 0)

main()
