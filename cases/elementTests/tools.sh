# Shared by the run scripts of cases/elementTests: finds scree-element and the plot script.
#   SCREE_ELEMENT=/path/to/scree-element   (default: on PATH, else <repo>/build/bin)
#   PYTHON=/usr/bin/python3
#   SCREE_PLOT=/path/to/plot_element_test.py   (default: beside scree-element, else <repo>/utilities)
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
# The plot script: SCREE_PLOT, else installed beside scree-element, else in the source tree
# these tests came from; without one the runs still write their CSVs.
PLOT="${SCREE_PLOT:-}"
if [ -z "$PLOT" ]; then
  for candidate in "$(dirname "$(command -v "$SCREE_ELEMENT")")/plot_element_test.py" \
                   "$repo/utilities/scree-element/plot_element_test.py"; do
    if [ -f "$candidate" ]; then PLOT="$candidate"; break; fi
  done
fi
# plot ARGS...: plot_element_test.py ARGS, or say where the CSVs are when it is not found.
plot() {
  if [ -n "$PLOT" ]; then
    "$PYTHON" "$PLOT" "$@"
  else
    echo "plot_element_test.py not found (set SCREE_PLOT to it): no figure; the results are in output/" >&2
  fi
}
