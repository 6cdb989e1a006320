#!/bin/bash
# Renders a scene on a Slurm cluster: a job array of SHARES tasks, each rendering one share of
# the samples with `raydiance render --part auto`, and a merge job that starts when all of them
# succeeded (sbatch --dependency=afterok). Prints the two job ids.
#
#   deploy/slurm/submit.sh SCENE OUT SHARES [--frames F0..F1] [-- RENDER OPTIONS...]
#
# With --frames the array has (frames x SHARES) tasks: task t renders share t mod SHARES of
# frame F0 + t / SHARES (SHARES=1: one whole frame a task). OUT must be a folder every node
# sees. RAYDIANCE names the binary (default: raydiance on the PATH); SBATCH_ARGS adds sbatch
# options to both jobs (e.g. "--partition=render --time=2:00:00").
# To render only missing shares again (merge names them): RESUME="2,5" submit.sh ... : the array
# is then just those shares, each told its share explicitly.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
if [ $# -lt 3 ]; then
  sed -n '2,14p' "$0" >&2
  exit 2
fi
scene=$(realpath "$1") out=$(realpath -m "$2") shares=$3
shift 3
frames=""
if [ "${1:-}" = "--frames" ]; then
  frames=$2
  shift 2
fi
if [ "${1:-}" = "--" ]; then
  shift
fi
case "$shares" in
  '' | *[!0-9]* | 0) echo "submit.sh: SHARES must be a whole number of at least 1, not '$shares'" >&2; exit 2 ;;
esac
tasks=$shares
if [ -n "$frames" ]; then
  tasks=$((shares * (${frames#*..} - ${frames%..*} + 1)))
fi
array="0-$((tasks - 1))"
explicit=""
if [ -n "${RESUME:-}" ]; then
  if [ -n "$frames" ]; then
    echo "submit.sh: RESUME renders shares of one image; for frames, merge names the shares to render" >&2
    exit 2
  fi
  array=$RESUME
  explicit=$shares
fi
mkdir -p "$out"
raydiance=$(command -v "${RAYDIANCE:-raydiance}" || true)
if [ -z "$raydiance" ]; then
  echo "submit.sh: no raydiance binary: set RAYDIANCE (e.g. target/release/raydiance)" >&2
  exit 2
fi
export RAYDIANCE=$raydiance SCENE=$scene OUT=$out FRAMES=$frames SHARES=$explicit
export RENDER_ARGS="$*"
# shellcheck disable=SC2086 # SBATCH_ARGS is a list of options
render=$(sbatch --parsable ${SBATCH_ARGS:-} --array="$array" --output="$out/render-%a.log" \
  "$here/render-array.sbatch")
render=${render%%;*}
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_ARGS:-} --dependency="afterok:$render" \
  --output="$out/merge.log" "$here/merge.sbatch")
merge=${merge%%;*}
echo "$render $merge"
