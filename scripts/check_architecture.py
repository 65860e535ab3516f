#!/usr/bin/env python3
"""Checks docs/ARCHITECTURE.md against the code (issues 15 and 29).

- Folder A depends on folder B when a file of src/A has a line `#include "B/..."` or names one of
  B's types or functions: a name qualified by B's namespace (`gp::GpPosterior`, `render::Scene`,
  `using namespace matlas::gp`, `namespace matlas::pathtrace {`), or, for the types declared
  directly in `namespace matlas` (core, brdf, formats, manifold), a class, struct, union, enum or
  alias that a header of B defines there, matched as a whole word. Comments and string literals
  do not count. These dependencies must equal, exactly, the fenced `dependencies` block of
  docs/ARCHITECTURE.md: one `folder: dep dep ...` line per folder of src/. A dependency through
  types only (a type reached through another folder's header) is reported with file:line and the
  name, as it is easy to miss.
- The graph must have no cycles, between folders or between files.
- The link lists (`matlas_module(NAME DEPS ...)` and `target_link_libraries` of src/NAME/
  CMakeLists.txt, `matlas_lib` standing for its members) link only folders that src/NAME depends
  on, and reach every one of them, directly or through the libraries they link.
- The document's folder table must name every folder of src/ (`src/NAME`) and every top-level
  folder of the repository that holds tracked files (`NAME/`).
- No file in src/ may be longer than 500 lines.

Usage: scripts/check_architecture.py [--root REPO] [--self-test]. Prints each problem and exits 1
if there is one, else prints a one-line summary and exits 0. --self-test runs the checks on small
synthetic trees (one forbidden type use, one stray link, one clean) and exits 1 unless each is
judged as it should be.
"""
import argparse
import bisect
import os
import re
import subprocess
import sys
import tempfile

MAX_LINES = 500
SOURCE_SUFFIXES = (".h", ".hpp", ".cpp", ".cc", ".inl")
HEADER_SUFFIXES = (".h", ".hpp", ".inl")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
BLOCK = re.compile(r"^```dependencies\s*\n(.*?)^```", re.M | re.S)

# Comments, string and character literals, kept apart from numbers (digit separators: 1'000).
LEXEME = re.compile(
    r"""//[^\n]*"""
    r"""|/\*.*?\*/"""
    r"""|\bu?8?[LuU]?R"([^(\s"\\]{0,16})\((?:.*?)\)\1\""""
    r"""|"(?:\\.|[^"\\\n])*\""""
    r"""|\b\d[\w']*"""
    r"""|'(?:\\.|[^'\\\n])*'""",
    re.S)
# Scopes and type definitions of a header, in order.
SCOPE = re.compile(
    r"\bnamespace\s+([A-Za-z_][\w:]*)?\s*\{"
    r"|\b(?:class|struct|union|enum(?:\s+(?:class|struct))?)\s+(?:alignas\s*\([^)]*\)\s*)?"
    r"(?:\[\[[^\]]*\]\]\s*)?([A-Za-z_]\w*)\s*(?:final\s*)?(?:[:{](?!:))"
    r"|\busing\s+([A-Za-z_]\w*)\s*(?:\[\[[^\]]*\]\]\s*)?=(?!=)"
    r"|([{}])")
# A name with its qualifiers: matlas::gp::GpPosterior, ::matlas::Model, Model::Options.
QUALIFIED = re.compile(r"(?<![\w.])(?<!->)(::\s*)?((?:[A-Za-z_]\w*\s*::\s*)*)([A-Za-z_]\w*)")
NAMESPACE_KEYWORD = re.compile(r"\bnamespace\s*$")
IGNORED_NAMESPACES = {"detail", "std", "fs"}


def source_files(src):
    for root, dirs, files in os.walk(src):
        dirs.sort()
        for name in sorted(files):
            yield os.path.relpath(os.path.join(root, name), src)


