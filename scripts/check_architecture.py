#!/usr/bin/env python3
"""Checks docs/ARCHITECTURE.md against the code (issue 15).

- The folder-level include graph of src/ (folder A depends on folder B when a file of src/A has a
  line `#include "B/..."`) must equal, exactly, the fenced `dependencies` block of
  docs/ARCHITECTURE.md: one `folder: dep dep ...` line per folder of src/.
- The graph must have no cycles, between folders or between files.
- The document's folder table must name every folder of src/ (`src/NAME`) and every top-level
  folder of the repository that holds tracked files (`NAME/`).
- No file in src/ may be longer than 500 lines.

Usage: scripts/check_architecture.py [--root REPO]. Prints each problem and exits 1 if there is
one, else prints a one-line summary and exits 0.
"""
import argparse
import os
import re
import subprocess
import sys

MAX_LINES = 500
SOURCE_SUFFIXES = (".h", ".hpp", ".cpp", ".cc", ".inl")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
BLOCK = re.compile(r"^```dependencies\s*\n(.*?)^```", re.M | re.S)


def source_files(src):
    for root, dirs, files in os.walk(src):
        dirs.sort()
        for name in sorted(files):
            yield os.path.relpath(os.path.join(root, name), src)


def include_graph(src):
    """(folder graph, file graph) of src/: {folder: set(folders)}, {file: set(files)}."""
    folders = {}
    files = {}
    for rel in source_files(src):
        folder = rel.split(os.sep)[0]
        if os.sep not in rel:
            continue  # src/CMakeLists.txt
        folders.setdefault(folder, set())
        if not rel.endswith(SOURCE_SUFFIXES):
            continue
        targets = files.setdefault(rel, set())
        with open(os.path.join(src, rel), encoding="utf-8") as f:
            for line in f:
                m = INCLUDE.match(line)
                if not m or "/" not in m.group(1):
                    continue
                target = m.group(1)
                dep = target.split("/")[0]
                if not os.path.isdir(os.path.join(src, dep)):
                    continue  # not a folder of src/ (e.g. a system header written with quotes)
                targets.add(os.path.normpath(target))
                if dep != folder:
                    folders[folder].add(dep)
    return folders, files


def documented_graph(text):
    """The `dependencies` block as {folder: set(deps)}, or an error string."""
    blocks = BLOCK.findall(text)
    if len(blocks) != 1:
        return f"expected one ```dependencies block, found {len(blocks)}"
    graph = {}
    for number, line in enumerate(blocks[0].splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        if ":" not in line:
            return f"dependencies block line {number}: expected 'folder: deps', got '{line}'"
        folder, deps = line.split(":", 1)
        folder = folder.strip()
        if folder in graph:
            return f"dependencies block line {number}: '{folder}' is listed twice"
        graph[folder] = set(deps.split())
    return graph


def find_cycle(graph):
    """One cycle of the graph as a list of nodes, or None."""
    state = {}
    stack = []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                cycle = visit(nxt)
                if cycle:
                    return cycle
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


def top_level_folders(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True, check=True).stdout
        names = {p.split("/")[0] for p in out.splitlines() if "/" in p}
    except (OSError, subprocess.CalledProcessError):
        names = {n for n in os.listdir(root) if os.path.isdir(os.path.join(root, n))}
        names = {n for n in names if not n.startswith("build")}
    return sorted(n for n in names if not n.startswith("."))


def check(root):
    problems = []
    src = os.path.join(root, "src")
    doc_path = os.path.join(root, "docs", "ARCHITECTURE.md")
    with open(doc_path, encoding="utf-8") as f:
        doc = f.read()

    actual, file_graph = include_graph(src)
    documented = documented_graph(doc)
    if isinstance(documented, str):
        problems.append(f"docs/ARCHITECTURE.md: {documented}")
    else:
        for folder in sorted(set(actual) | set(documented)):
            if folder not in documented:
                problems.append(f"src/{folder} is missing from the dependencies block "
                                f"(it includes: {' '.join(sorted(actual[folder])) or 'nothing'})")
            elif folder not in actual:
                problems.append(f"the dependencies block lists '{folder}', which is not a folder of src/")
            else:
                for dep in sorted(actual[folder] - documented[folder]):
                    problems.append(f"src/{folder} includes {dep}/ but the dependencies block does not say so")
                for dep in sorted(documented[folder] - actual[folder]):
                    problems.append(f"the dependencies block says {folder} includes {dep}/, but no file of "
                                    f"src/{folder} does")
    cycle = find_cycle(actual)
    if cycle:
        problems.append("folder include cycle: " + " -> ".join(cycle))
    cycle = find_cycle(file_graph)
    if cycle:
        problems.append("file include cycle: " + " -> ".join(cycle))

    for folder in sorted(actual):
        if f"`src/{folder}`" not in doc:
            problems.append(f"docs/ARCHITECTURE.md's table does not describe `src/{folder}`")
    for folder in top_level_folders(root):
        if folder != "src" and f"`{folder}/`" not in doc:
            problems.append(f"docs/ARCHITECTURE.md's table does not describe `{folder}/`")

    for rel in source_files(src):
        path = os.path.join(src, rel)
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = sum(1 for _ in f)
        if lines > MAX_LINES:
            problems.append(f"src/{rel}: {lines} lines (at most {MAX_LINES})")
    return problems, actual


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    default_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--root", default=default_root, help="repository root (default: this script's)")
    args = parser.parse_args()
    problems, graph = check(args.root)
    for p in problems:
        print(f"check_architecture: {p}", file=sys.stderr)
    if problems:
        return 1
    edges = sum(len(d) for d in graph.values())
    print(f"check_architecture: {len(graph)} folders, {edges} folder dependencies, as documented; "
          f"no cycles; no file in src/ over {MAX_LINES} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main())
