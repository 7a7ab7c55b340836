#!/usr/bin/env python3
"""Lists import cycles between the modules of each crate of the workspace.

A module's edges are the `crate::` paths its file names (in `use` lines and
in code), each resolved to the module that defines the item: a name the crate
root re-exports (`pub use module::Name`) counts as that module's. Exits 1 when
a crate has a cycle, printing each strongly connected set of modules.
"""
import re
import sys
from pathlib import Path

ROOTS = ["src", "crates/bvol-volumes/src", "crates/bvol-tree/src", "crates/bvol-narrow/src", "crates/bvol-cli/src"]


def module_of(src: Path, path: Path) -> str:
    rel = path.relative_to(src).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "mod":
        parts.pop()
    if parts in (["lib"], ["main"]):
        return "crate"
    return "::".join(parts)


def reexports(lib: str) -> dict:
    """Names the crate root re-exports, mapped to their modules."""
    out = {}
    for m in re.finditer(r"pub(?:\(crate\))?\s+use\s+(\w+)::(\{[^;]*\}|\w+)\s*;", lib):
        module, names = m.group(1), m.group(2)
        for name in re.findall(r"\b(\w+)\b", names.strip("{}")):
            if name != "as":
                out[name] = module
    return out


def uses(text: str, modules: set, exported: dict) -> set:
    found = set()
    for m in re.finditer(r"crate::(\{[^;]*?\}|[\w:]+)", text):
        body = m.group(1)
        heads = re.findall(r"(?:^|[{,]\s*)(\w+)", body) if body.startswith("{") else [body.split("::")[0]]
        for head in heads:
            if head in modules:
                found.add(head)
            elif head in exported:
                found.add(exported[head])
    return found


def sccs(graph: dict) -> list:
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
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

    for v in list(graph):
        if v not in index:
            visit(v)
    return out


def main() -> int:
    root = Path(__file__).resolve().parent.parent
    bad = 0
    for r in ROOTS:
        src = root / r
        if not src.exists():
            continue
        files = [p for p in src.rglob("*.rs")]
        lib = (src / "lib.rs").read_text() if (src / "lib.rs").exists() else ""
        exported = reexports(lib)
        # Top-level modules: a nested module counts as its top module.
        tops = {module_of(src, p).split("::")[0] for p in files} - {"crate"}
        graph = {}
        for p in files:
            me = module_of(src, p).split("::")[0]
            if me == "crate":
                continue
            text = p.read_text()
            text = text.split("#[cfg(test)]")[0]
            # Doc links and comments name modules without depending on them.
            text = "\n".join(l for l in text.splitlines() if not l.lstrip().startswith("//"))
            graph.setdefault(me, set()).update(uses(text, tops, exported) - {me})
        for comp in sccs(graph):
            bad += 1
            print(f"{r}: cycle among {', '.join(comp)}")
            for a in comp:
                print(f"    {a} -> {', '.join(sorted(graph[a] & set(comp)))}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
