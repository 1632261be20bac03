#!/usr/bin/env bash
# Regenerates every figure and table of docs/accuracy.md (run from the repository root):
#   bash docs/figures/regenerate.sh [BUDGET_SECONDS_PER_CONFIGURATION]   (default 30)
# 15 configurations × BUDGET per run, three runs (≈ 20 minutes at the default on 2 cores), plus ≈ 8 minutes
# for the caustic's BDPT reference when its state file is absent (a fresh clone). Timings depend on
# the machine's load: run it on an otherwise idle machine.
set -euo pipefail
budget="${1:-30}"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-target}"
cargo build --release -p spectrace
st="$CARGO_TARGET_DIR/release/spectrace"
ref=host/data/reference

# Cornell box against the independent Mitsuba 3 reference (10,240 spp).
"$st" bench accuracy --reference "$ref/cbox_reference_mitsuba.exr" \
    --budget "$budget" --out docs/figures/cornell
"$st" render --spp 64 --integrator pt -o docs/figures/cornell/pt_64spp.exr --quiet
"$st" compare docs/figures/cornell/pt_64spp.exr "$ref/cbox_reference_mitsuba.exr" \
    --exclude-light --diff docs/figures/cornell/pt_64spp_delta_e.png

# Caustic scene. The benchmark's reference is spectrace's BDPT at 16,384 spp (seeded, resumable):
# it is far less noisy in the caustic than the independent Mitsuba path-traced reference
# ($ref/caustic_reference_mitsuba.exr, 161,792 spp), which checks it (printed below and in
# docs/accuracy.md) rather than serving as the yardstick.
mkdir -p docs/figures/caustic
"$st" reference scenes/caustic.ron --integrator bdpt --spp 16384 --pass-spp 256 \
    -o docs/figures/caustic/reference_bdpt_16384spp.exr
"$st" compare docs/figures/caustic/reference_bdpt_16384spp.exr "$ref/caustic_reference_mitsuba.exr" \
    --exclude-light | tee docs/figures/caustic/reference_vs_mitsuba.txt
# Judged where the caustic is: pixels that show the glass ball are left out (sub-pixel images of
# the lamp in the ball dominate any whole-image error for thousands of samples); the whole-image
# run follows for comparison.
"$st" bench accuracy scenes/caustic.ron --reference docs/figures/caustic/reference_bdpt_16384spp.exr \
    --budget "$budget" --exclude-specular --target-rmse 0.002 --out docs/figures/caustic
"$st" bench accuracy scenes/caustic.ron --reference docs/figures/caustic/reference_bdpt_16384spp.exr \
    --budget "$budget" --out docs/figures/caustic/whole_image
