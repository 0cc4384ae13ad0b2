#!/usr/bin/env python3
"""The framework's layering rule, checked: a folder of framework/ (include/scree/<folder>
for headers, src/<folder> for their code) includes only folders below it in the README's
table, never one above.

    check_layering.py [--root REPO] [--allow FILE:FOLDER ...]

The order is read from the README's table that follows the sentence "a folder includes
only folders below it in this list, never one above" (first column: the folders of a row,
each as `name/`; folders of one row are on one level and may include each other), so the
rule and its check cannot drift apart: a new folder must be added to that table, or this
check fails naming it. Both `#include "scree/<folder>/..."` and relative includes
(`#include "../<folder>/..."`, resolved against the including file) count.

--allow FILE:FOLDER accepts one known break, FILE (relative to framework/) including
FOLDER, until it is fixed; an allowance that no longer matches any include is an error too,
so that it is removed with the break.

Exit status 0 when no file includes a folder above its own; 1 with each break listed as
file:line: the include, and the two folders' rows.
"""
import argparse
import os
import re
import sys

RULE = "a folder includes only folders below it in this list, never one above"
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')
SOURCES = (".hpp", ".h", ".cpp", ".cu", ".cuh", ".inl")


def read_order(readme):
    """{folder: row index} from the README's layering table (row 0 is the top)."""
    with open(readme, encoding="utf-8") as f:
        lines = f.read().splitlines()
    start = next((i for i, line in enumerate(lines) if RULE in line), None)
    if start is None:
        raise SystemExit(f"{readme}: no sentence '{RULE}' followed by the framework's table")
    rows = []
    i = start + 1
    while i < len(lines) and not lines[i].startswith("|"):
        i += 1
    while i < len(lines) and lines[i].startswith("|"):
        first = lines[i].split("|")[1]
        names = re.findall(r"`([A-Za-z0-9_]+)/`", first)
        if names:  # the header and separator rows name no folder
            rows.append(names)
        i += 1
    if not rows:
        raise SystemExit(f"{readme}:{start + 1}: the layering table after this line lists no `folder/`")
    return {name: r for r, names in enumerate(rows) for name in names}


def folder_of(path, framework):
    """The framework folder holding `path` (include/scree/<f>/... or src/<f>/...), or None."""
    rel = os.path.relpath(os.path.normpath(path), framework).split(os.sep)
    if len(rel) >= 4 and rel[0] == "include" and rel[1] == "scree":
        return rel[2]
    if len(rel) >= 3 and rel[0] == "src":
        return rel[1]
    return None


def included_folder(target, including_file, framework):
    """The framework folder an include names, or None (a system or third-party header)."""
    if target.startswith("scree/"):
        parts = target.split("/")
        return parts[1] if len(parts) >= 3 else None
    resolved = os.path.join(os.path.dirname(including_file), target)
    if os.path.exists(resolved):
        return folder_of(resolved, framework)
    return None


def check(root, allow):
    framework = os.path.join(root, "framework")
    order = read_order(os.path.join(root, "README.md"))
    problems, used = [], set()
    folders = set()
    for top in (os.path.join(framework, "include", "scree"), os.path.join(framework, "src")):
        if os.path.isdir(top):
            folders.update(d for d in os.listdir(top) if os.path.isdir(os.path.join(top, d)))
    for f in sorted(folders - set(order)):
        problems.append(f"framework folder '{f}/' is not in the README's layering table: add its row "
                        f"where it belongs in the order")
    for top in (os.path.join(framework, "include", "scree"), os.path.join(framework, "src")):
        for dirpath, _, files in sorted(os.walk(top)):
            for name in sorted(files):
                if not name.endswith(SOURCES):
                    continue
                path = os.path.join(dirpath, name)
                own = folder_of(path, framework)
                if own not in order:
                    continue
                rel = os.path.relpath(path, framework)
                with open(path, encoding="utf-8", errors="replace") as f:
                    for lineno, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        other = included_folder(m.group(1), path, framework)
                        if other is None or other == own or other not in order or order[other] >= order[own]:
                            continue
                        if (rel, other) in allow:
                            used.add((rel, other))
                            continue
                        problems.append(f"framework/{rel}:{lineno}: includes {m.group(1)}: {own}/ may not include "
                                        f"{other}/, a folder above it in the README's layering table")
    for rel, other in sorted(allow - used):
        problems.append(f"--allow {rel}:{other}: framework/{rel} no longer includes {other}/; remove the allowance")
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    ap.add_argument("--allow", action="append", default=[], metavar="FILE:FOLDER")
    a = ap.parse_args()
    allow = set()
    for item in a.allow:
        rel, _, other = item.rpartition(":")
        allow.add((rel, other))
    problems = check(a.root, allow)
    for p in problems:
        print(p)
    if problems:
        print(f"layering: {len(problems)} break(s) of the rule '{RULE}' (README.md, Layout)")
        return 1
    print("layering: every framework folder includes only folders below it")
    return 0


if __name__ == "__main__":
    sys.exit(main())
