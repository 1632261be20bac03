#!/usr/bin/env bash
# Render SCENE at SPP samples per pixel as M slices on Slurm and merge them into OUT.exr:
#   scripts/slurm/submit.sh SCENE SPP M OUTDIR OUT.exr [--wait] [-- more render flags]
# The merge job depends on the whole array (--dependency=afterok). With --wait this script
# blocks until the merge has finished and exits with its status. SPECTRACE names the binary
# (default: spectrace on PATH); it must be reachable from the compute nodes, as must OUTDIR.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
SCENE="$1"; SPP="$2"; M="$3"; OUTDIR="$4"; OUT="$5"; shift 5
WAIT=()
if [ "${1:-}" = "--wait" ]; then WAIT=(--wait); shift; fi
if [ "${1:-}" = "--" ]; then shift; fi
mkdir -p "$OUTDIR"
export SLICES="$M"
ARRAY=$(sbatch --parsable --export=ALL --chdir="$OUTDIR" --array="1-$M" \
    "$HERE/render-array.sbatch" "$SCENE" "$SPP" "$OUTDIR" "$@")
ARRAY="${ARRAY%%;*}"
echo "submitted slice array $ARRAY (1-$M)"
MERGE=$(sbatch --parsable --export=ALL --chdir="$OUTDIR" --dependency="afterok:$ARRAY" \
    --kill-on-invalid-dep=yes "${WAIT[@]}" "$HERE/merge.sbatch" "$OUTDIR" "$OUT")
echo "merge job ${MERGE%%;*} (after $ARRAY) writes $OUT"
