#!/usr/bin/env bash
# Regenerates every figure and table of docs/accuracy.md (run from the repository root):
#   bash docs/figures/regenerate.sh [BUDGET_SECONDS_PER_CONFIGURATION]   (default 60)
# About 6 configurations × BUDGET per scene plus ~3 minutes for the caustic reference on
# 2 cores. Timings depend on the machine's load; run it on an otherwise idle machine.
set -euo pipefail
budget="${1:-60}"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-target}"
cargo build --release -p spectrace
st="$CARGO_TARGET_DIR/release/spectrace"

# Cornell box against the independent Mitsuba 3 reference (10,240 spp, host/data/reference/).
"$st" bench accuracy --reference host/data/reference/cbox_reference_mitsuba.exr \
    --budget "$budget" --out docs/figures/cornell
"$st" render --spp 64 --integrator pt -o docs/figures/cornell/pt_64spp.exr --quiet
"$st" compare docs/figures/cornell/pt_64spp.exr host/data/reference/cbox_reference_mitsuba.exr \
    --exclude-light --diff docs/figures/cornell/pt_64spp_delta_e.png

mkdir -p docs/figures/caustic
# Caustic scene: no independent reference exists, so spectrace's own BDPT at 2048 spp (seeded,
# so the same every time; resumable if stopped) is the reference.
"$st" reference scenes/caustic.ron --integrator bdpt --spp 2048 --pass-spp 64 \
    -o docs/figures/caustic/reference_bdpt_2048spp.exr
"$st" bench accuracy scenes/caustic.ron --reference docs/figures/caustic/reference_bdpt_2048spp.exr \
    --budget "$budget" --out docs/figures/caustic
