#!/usr/bin/env bash
# The figures of docs/plugins.md, "An API-only plugin matches the built-ins" (run from the
# repository root): scenes with the built-in rough conductor and spot light against the same
# scenes with plugins/api-only's `api_conductor` and `api_spot`, BDPT, 32 spp, seed 1 for both,
# and a seed-2 plugin render for the noise level; the ΔE00 maps and `spectrace compare` figures.
set -euo pipefail
cargo build --release -p spectrace -p spectrace-api-only
st=target/release/spectrace
lib=target/release/libspectrace_api_only.so
out=docs/figures/api-only
tmp=$(mktemp -d)
for pair in "cornell scenes/api_only/cornell_box.ron scenes/api_only/cornell_box_plugin.ron" \
            "materials scenes/materials.ron scenes/api_only/materials_plugin.ron"; do
    set -- $pair
    name=$1
    "$st" render "$2" --spp 32 --seed 1 --quiet -o "$tmp/$name-builtin.exr" --png "$out/$name-builtin.png"
    "$st" render "$3" --plugin "$lib" --spp 32 --seed 1 --quiet -o "$tmp/$name-plugin.exr" --png "$out/$name-plugin.png"
    "$st" render "$3" --plugin "$lib" --spp 32 --seed 2 --quiet -o "$tmp/$name-plugin-seed2.exr" --png "$tmp/x.png"
    {
        echo "same seed (1), plugin against built in:"
        "$st" compare "$tmp/$name-plugin.exr" "$tmp/$name-builtin.exr" --diff "$out/$name-delta-e.png"
        echo "independent seeds (plugin 2, built in 1): the noise level"
        "$st" compare "$tmp/$name-plugin-seed2.exr" "$tmp/$name-builtin.exr" --diff "$out/$name-delta-e-seed2.png"
    } | sed "s#$tmp/##g" | tee "$out/$name-compare.txt"
done
rm -r "$tmp"
