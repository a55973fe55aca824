#!/usr/bin/env bash
# The figures that need a real GPU (issue 6: culling, specialised against interpreted, first
# pixel, tables, unions as data, relaxation's time) and the render tests on it, prepared here
# and run in one call on a machine lent through the device tool, which has no Rust toolchain
# and no network and whose device time is short (docs/performance.md, "Measuring on a GPU").
# Two steps:
#
#   scripts/gpu-bench.sh prepare
#       here, on a machine with cargo: builds the release `sdfc`, the three render benches,
#       the `compare_shader` example and the render tests (profile gpu-test, packed with xz),
#       strips them into `.gpu/` (ignored by git, about 45 MB), writes the table and data
#       experiments' grids, shaders and data (scripts/table-experiment.py,
#       scripts/bvh-experiment.py) and the culled grids there, and
#       downloads the Vulkan and EGL loaders' Debian packages into `.gl/` (ignored).
#   scripts/gpu-bench.sh run [SIZE]
#       there, from the repository's root, with `.gpu` and `.gl` carried:
#           run(command: "scripts/gpu-bench.sh run", carry: [".gpu", ".gl"], timeout_s: 580)
#       unpacks the loaders, then runs each measurement (ALL below, or those named in
#       SDFC_GPU_ONLY) under a time limit of its own. Their logs are packed into
#       $OUT/logs.tar (./gpu-out without OUT) after each one, beside summary.txt, which says
#       how each ended: the device tool brings back at most 8 files, and what is under $OUT
#       when a call runs out of time still comes back. SIZE (default 640x480) is the image
#       size of the render, culling and table benches: 160x120 is too few pixels to fill a
#       GPU.
#
# `scripts/gpu-bench.sh run` works on any machine with a wgpu device (lavapipe too, slowly),
# so it can be tried here before device time is spent: `SDFC_GPU_QUICK=1` shortens it, and
# `SDFC_GPU_TEST_LIMIT=5` cuts each test binary short (those cut count as failed).
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
    # The render tests (crates/sdfc-render/tests), optimised without LTO (profile gpu-test).
    rm -rf .gpu/tests && mkdir -p .gpu/tests
    cargo test -p sdfc-render --profile gpu-test --no-run --message-format=json \
        | python3 -c '
import json, sys, shutil
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["kind"] == ["test"]:
        shutil.copy(m["executable"], ".gpu/tests/" + m["target"]["name"])