def strip_code(text):
    """The text with comments, string and character literals blanked, lines kept in place."""
    def blank(m):
        s = m.group(0)
        if s[0].isdigit():
            return s
        quote = '""' if '"' in s and not s.startswith(("/", "'")) else " "
        return quote + "\n" * s.count("\n")
    return LEXEME.sub(blank, text)


def read_sources(src):
    """{rel: (raw text, stripped text)} of every source file under a folder of src/."""
    out = {}
    for rel in source_files(src):
        if os.sep in rel and rel.endswith(SOURCE_SUFFIXES):
            with open(os.path.join(src, rel), encoding="utf-8", errors="replace") as f:
                raw = f.read()
            out[rel] = (raw, strip_code(raw))
    return out


def include_graph(src, sources):
    """(folder graph, file graph) of src/: {folder: set(folders)}, {file: set(files)}."""
    folders = {}
    files = {}
    for rel in source_files(src):
        if os.sep in rel:  # not src/CMakeLists.txt
            folders.setdefault(rel.split(os.sep)[0], set())
    for rel, (raw, _) in sources.items():
        folder = rel.split(os.sep)[0]
        targets = files.setdefault(rel, set())
        for line in raw.splitlines():
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


def declarations(sources):
    """What each folder declares: (namespaces {name: set(folders) opening it inside matlas},
    plain types {name: set(folders) defining it in namespace matlas in a header},
    all types {folder: set(names of every type it defines, at any scope)})."""
    namespaces, plain, every = {}, {}, {}
    for rel, (_, code) in sources.items():
        folder = rel.split(os.sep)[0]
        mine = every.setdefault(folder, set())
        stack = []  # one entry per open brace: the namespace path it opens, or None
        for m in SCOPE.finditer(code):
            ns, typename, alias, brace = m.groups()
            path = [p for s in stack if s for p in s] if all(stack) else None
            if m.group(0).startswith("namespace"):
                parts = ns.split("::") if ns else ["(anonymous)"]
                if path is not None:
                    full = path + parts
                    if full[0] == "matlas" and len(full) > 1:
                        namespaces.setdefault(full[1], set()).add(folder)
                stack.append(parts)
            elif typename or alias:
                name = typename or alias
                if typename and m.group(0).rstrip().endswith("{"):
                    stack.append(None)
                if alias and path is None:
                    continue  # an alias inside a class or function
                mine.add(name)
                if path == ["matlas"] and rel.endswith(HEADER_SUFFIXES):
                    plain.setdefault(name, set()).add(folder)
            elif brace == "{":
                stack.append(None)
            elif stack:
                stack.pop()
    return namespaces, plain, every


def owners(folders, namespaces, plain):
    """({namespace: folder}, {plain type: folder}, problems): a namespace belongs to the folder of its
    name, else to the one folder that opens it; a plain type to the one folder that defines it."""
    ns_owner, type_owner, problems = {}, {}, []
    for name, openers in namespaces.items():
        if name in folders:
            ns_owner[name] = name
        elif len(openers) == 1 and name not in IGNORED_NAMESPACES:
            ns_owner[name] = next(iter(openers))
    for name, definers in sorted(plain.items()):
        if len(definers) == 1:
            type_owner[name] = next(iter(definers))
        else:
            problems.append(f"matlas::{name} is defined by the headers of several folders: "
                            f"{' '.join(sorted(definers))}")
    return ns_owner, type_owner, problems


