#!/usr/bin/env python3
"""The source tree's two shape rules (docs/building.md, "Layout"), checked from the files:

1. No include cycle between the folders of engine/src: a file of folder A that includes
   "B/x.hpp" makes A depend on B; the folders' graph must have no cycle (a folder's own files may
   include each other). A cycle is printed with one include per edge that makes it.
2. No source file over 800 lines in engine/, tools/, bench/ and tests/ (C, C++, Python, CMake,
   shell; the test data under tests/data is not source).
3. docs/building.md's layout map names every folder of engine/src ("engine/src/NAME/").

    check_source_layout.py ROOT    exit 0: both hold; 1: each breach printed, one per line.
"""
import os
import re
import sys

MAX_LINES = 800
SOURCE_SUFFIXES = ('.c', '.h', '.cpp', '.hpp', '.py', '.cmake', '.sh', 'CMakeLists.txt')
INCLUDE = re.compile(r'\s*#\s*include\s+"([^"/]+)/[^"]+"')


def folder_graph(src):
    """{folder: {included folder: 'file:line' of the first include that makes the edge}}."""
    graph = {}
    for folder in sorted(os.listdir(src)):
        path = os.path.join(src, folder)
        if not os.path.isdir(path):
            continue
        edges = graph.setdefault(folder, {})
        for dirpath, _, files in sorted(os.walk(path)):
            for name in sorted(files):
                if not name.endswith(('.c', '.h', '.cpp', '.hpp')):
                    continue
                file = os.path.join(dirpath, name)
                with open(file, encoding='utf-8', errors='replace') as f:
                    for number, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if m and m.group(1) != folder and os.path.isdir(os.path.join(src, m.group(1))):
                            edges.setdefault(m.group(1), f'{os.path.relpath(file, src)}:{number}')
    return graph


def cycles(graph):
    """The strongly connected components of more than one folder (Tarjan), each sorted."""
    index, low, stack, on_stack, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, {})):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def long_files(root):
    for top in ('engine', 'tools', 'bench', 'tests'):
        for dirpath, dirs, files in os.walk(os.path.join(root, top)):
            dirs[:] = sorted(d for d in dirs if not (top == 'tests' and d == 'data') and d != 'node_modules')
            for name in sorted(files):
                file = os.path.join(dirpath, name)
                is_script = os.access(file, os.X_OK) and '.' not in name
                if not (name.endswith(SOURCE_SUFFIXES) or is_script):
                    continue
                with open(file, 'rb') as f:
                    lines = f.read().count(b'\n')
                if lines > MAX_LINES:
                    yield os.path.relpath(file, root), lines


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1].strip(), file=sys.stderr)
        return 2
    root = sys.argv[1]
    graph = folder_graph(os.path.join(root, 'engine', 'src'))
    breaches = 0
    for component in cycles(graph):
        breaches += 1
        members = set(component)
        edges = [f'{a} -> {b} ({graph[a][b]})' for a in component for b in sorted(graph[a]) if b in members]
        print(f'include cycle between engine/src folders {", ".join(component)}: ' + '; '.join(edges))
    with open(os.path.join(root, 'docs', 'building.md'), encoding='utf-8') as f:
        building = f.read()
    for folder in sorted(graph):
        if f'engine/src/{folder}/' not in building:
            breaches += 1
            print(f'docs/building.md: the layout map does not show engine/src/{folder}/')
    for file, lines in long_files(root):
        breaches += 1
        print(f'{file}: {lines} lines (at most {MAX_LINES})')
    if breaches == 0:
        print(f'{len(graph)} folders of engine/src include each other without a cycle and are in '
              f'docs/building.md; no source file over {MAX_LINES} lines')
    return 1 if breaches else 0


if __name__ == '__main__':
    sys.exit(main())