'
    pwd >.gpu/tests.root
    find .gpu -type f -perm -u+x -exec strip {} +
    # 113 MB of test binaries share most of their code: xz packs them into 9 MB, which keeps
    # the carried tree under the device tool's 64 MiB.
    tar -cf - -C .gpu tests | xz -T2 -9 --lzma2=preset=9,dict=128MiB >.gpu/tests.tar.xz
    rm -rf .gpu/tests
    rm -f .gpu/grid*
    for n in 300 5000; do
        .gpu/compare_shader emit "$n" .gpu
        scripts/table-experiment.py ".gpu/grid$n.wgsl" ".gpu/grid$n-tables.wgsl"
        # Large unions as data: the divergent walks (a hierarchy per kind, leaves of 1; one
        # for all kinds, without and with the hint) and the coherent one (per kind, leaves of 4).
        local g=".gpu/grid$n-bvh"
        scripts/bvh-experiment.py ".gpu/grid$n.wgsl" "$g.wgsl" "$g.bin" 1
        scripts/bvh-experiment.py ".gpu/grid$n.wgsl" "$g-mix.wgsl" "$g-mix.bin" --mixed
        scripts/bvh-experiment.py ".gpu/grid$n.wgsl" "$g-hint.wgsl" "$g-hint.bin" --mixed --hint
        scripts/bvh-experiment.py ".gpu/grid$n.wgsl" "$g-sg.wgsl" "$g-sg.bin" 4 --subgroup
    done
    # Culling's own comparison: the close grid and the grid from the suite's camera, each
    # compiled with --cull (the camera is in the shader).
    sed 's/camera { position: \[2, 6, 12\], target: \[0, 3, -4\]/camera { position: [0, 20, 60], target: [0, 0, 0]/' \
        .gpu/grid300.sdf >.gpu/grid300-far.sdf
    cmp -s .gpu/grid300.sdf .gpu/grid300-far.sdf && { echo "the close grid's camera has changed" >&2; exit 1; }
    .gpu/sdfc compile --cull .gpu/grid300.sdf -o .gpu/grid300-cull.wgsl
    .gpu/sdfc compile --cull .gpu/grid300-far.sdf -o .gpu/grid300-far-cull.wgsl
    .gpu/sdfc compile .gpu/grid300-far.sdf -o .gpu/grid300-far.wgsl
    scripts/bvh-experiment.py .gpu/grid300-far.wgsl .gpu/grid300-far-bvh-hint.wgsl \
        .gpu/grid300-far-bvh-hint.bin --mixed --hint
    rm .gpu/grid300-far.wgsl
    # The marcher as one loop (refinement inside the stepping loop), the form before
    # 2026-12-04, for the marching scenes that still take two loops (a scene whose distance
    # is dear, as the terrain's and the fractals' now are, is marched in one loop already and
    # has no `refine` to call): `marcher_loops` times it against the two loops.
    rm -f .gpu/*-one-loop.wgsl
    for s in spec_section10 terrain fractals; do
        .gpu/sdfc compile "examples/$s.sdf" -o ".gpu/$s.wgsl"
        if grep -q '^fn refine(' ".gpu/$s.wgsl"; then
            scripts/swap-function.py ".gpu/$s.wgsl" march scripts/experiments/march_one_loop.wgsl \
                ".gpu/$s-one-loop.wgsl"
        fi
        rm ".gpu/$s.wgsl"
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

# Runs one step under a time limit, its output to $logs/NAME; records how it ended in
# $out/summary.txt and packs every log so far into $out/logs.tar. The device tool brings back
# at most 8 files, and what is under $out when a call runs out of time still comes back.
step() {
    local name="$1" limit="$2"
    shift 2
    local start=$SECONDS
    # The running step's log is under $out itself, so that a call cut short in it (the
    # 5 000-shape union's build outlasts any) still brings back what it printed.
    timeout "$limit" "$@" >"$out/running-$name" 2>&1
    local rc=$?
    local how="ok"
    [ "$rc" -eq 124 ] && how="timed out after ${limit}s"
    [ "$rc" -ne 0 ] && [ "$rc" -ne 124 ] && how="failed (exit $rc)"
    [ "$rc" -ne 0 ] && failures=$((failures + 1))
    echo "$name: $how, $((SECONDS - start)) s" | tee -a "$out/summary.txt"
    mv "$out/running-$name" "$logs/$name"
    # Written beside and renamed over, so that a call cut short here leaves a whole archive.
    tar -cf "$out/logs.tar.part" -C "$logs" . && mv "$out/logs.tar.part" "$out/logs.tar"
}

# Says in the summary why a measurement did not run.
skipped() {
    echo "$1: skipped, $2" | tee -a "$out/summary.txt"
}

# The render tests carried in .gpu/tests.tar.xz, each binary in turn (those named in
# SDFC_GPU_TESTS, else all), each with its own limit; CI=1 makes a test that finds no device
# fail instead of skipping.
render_tests() {
    local t dir rc failed=""
    dir="$(mktemp -d)"
    tar -xJf .gpu/tests.tar.xz -C "$dir"
    for t in "$dir"/tests/*; do
        if [ -n "${SDFC_GPU_TESTS:-}" ] && ! [[ " $SDFC_GPU_TESTS " == *" $(basename "$t") "* ]]; then
            continue
        fi
        echo "== $(basename "$t")"
        # --foreground keeps the binary in this step's process group, so that the step's
        # own limit ends it too rather than leaving it on the device beside the next step.
        # shellcheck disable=SC2086 # SDFC_GPU_TEST_ARGS is split into arguments on purpose
        CI=1 timeout --foreground "${SDFC_GPU_TEST_LIMIT:-60}" "$t" --test-threads 8 ${SDFC_GPU_TEST_ARGS:-} 2>&1 | grep -v '^test .* ok$'
        rc=${PIPESTATUS[0]}
        echo "== $(basename "$t"): exit $rc (124: out of time)"
        [ "$rc" -ne 0 ] && failed="$failed $(basename "$t")"
    done
    rm -rf "$dir"
    [ -z "$failed" ] || { echo "failed:$failed"; return 1; }
}

# Loaders and driver files, where the test binaries look for the repository, and $out/$logs.
setup() {
    out="${OUT:-gpu-out}"
    logs="$(mktemp -d)"
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
    # The test binaries find the repository where they were built.
    local built
    built="$(cat .gpu/tests.root 2>/dev/null)"
    if [ -n "$built" ] && [ ! -e "$built" ]; then
        mkdir -p "$(dirname "$built")" && ln -s "$PWD" "$built"
    fi
    export -f render_tests
}

# One measurement by name, under its own time limit. $size is the image size of the render,
# culling and table benches.
measure() {
    local quick="${SDFC_GPU_QUICK:-}" c=.gpu/compare_shader
    case "$1" in
        gpu)
            if command -v nvidia-smi >/dev/null; then step gpu.txt 15 nvidia-smi; else skipped gpu "no nvidia-smi"; fi ;;
        # The first render names the adapter; every later figure is on it.
        adapter) step adapter.txt 40 .gpu/sdfc render examples/spec_section10.sdf -o "$logs/spec_section10.png" --size "$size" ;;
        render) step render.log 90 .gpu/render none ;;
        # The reference is left out: the CPU takes minutes for it at this size (lavapipe's
        # runs of the bench measure it, and `instances` compares the forms' pictures).
        culling) SDFC_BENCH_REFERENCE=0 step culling.log 45 .gpu/culling none ;;
        # The 300-shape grid culled against plain, interleaved frames: from close by (every
        # ray among the shapes) and from the suite's camera (most rays miss the grid).
        culling_compare)
            step culling_close.log 40 $c compare .gpu/grid300.sdf .gpu/grid300-cull.wgsl "$size"
            step culling_far.log 40 $c compare .gpu/grid300-far.sdf .gpu/grid300-far-cull.wgsl "$size" ;;
        # Every suite scene, the specialised path against the live one (with and without grace).
        first_pixel) SDFC_BENCH_5000=0 step first_pixel.log 60 .gpu/first_pixel ;;
        # The 5 000-shape union's live path alone: its preview is printed as soon as it is
        # drawn, before the driver's build of the specialised pipeline, which can take minutes.
        first_pixel_5000)
            if [ -n "$quick" ]; then
                skipped first_pixel_5000 "quick run"
            else
                SDFC_BENCH_SCENES=grid_5000 SDFC_BENCH_LIVE_ONLY=1 step first_pixel_5000.log "${SDFC_GPU_5000_LIMIT:-240}" .gpu/first_pixel
            fi ;;
        render_tests)
            if [ -f .gpu/tests.tar.xz ]; then
                step render_tests.log 150 bash -c render_tests
            else
                skipped render_tests "no .gpu/tests.tar.xz"
            fi ;;
        tables_300) step tables_300.log 30 $c compare .gpu/grid300.sdf .gpu/grid300-tables.wgsl "$size" ;;
        # Large unions as data (scripts/bvh-experiment.py): the 300-shape grid's walks against
        # its code, from close by and (the hinted walk) from the suite's camera; the 5 000-shape
        # grid's other walks against its walk per kind (its code's build outlasts any call).
        bvh_300)
            local g=.gpu/grid300 w
            for w in hint mix sg; do
                step "bvh_300_$w.log" 30 $c compare $g.sdf "$g-bvh-$w.wgsl:$g-bvh-$w.bin" "$size"
            done
            step bvh_300.log 30 $c compare $g.sdf $g-bvh.wgsl:$g-bvh.bin "$size"
            step bvh_300_far.log 30 $c compare $g-far.sdf $g-far-bvh-hint.wgsl:$g-far-bvh-hint.bin "$size" ;;
        bvh_5000)
            local g=.gpu/grid5000 w
            for w in hint mix sg; do
                step "bvh_5000_$w.log" 40 $c compare $g.sdf "$g-bvh-$w.wgsl:$g-bvh-$w.bin" "$size" \
                    $g-bvh.wgsl:$g-bvh.bin
            done ;;
        # `--instances` (the union as data, built in): against the code on the 300-shape grid
        # from both cameras, against the experiment's hinted walk on the 5 000-shape grid.
        instances)
            local g=.gpu/grid300
            step instances_300.log 30 $c compare $g.sdf instances "$size"
            step instances_300_far.log 30 $c compare $g-far.sdf instances "$size"
            g=.gpu/grid5000
            step instances_5000.log 40 $c compare $g.sdf instances "$size" $g-bvh-hint.wgsl:$g-bvh-hint.bin ;;
        # The two-loop marcher ("own") against the one-loop form ("other"), same pictures.
        marcher_loops)
            local s
            for s in spec_section10 terrain fractals; do
                if [ -f ".gpu/$s-one-loop.wgsl" ]; then
                    step "marcher_loops_$s.log" 20 $c compare "examples/$s.sdf" ".gpu/$s-one-loop.wgsl" "$size"
                else
                    skipped "marcher_loops_$s" "marched in one loop already"
                fi
            done ;;
        tables_5000)
            if [ -n "$quick" ]; then
                skipped tables_5000 "quick run"
            else
                step tables_5000.log 60 $c compare .gpu/grid5000.sdf .gpu/grid5000-tables.wgsl "$size"
            fi ;;
        benches)
            # The quick run leaves out three of the four scenes.
            local s scenes="spec_section10 terrain fractals ribbed_sphere"
            [ -n "$quick" ] && scenes="ribbed_sphere"
            for s in $scenes; do
                step "bench_$s.md" 30 .gpu/sdfc bench "examples/$s.sdf" --size 320x240 --runs 5 --markdown
            done ;;
    esac
}

# All measurements, the slowest (the 5 000-shape union's) last. Their limits add up to about
# 20 minutes, more than one call may take (pick with SDFC_GPU_ONLY); on the H200 all but the
# last two took about four minutes before bvh_300 and bvh_5000 were added (25 s on lavapipe
# at 64x48), and first_pixel_5000 is cut short by design (its preview line comes first).
ALL="gpu adapter render culling culling_compare first_pixel render_tests tables_300 bvh_300 bvh_5000 instances marcher_loops benches tables_5000 first_pixel_5000"

# Runs the measurements; exits 1 if any failed or ran out of time (summary.txt says which).
run() {
    size="${1:-640x480}"
    local m
    # Every name is checked before any device time is spent.
    for m in ${SDFC_GPU_ONLY:-$ALL}; do
        [[ " $ALL " == *" $m "* ]] || { echo "no measurement $m (there are: $ALL)" >&2; exit 2; }
    done
    setup
    export SDFC_BENCH_SIZE="$size"
    failures=0
    for m in ${SDFC_GPU_ONLY:-$ALL}; do
        measure "$m"
    done
    [ "$failures" -eq 0 ]
}

case "${1:-}" in
    prepare) prepare ;;
    run) shift; run "$@" ;;
    *) echo "usage: scripts/gpu-bench.sh prepare | run [WxH]" >&2; exit 2 ;;
esac
