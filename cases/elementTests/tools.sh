# Shared by the run scripts of cases/elementTests: finds scree-element and the plot script.
#   SCREE_ELEMENT=/path/to/scree-element   (default: on PATH, else <repo>/build/bin)
#   PYTHON=/usr/bin/python3
here_tools="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here_tools/../.." && pwd)"
if [ -z "${SCREE_ELEMENT:-}" ]; then
  if command -v scree-element >/dev/null 2>&1; then
    SCREE_ELEMENT=scree-element
  elif [ -x "$repo/build/bin/scree-element" ]; then
    SCREE_ELEMENT="$repo/build/bin/scree-element"
  else
    echo "scree-element not found: build Scree (cmake -B build && cmake --build build)," \
         "put it on PATH or set SCREE_ELEMENT" >&2
    exit 1
  fi
fi
PYTHON="${PYTHON:-/usr/bin/python3}"
PLOT="$repo/utilities/scree-element/plot_element_test.py"
