#!/usr/bin/env bash
# Renders the README's pictures from the example scenes (run from anywhere; needs a wgpu
# device: a GPU, or Mesa's software Vulkan or GL).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p sdfc-cli
mkdir -p docs/images
for scene in spec_section10 blob_floor primitives fractals; do
    ./target/release/sdfc render "examples/$scene.sdf" -o "docs/images/$scene.png" --size 480x320
done
