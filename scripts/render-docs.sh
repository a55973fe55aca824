#!/usr/bin/env bash
# Renders every example scene (examples/*.sdf) into docs/images/ and writes docs/gallery.md,
# a table of the pictures with their scene files (run from anywhere; needs a wgpu device: a
# GPU, or Mesa's software Vulkan or GL). SIZE=WxH changes the picture size (default 320x240,
# modest enough for a software device).
set -euo pipefail
cd "$(dirname "$0")/.."
size="${SIZE:-320x240}"
cargo build --release -p sdfc-cli
sdfc="${CARGO_TARGET_DIR:-target}/release/sdfc"
mkdir -p docs/images
gallery=docs/gallery.md
{
    echo "# Gallery"
    echo
    echo "Every scene in \`examples/\`, rendered at $size by \`scripts/render-docs.sh\` (which"
    echo "regenerates this page and the pictures)."
    echo
    echo "| name | picture | scene |"
    echo "| --- | --- | --- |"
} > "$gallery.tmp"
for path in examples/*.sdf; do
    name="$(basename "$path" .sdf)"
    echo "rendering $name" >&2
    "$sdfc" render "$path" -o "docs/images/$name.png" --size "$size"
    # The scene's leading comment describes it: its lines joined, `|` escaped for the table.
    about="$(awk '!/^\/\//{exit} {sub(/^\/\/ */, ""); printf "%s ", $0}' "$path" | sed 's/ *$//; s/|/\\|/g')"
    echo "| **$name**: $about | ![$name](images/$name.png) | [\`$path\`](../$path) |" >> "$gallery.tmp"
done
mv "$gallery.tmp" "$gallery"