def type_uses(sources, ns_owner, type_owner, every):
    """{(folder, dep): [(rel, line, name)]}: the names of folder dep used by files of folder."""
    uses = {}
    for rel, (_, code) in sources.items():
        folder = rel.split(os.sep)[0]
        own = every.get(folder, set())
        starts = [0] + [i + 1 for i, c in enumerate(code) if c == "\n"]
        for m in QUALIFIED.finditer(code):
            rooted, quals, last = m.groups()
            parts = [p.strip() for p in quals.split("::") if p.strip()] + [last]
            qualified_by_matlas = parts[0] == "matlas"
            if qualified_by_matlas:
                parts = parts[1:]
                if not parts:
                    continue
            first = parts[0]
            dep = None
            if first in ns_owner and (len(parts) > 1 or qualified_by_matlas or
                                      NAMESPACE_KEYWORD.search(code, max(0, m.start() - 20), m.start())):
                dep = ns_owner[first]
            elif first in type_owner and (qualified_by_matlas or rooted or first not in own):
                dep = type_owner[first]
            if dep is None or dep == folder:
                continue
            line = bisect.bisect_right(starts, m.start())
            name = "::".join((["matlas"] if qualified_by_matlas else []) + parts)
            uses.setdefault((folder, dep), []).append((rel, line, name))
    return uses


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


CMAKE_CALL = re.compile(r"\b(matlas_module|target_link_libraries|add_library)\s*\(([^)]*)\)", re.S)


def link_graph(src, folders):
    """{folder: set(folders its targets link)} from src/*/CMakeLists.txt, `matlas_lib` (an INTERFACE
    library of src/CMakeLists.txt) expanded to its members; the folders without a CMakeLists.txt are
    left out."""
    def calls(path):
        if not os.path.isfile(path):
            return []
        with open(path, encoding="utf-8") as f:
            text = re.sub(r"#[^\n]*", "", f.read())
        return [(m.group(1), m.group(2).split()) for m in CMAKE_CALL.finditer(text)]

    groups = {}  # INTERFACE libraries named matlas_X that are not folders, e.g. matlas_lib
    for name, args in calls(os.path.join(src, "CMakeLists.txt")):
        if name == "target_link_libraries" and args and args[0].startswith("matlas_"):
            groups.setdefault(args[0][len("matlas_"):], set()).update(
                a[len("matlas_"):] for a in args[1:] if a.startswith("matlas_"))

    def expand(lib, seen=()):
        if lib in folders:
            return {lib}
        out = set()
        for member in groups.get(lib, ()):
            if member not in seen:
                out |= expand(member, seen + (lib,))
        return out

    links = {}
    for folder in folders:
        path = os.path.join(src, folder, "CMakeLists.txt")
        if not os.path.isfile(path):
            continue
        linked = links.setdefault(folder, set())
        for name, args in calls(path):
            if name == "add_library" or not args:
                continue
            if name == "matlas_module":
                libs = args[args.index("DEPS") + 1:] if "DEPS" in args else []
            else:
                libs = args[1:]
            for lib in libs:
                if lib.startswith("matlas_") and lib != "matlas_options":
                    linked |= expand(lib[len("matlas_"):])
        linked.discard(folder)
    return links


def reachable(links, start):
    seen, todo = set(), list(links.get(start, ()))
    while todo:
        f = todo.pop()
        if f not in seen:
            seen.add(f)
            todo.extend(links.get(f, ()))
    return seen


def top_level_folders(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True, check=True).stdout
        names = {p.split("/")[0] for p in out.splitlines() if "/" in p}
    except (OSError, subprocess.CalledProcessError):
        names = set()
    if not names:
        names = {n for n in os.listdir(root) if os.path.isdir(os.path.join(root, n))}
        names = {n for n in names if not n.startswith("build")}
    return sorted(n for n in names if not n.startswith("."))


