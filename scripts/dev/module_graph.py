#!/usr/bin/env python3
"""The module diagram of docs/architecture.md, generated from the CMake modules.

Reads every graftnav_add_module(<name> DEPS ...) call in core/, filters/, graph/ and apps/
CMakeLists.txt, and the graftnav_* libraries the `graftnav` executable links, and writes the
block between the "module graph" markers of docs/architecture.md: one row per module with its
level (0: links no other module; else one more than its highest dependency) and the modules it
links directly.

    python3 scripts/dev/module_graph.py [REPO]           # exit 1 when the page differs (a CTest)
    python3 scripts/dev/module_graph.py [REPO] --write   # rewrite the block
"""
import re
import sys
from pathlib import Path

BEGIN = "<!-- module graph: written by scripts/dev/module_graph.py from the CMake modules -->"
END = "<!-- end of module graph -->"
KEYWORDS = {"DEPS", "ROOT", "PUBLIC_LIBS", "PRIVATE_LIBS", "TEST_LIBS"}


def calls(text, function):
    """The argument lists of every call of `function` in a CMake file (comments dropped)."""
    text = re.sub(r"#[^\n]*", "", text)
    for m in re.finditer(r"\b" + re.escape(function) + r"\s*\(", text):
        depth, i = 1, m.end()
        while depth:
            depth += {"(": 1, ")": -1}.get(text[i], 0)
            i += 1
        yield text[m.end():i - 1].split()


def folder_of(cmake_dir, name):
    top = cmake_dir.name
    if top == "core":
        return "core/" + name
    if top == "apps":
        return "apps/" + name
    return top


def modules(repo):
    """name -> (folder, [dependency names])."""
    found = {}
    for d in ("core", "filters", "graph", "apps"):
        text = (repo / d / "CMakeLists.txt").read_text()
        for args in calls(text, "graftnav_add_module"):
            name, deps, key = args[0], [], None
            for a in args[1:]:
                if a in KEYWORDS:
                    key = a
                elif key == "DEPS":
                    deps.append(a)
            found[name] = (folder_of(repo / d, name), deps)
    core_all = []
    for args in calls((repo / "core" / "CMakeLists.txt").read_text(), "target_link_libraries"):
        if args[0] == "graftnav_core":
            core_all = [a[len("graftnav_"):] for a in args[2:] if a.startswith("graftnav_")]
    for args in calls((repo / "apps" / "CMakeLists.txt").read_text(), "target_link_libraries"):
        if args[0] == "graftnav":
            deps = []
            for a in args[2:]:
                if a == "graftnav_core":
                    deps += [m for m in core_all if m not in deps]
                elif a.startswith("graftnav_") and a != "graftnav_warnings":
                    deps.append(a[len("graftnav_"):])
            found["graftnav"] = ("apps (the graftnav command)", deps)
    return found


def block(found):
    level = {}

    def lvl(n):
        if n not in level:
            level[n] = 0
            level[n] = 1 + max((lvl(d) for d in found[n][1]), default=-1)
        return level[n]

    for n in found:
        lvl(n)
    rows = sorted(found, key=lambda n: (level[n], found[n][0]))
    width = max(len(found[n][0]) for n in rows)
    lines = [BEGIN, "```", f"{'level':<6} {'module':<{width}}  links (CMake DEPS)"]
    for n in rows:
        folder, deps = found[n]
        names = ", ".join(found[d][0] for d in sorted(deps, key=lambda d: (level[d], found[d][0])))
        names = names or "-"
        lines.append(f"{level[n]:<6} {folder:<{width}}  {names}")
    lines += ["```", END]
    return "\n".join(lines)


def main(argv):
    write = "--write" in argv
    args = [a for a in argv if a != "--write"]
    repo = Path(args[0]) if args else Path(__file__).resolve().parents[2]
    page = repo / "docs" / "architecture.md"
    text = page.read_text()
    if BEGIN not in text or END not in text:
        print(f"{page}: no module graph markers", file=sys.stderr)
        return 1
    a, b = text.index(BEGIN), text.index(END) + len(END)
    new = text[:a] + block(modules(repo)) + text[b:]
    if write:
        page.write_text(new)
        return 0
    if new != text:
        print(f"{page}: the module graph differs from the CMake modules; the generated one:")
        print(block(modules(repo)))
        print("(python3 scripts/dev/module_graph.py --write)")
        return 1
    print("module_graph: docs/architecture.md matches the CMake modules")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
