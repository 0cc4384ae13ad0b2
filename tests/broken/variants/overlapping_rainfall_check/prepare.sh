# The case of overlapping_rainfall, checked instead of run.
. "$(dirname "$0")/../overlapping_rainfall/prepare.sh"