def check(root):
    problems = []
    src = os.path.join(root, "src")
    doc_path = os.path.join(root, "docs", "ARCHITECTURE.md")
    with open(doc_path, encoding="utf-8") as f:
        doc = f.read()

    sources = read_sources(src)
    includes, file_graph = include_graph(src, sources)
    namespaces, plain, every = declarations(sources)
    ns_owner, type_owner, owner_problems = owners(includes, namespaces, plain)
    problems += owner_problems
    uses = type_uses(sources, ns_owner, type_owner, every)
    actual = {folder: set(deps) for folder, deps in includes.items()}
    for folder, dep in uses:
        actual[folder].add(dep)

    def type_evidence(folder, dep, limit=3):
        found = uses.get((folder, dep), [])
        first = {}
        for rel, line, name in found:
            first.setdefault((rel, name), (line, 0))
            first[(rel, name)] = (first[(rel, name)][0], first[(rel, name)][1] + 1)
        shown = [f"src/{rel}:{line}: {name}" + (f" (and {n - 1} more lines)" if n > 1 else "")
                 for (rel, name), (line, n) in sorted(first.items(), key=lambda kv: (kv[0][0], kv[1][0]))]
        more = f"; and {len(shown) - limit} more names" if len(shown) > limit else ""
        return shown[:limit], more

    documented = documented_graph(doc)
    if isinstance(documented, str):
        problems.append(f"docs/ARCHITECTURE.md: {documented}")
    else:
        for folder in sorted(set(actual) | set(documented)):
            if folder not in documented:
                problems.append(f"src/{folder} is missing from the dependencies block "
                                f"(it depends on: {' '.join(sorted(actual[folder])) or 'nothing'})")
            elif folder not in actual:
                problems.append(f"the dependencies block lists '{folder}', which is not a folder of src/")
            else:
                for dep in sorted(actual[folder] - documented[folder]):
                    if dep in includes[folder]:
                        problems.append(f"src/{folder} includes {dep}/ but the dependencies block does not say so")
                    else:
                        shown, more = type_evidence(folder, dep)
                        for s in shown:
                            problems.append(f"{s}: names a type or function of src/{dep}, but the edge "
                                            f"{folder} -> {dep} is not in the dependencies block")
                        if more:
                            problems.append(f"src/{folder} -> {dep}{more}")
                for dep in sorted(documented[folder] - actual[folder]):
                    problems.append(f"the dependencies block says {folder} depends on {dep}/, but no file of "
                                    f"src/{folder} includes it or names its types")
    cycle = find_cycle(actual)
    if cycle:
        problems.append("folder dependency cycle: " + " -> ".join(cycle))
        for a, b in zip(cycle, cycle[1:]):
            if b not in includes.get(a, ()):
                shown, _ = type_evidence(a, b, 1)
                problems.append(f"  ({a} -> {b} by its types: {shown[0]})")
    cycle = find_cycle(file_graph)
    if cycle:
        problems.append("file include cycle: " + " -> ".join(cycle))

    links = link_graph(src, actual)
    for folder in sorted(links):
        for dep in sorted(links[folder] - actual[folder]):
            problems.append(f"src/{folder}/CMakeLists.txt links matlas_{dep}, but src/{folder} neither includes "
                            f"{dep}/ nor names its types")
        missing = actual[folder] - reachable(links, folder)
        for dep in sorted(missing):
            problems.append(f"src/{folder} depends on {dep}/, but src/{folder}/CMakeLists.txt links neither "
                            f"matlas_{dep} nor a library that links it")

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
    stats = {"folders": len(actual), "edges": sum(len(d) for d in actual.values()),
             "type_only": sum(1 for (f, d) in uses if d not in includes[f])}
    return problems, stats


SELF_TEST_DOC = """# Architecture
| `src/core` | | `src/gp` | | `src/manifold` | | `src/server` | | `docs/` | |
```dependencies
core:
gp: core
manifold: gp
server: core manifold{extra}
```
"""
SELF_TEST_FILES = {
    "core/error.h": "#pragma once\nnamespace matlas {\nclass Error {};\nusing Seconds = double;\n}\n",
    "gp/posterior.h": ('#pragma once\n#include "core/error.h"\nnamespace matlas::gp {\nstruct GpPosterior {};\n'
                       "struct ModelView {};\n{gpuse}\n}}\n"),
    "manifold/model.h": ('#pragma once\n#include "gp/posterior.h"\nnamespace matlas {\n'
                         "class Model {\n public:\n  const gp::GpPosterior& posterior() const;\n};\n}\n"),
    "server/api.cpp": ('#include "manifold/model.h"\n// gp::GpPosterior in a comment does not count\n'
                       'namespace matlas::server {\nconst char* s = "gp::GpPosterior";\n'
                       "Seconds t = 1'000; const char* r = R\"x(gp::GpPosterior)x\";\n{use}\n}}\n"),
    "core/CMakeLists.txt": "matlas_module(core DEPS Threads::Threads)\n",
    "gp/CMakeLists.txt": "matlas_module(gp DEPS matlas_core)\n",
    "manifold/CMakeLists.txt": "matlas_module(manifold DEPS matlas_gp)\n",
    "server/CMakeLists.txt": "matlas_module(server DEPS matlas_manifold{link})\n",
}


