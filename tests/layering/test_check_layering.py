#!/usr/bin/env python3
"""A test of the layering check (check_layering.py) on small fixture trees: a tree that
keeps the rule passes; a back-include (by scree/<folder>/ or by a relative path), a folder
missing from the README's table, and an allowance that no longer matches each fail, naming
the file and line."""
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
README = """# A fixture

Inside `framework/`, a folder includes only folders below it in this list, never one above:

| folder | holds |
| --- | --- |
| `top/` | the top |
| `middle/` | the middle |
| `low/`, `base/` | one level |
"""
failures = []
roots = []


def tree(files):
    root = tempfile.mkdtemp(prefix="scree_layering_")
    roots.append(root)
    files = dict({"README.md": README,
                  "framework/include/scree/top/a.hpp": '#include "scree/middle/b.hpp"\n',
                  "framework/include/scree/middle/b.hpp": '#include "scree/low/c.hpp"\n#include <vector>\n',
                  "framework/include/scree/low/c.hpp": '#include "scree/base/d.hpp"\n',
                  "framework/include/scree/base/d.hpp": '#include "scree/low/c.hpp"\n',
                  "framework/src/middle/b.cpp": '#include "scree/middle/b.hpp"\n#include "../low/e.hpp"\n',
                  "framework/src/low/e.hpp": "\n"}, **files)
    for rel, text in files.items():
        path = os.path.join(root, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text)
    return root


def expect(what, files, status, text="", args=()):
    r = subprocess.run([sys.executable, os.path.join(HERE, "check_layering.py"), "--root", tree(files), *args],
                       capture_output=True, text=True)
    if r.returncode != status or text not in r.stdout:
        failures.append(f"{what}: expected status {status} and {text!r}, got {r.returncode}:\n{r.stdout}{r.stderr}")


expect("a tree that keeps the rule", {}, 0, "every framework folder includes only folders below it")
expect("a header including a folder above it",
       {"framework/include/scree/low/c.hpp": '#include <cmath>\n#include "scree/middle/b.hpp"\n'}, 1,
       "framework/include/scree/low/c.hpp:2: includes scree/middle/b.hpp: low/ may not include middle/")
expect("a source implementing a header of a folder above it",
       {"framework/src/base/f.cpp": '#include "scree/top/a.hpp"\n'}, 1,
       "framework/src/base/f.cpp:1: includes scree/top/a.hpp: base/ may not include top/")
expect("a relative back-include", {"framework/src/low/g.cpp": '#include "../middle/b.cpp"\n'}, 1,
       "framework/src/low/g.cpp:1: includes ../middle/b.cpp: low/ may not include middle/")
expect("a folder missing from the table", {"framework/include/scree/extra/x.hpp": "\n"}, 1,
       "framework folder 'extra/' is not in the README's layering table")
expect("a known break allowed", {"framework/include/scree/low/c.hpp": '#include "scree/top/a.hpp"\n'}, 0,
       args=("--allow", "include/scree/low/c.hpp:top"))
expect("an allowance that no longer matches", {}, 1,
       "framework/include/scree/low/c.hpp no longer includes top/", args=("--allow", "include/scree/low/c.hpp:top"))

for root in roots:
    shutil.rmtree(root, ignore_errors=True)
for f in failures:
    print("FAIL:", f)
print(f"{7 - len(failures)} of 7 fixture checks passed")
sys.exit(1 if failures else 0)
