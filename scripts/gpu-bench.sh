#!/usr/bin/env bash
# The performance figures that need a real GPU (issue 6: culling, specialised against
# interpreted, first pixel, relaxation's time), in one prepared run for a session that is lent
# a GPU machine through the device tool, whose device time is short and which has no Rust
# toolchain and no network. Two steps:
#
#   scripts/gpu-bench.sh prepare
#       here, on a machine with cargo: builds the release `sdfc`, the three render benches and
#       the `compare_shader` example, strips them into `.gpu/` (ignored by git, about 35 MB),
#       writes the table experiment's grids and shaders there (scripts/table-experiment.py),
#       and downloads the Vulkan and EGL loaders' Debian packages into `.gl/` (ignored), which
#       the GPU machine may lack.
#   scripts/gpu-bench.sh run [SIZE]
#       there, from the repository's root, with `.gpu` and `.gl` carried:
#           run(command: "scripts/gpu-bench.sh run", carry: [".gpu", ".gl"], timeout_s: 580)
#       unpacks the loaders, then runs each measurement under a time limit of its own and
#       writes its log to $OUT (./gpu-out without it): render.log (specialised against
#       interpreted, per suite scene), culling.log, first_pixel.log (with the 5 000-shape
#       union), tables_300.log and tables_5000.log (a large union as code against as tables
#       and loops), bench_*.md (`sdfc bench`: time against error, relaxation among the
#       settings) and adapter.txt. SIZE (default 640x480) is the image size of the render,
#       culling and table benches: 160x120 is too few pixels to fill a GPU. Each step that
#       fails or runs out of time says so in summary.txt, and the others still run. The steps'
#       limits add up to more than the call's: the last steps are the first to go, and the
#       logs of those that ran still come back.
#
# `scripts/gpu-bench.sh run` works on any machine with a wgpu device (lavapipe too, slowly),
# so it can be tried here before device time is spent: `SDFC_GPU_QUICK=1` shortens it.
set -uo pipefail
cd "$(dirname "$0")/.."

prepare() {
    set -e
    mkdir -p .gpu
    cargo build --release -p sdfc-cli
    cp target/release/sdfc .gpu/sdfc
    # The bench executables, by name, from cargo's own report of what it built.
    cargo bench -p sdfc-render --no-run --message-format=json \
        | python3 -c '
import json, sys, shutil
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and "bench" in m["target"]["kind"]:
        shutil.copy(m["executable"], ".gpu/" + m["target"]["name"])
        print(".gpu/" + m["target"]["name"])
'
    cargo build --release -p sdfc-render --example compare_shader
    cp target/release/examples/compare_shader .gpu/compare_shader
    rm -f .gpu/grid*
    strip .gpu/*
    for n in 300 5000; do
        .gpu/compare_shader emit "$n" .gpu
        scripts/table-experiment.py ".gpu/grid$n.wgsl" ".gpu/grid$n-tables.wgsl"
    done
    du -sh .gpu
    if command -v apt-get >/dev/null 2>&1; then
        # The device tool's advice: x86-64 packages of the loaders, unpacked there.
        local o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
        mkdir -p .gl /tmp/amd64/partial
        # shellcheck disable=SC2086
        apt-get $o update -qq
        # shellcheck disable=SC2086
        (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
    fi
    echo "ready: run scripts/gpu-bench.sh run with carry [\".gpu\", \".gl\"]"
}

# Runs one step under a time limit, its output to $out/NAME; records how it ended.
step() {
    local name="$1" limit="$2"
    shift 2
    local start=$SECONDS
    timeout "$limit" "$@" >"$out/$name" 2>&1
    local rc=$?
    local how="ok"
    [ "$rc" -eq 124 ] && how="timed out after ${limit}s"
    [ "$rc" -ne 0 ] && [ "$rc" -ne 124 ] && how="failed (exit $rc)"
    echo "$name: $how, $((SECONDS - start)) s" | tee -a "$out/summary.txt"
}

run() {
    local size="${1:-640x480}"
    out="${OUT:-gpu-out}"
    mkdir -p "$out"
    : >"$out/summary.txt"
    [ -x .gpu/sdfc ] || { echo "no .gpu/sdfc: run scripts/gpu-bench.sh prepare first, and carry .gpu" >&2; exit 2; }
    if [ -d .gl ] && ! ldconfig -p 2>/dev/null | grep -q libvulkan.so.1; then
        for f in .gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    fi
    # NVIDIA's driver files where the loader does not look for them by itself.
    local icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
    [ -f "$icd" ] && export VK_DRIVER_FILES="${VK_DRIVER_FILES:-$icd}"
    local egl=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
    [ -f "$egl" ] && export __EGL_VENDOR_LIBRARY_FILENAMES="${__EGL_VENDOR_LIBRARY_FILENAMES:-$egl}"
    export SDFC_BENCH_SIZE="$size"
    local quick="${SDFC_GPU_QUICK:-}"
    # The first render names the adapter; every later figure is on it.
    step adapter.txt 60 .gpu/sdfc render examples/spec_section10.sdf -o "$out/spec_section10.png" --size "$size"
    step render.log 120 .gpu/render none
    step culling.log 60 .gpu/culling none
    step tables_300.log 45 .gpu/compare_shader compare .gpu/grid300.sdf .gpu/grid300-tables.wgsl "$size"
    # The quick run leaves out the 5 000-shape union and three of the four scenes.
    local big=1 scenes="spec_section10 terrain fractals ribbed_sphere"
    [ -n "$quick" ] && big=0 scenes="ribbed_sphere"
    SDFC_BENCH_5000=$big step first_pixel.log 150 .gpu/first_pixel
    [ -z "$quick" ] && step tables_5000.log 75 .gpu/compare_shader compare .gpu/grid5000.sdf .gpu/grid5000-tables.wgsl "$size"
    for s in $scenes; do
        step "bench_$s.md" 40 .gpu/sdfc bench "examples/$s.sdf" --size 320x240 --runs 5 --markdown
    done
}

case "${1:-}" in
    prepare) prepare ;;
    run) shift; run "$@" ;;
    *) echo "usage: scripts/gpu-bench.sh prepare | run [WxH]" >&2; exit 2 ;;
esac