def self_test():
    """Runs check() on synthetic trees; returns the number of failed cases."""
    cases = [
        # (name, use in server/api.cpp, extra server deps, extra server links, expected substrings);
        # a use given as "gp: ..." is written in gp/posterior.h instead.
        ("clean", "int n = sizeof(Model);", "", "", []),
        ("whole words only", "gp: ModelView v; int Models = 0;", "", "", []),
        ("cycle through types", "gp: const matlas::Model* m = nullptr;", "", "",
         ["src/gp/posterior.h:6: matlas::Model: names a type or function of src/manifold, but the edge "
          "gp -> manifold is not in the dependencies block",
          "folder dependency cycle: gp -> manifold -> gp"]),
        ("forbidden type use", "double f(const Model& m) { const gp::GpPosterior& p = m.posterior(); }", "", "",
         ["src/server/api.cpp:6: gp::GpPosterior: names a type or function of src/gp, but the edge "
          "server -> gp is not in the dependencies block"]),
        ("documented type use", "double f(const Model& m) { const gp::GpPosterior& p = m.posterior(); }", " gp",
         "", []),
        ("stray link", "int n = sizeof(Model);", "", " matlas_gp",
         ["src/server/CMakeLists.txt links matlas_gp, but src/server neither includes gp/ nor names its types"]),
        ("using directive", "using namespace matlas::gp;", "", "", ["matlas::gp: names a type or function of src/gp"]),
    ]
    failures = 0
    for name, use, extra, link, expected in cases:
        with tempfile.TemporaryDirectory(prefix="check_architecture.") as root:
            os.makedirs(os.path.join(root, "docs"))
            with open(os.path.join(root, "docs", "ARCHITECTURE.md"), "w") as f:
                f.write(SELF_TEST_DOC.replace("{extra}", extra))
            for rel, text in SELF_TEST_FILES.items():
                os.makedirs(os.path.join(root, "src", os.path.dirname(rel)), exist_ok=True)
                with open(os.path.join(root, "src", rel), "w") as f:
                    in_gp = use.startswith("gp: ")
                    f.write(text.replace("{use}", "" if in_gp else use).replace("{gpuse}", use[4:] if in_gp else "")
                            .replace("{link}", link).replace("}}", "}"))
            problems, _ = check(root)
        ok = all(any(e in p for p in problems) for e in expected) and (problems if expected else not problems)
        print(f"check_architecture --self-test: {name}: {'ok' if ok else 'FAILED'}")
        if not ok:
            failures += 1
            print(f"  expected: {expected}\n  reported: {problems}", file=sys.stderr)
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    default_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--root", default=default_root, help="repository root (default: this script's)")
    parser.add_argument("--self-test", action="store_true", help="check the checker on synthetic trees")
    args = parser.parse_args()
    if args.self_test:
        return 1 if self_test() else 0
    problems, stats = check(args.root)
    for p in problems:
        print(f"check_architecture: {p}", file=sys.stderr)
    if problems:
        return 1
    print(f"check_architecture: {stats['folders']} folders, {stats['edges']} folder dependencies "
          f"({stats['type_only']} through types only), as documented and linked; no cycles; "
          f"no file in src/ over {MAX_LINES} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main())
