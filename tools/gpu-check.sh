#!/usr/bin/env bash
# GPU check for a bare machine with a Vulkan driver but no build tools, no network and no Vulkan
# loader (the NVIDIA machine that some sessions borrow; see README "GPU").
#
#   tools/gpu-check.sh pack DIR   builds here (Release, ./build) and writes DIR/vpsim-gpu-check.tar.gz
#                                 (stripped test and benchmark binaries, the vpsim CLI, the shared
#                                 libraries a bare image lacks, the Vulkan loader's Debian package,
#                                 the validation layer, the data the tests read) and DIR/gpu-check.sh;
#                                 fails if DIR holds more than GPU_CHECK_MAX_MIB (64) MiB
#   tools/gpu-check.sh run DIR    unpacks DIR's archive into a private prefix, points the loader at
#                                 the NVIDIA ICD (or any other driver found), runs the [gpu] tests
#                                 under the validation layer and the benchmarks that matter (photon
#                                 MC, both exposure engines CPU vs shader, pipeline, the 20 mm
#                                 block) with short settings, four example jobs with --backend cpu
#                                 and vulkan side by side, and prints one JSON summary (also
#                                 DIR/summary.json);
#                                 each step has a time limit (359 s in all) so the whole run stays
#                                 under 6 minutes; a step cut off reports rc 124 and no output
#
# The run step works on any x86-64 Linux with a Vulkan driver (here: lavapipe).
set -euo pipefail

usage() {
    echo "usage: $0 pack DIR | run DIR" >&2
    exit 2
}
[[ $# -eq 2 ]] || usage
mode="$1"
dir="$2"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
max_mib="${GPU_CHECK_MAX_MIB:-64}"

binaries=(tests/test_gpu tests/test_exposure tests/test_transport benchmarks/bench_photon_mc
    benchmarks/bench_exposure benchmarks/bench_pipeline vpsim)

pack() {
    local build="$root/build"
    cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DVPSIM_BUILD_TESTS=ON \
        -DVPSIM_BUILD_BENCHMARKS=ON >/dev/null
    local targets=()
    for b in "${binaries[@]}"; do
        [[ "$b" == vpsim ]] && b=vpsim_cli  # the CLI's target (its binary is vpsim)
        targets+=(--target "$(basename "$b")")
    done
    cmake --build "$build" -j "${GPU_CHECK_JOBS:-2}" "${targets[@]}"
    # PLplot's drivers for the figures (svg, cairo) and its palettes and fonts: read through
    # PLPLOT_DRV_DIR and PLPLOT_LIB there.
    local drvdir plplot_drivers=()
    drvdir="$(pkg-config --variable=drvdir plplot)"
    plplot_drivers=("$drvdir/svg.so" "$drvdir/cairo.so")
    local stage
    stage="$(mktemp -d)"
    trap 'rm -rf "$stage"' RETURN
    mkdir -p "$stage/bin" "$stage/lib" "$stage/lib-fallback" "$stage/deb" "$stage/layers" \
        "$stage/src" "$stage/plplot/drivers"
    cp "$drvdir"/{svg,cairo}.{so,driver_info} "$stage/plplot/drivers/"
    cp -r "/usr/share/$(basename "$(dirname "$drvdir")")" "$stage/plplot/data"  # plplot5.15.0
    for b in "${binaries[@]}"; do
        strip -o "$stage/bin/$(basename "$b")" "$build/$b"
    done
    # Shared libraries: everything ldd names except glibc's own and the Vulkan loader (from its
    # package); libstdc++/libgcc_s only as a fallback for an image without them.
    local lib name
    while read -r lib; do
        name="$(basename "$lib")"
        case "$name" in
            libc.so* | libm.so* | libmvec.so* | libpthread.so* | libdl.so* | librt.so* | ld-linux*) ;;
            libvulkan.so*) ;;
            libstdc++.so* | libgcc_s.so*) cp -L "$lib" "$stage/lib-fallback/$name" ;;
            *) cp -L "$lib" "$stage/lib/$name" ;;
        esac
    done < <(for b in "${binaries[@]}" "${plplot_drivers[@]}"; do ldd "$build/$b" 2>/dev/null ||
        ldd "$b"; done | awk '$2 == "=>" && $3 ~ /^\// {print $3}' | sort -u)
    strip --strip-unneeded "$stage"/lib/*.so* "$stage"/lib-fallback/*.so* 2>/dev/null || true
    # The Vulkan loader as Debian ships it (unpacked with dpkg -x there), with the GL vendor-neutral
    # dispatch libraries that NVIDIA's ICD (libGLX_nvidia.so.0) loads; the installed loader if apt
    # cannot download.
    (cd "$stage/deb" && apt-get download libglvnd0 libglx0 libgl1 libegl1 libopengl0 libgles2 \
        >/dev/null 2>&1) || echo "gpu-check: apt-get download of the GL dispatch libraries failed" >&2
    if ! (cd "$stage/deb" && apt-get download libvulkan1 >/dev/null 2>&1); then
        echo "gpu-check: apt-get download libvulkan1 failed; packing the installed loader" >&2
        cp -L /lib/x86_64-linux-gnu/libvulkan.so.1 "$stage/lib/libvulkan.so.1"
    fi
    # The validation layer (the [gpu] tests run under it and fail on any message).
    local layer=/usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so
    if [[ -f "$layer" ]]; then
        strip --strip-unneeded -o "$stage/layers/libVkLayer_khronos_validation.so" "$layer"
        sed 's#"library_path": *"[^"]*"#"library_path": "./libVkLayer_khronos_validation.so"#' \
            /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json \
            >"$stage/layers/VkLayer_khronos_validation.json"
    else
        echo "gpu-check: no validation layer here (vulkan-validationlayers); [gpu] tests will fail" >&2
    fi
    # Data the tests and benchmarks read through VPSIM_SOURCE_DIR (compiled in) or the cwd.
    (cd "$root" && cp -r --parents examples tests/data benchmarks/jobs "$stage/src/")
    echo "$root" >"$stage/source_dir"
    git -C "$root" rev-parse --short HEAD >"$stage/commit" 2>/dev/null || echo unknown >"$stage/commit"
    mkdir -p "$dir"
    tar -C "$stage" -czf "$dir/vpsim-gpu-check.tar.gz" .
    cp "$root/tools/gpu-check.sh" "$dir/gpu-check.sh"
    local bytes
    bytes=$(du -sb "$dir" | cut -f1)
    local mib=$(((bytes + 1048575) / 1048576))
    echo "gpu-check: packed $(du -sb "$stage" | cut -f1) bytes into $dir: $bytes bytes ($mib MiB)"
    if ((bytes > max_mib * 1048576)); then
        echo "gpu-check: error: $dir is $mib MiB, over the ${max_mib} MiB that may travel" >&2
        exit 1
    fi
}

# Runs "$@" with a time limit, output to $results/NAME.out; records the exit status.
step() {
    local name="$1" limit="$2"
    shift 2
    local start=$SECONDS rc=0
    (cd "$prefix/src" && timeout "$limit" "$@") </dev/null >"$results/$name.out" \
        2>"$results/$name.err" || rc=$?
    echo "$rc" >"$results/$name.rc"
    echo "$((SECONDS - start))" >"$results/$name.seconds"
    echo "gpu-check: $name rc=$rc in $((SECONDS - start)) s" >&2
}

run() {
    [[ -f "$dir/vpsim-gpu-check.tar.gz" ]] || {
        echo "gpu-check: $dir/vpsim-gpu-check.tar.gz not found: run '$0 pack $dir' first" >&2
        exit 1
    }
    dir="$(cd "$dir" && pwd)"
    prefix="$(mktemp -d /tmp/vpsim-gpu-check.XXXXXX)"
    results="$prefix/results"
    mkdir -p "$results"
    tar -C "$prefix" -xzf "$dir/vpsim-gpu-check.tar.gz"
    # The loader, in a private prefix.
    for deb in "$prefix"/deb/*.deb; do
        [[ -f "$deb" ]] && dpkg -x "$deb" "$prefix/root"
    done
    local libpath="$prefix/lib"
    [[ -d "$prefix/root/usr/lib/x86_64-linux-gnu" ]] &&
        libpath="$prefix/root/usr/lib/x86_64-linux-gnu:$libpath"
    if ! ldconfig -p 2>/dev/null | grep -q 'libstdc++.so.6 '; then
        libpath="$libpath:$prefix/lib-fallback"
    fi
    export LD_LIBRARY_PATH="$libpath${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
    # The driver: the NVIDIA ICD where the device image keeps it; else the loader's own search.
    local icd=""
    for f in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd*.json \
        /usr/share/vulkan/icd.d/nvidia_icd*.json /etc/vulkan/icd.d/nvidia_icd*.json; do
        [[ -f "$f" ]] && { icd="$f"; break; }
    done
    if [[ -n "$icd" && -z "${VK_DRIVER_FILES:-}" ]]; then
        export VK_DRIVER_FILES="$icd" VK_ICD_FILENAMES="$icd"
    fi
    # The driver's own libraries, where the image keeps them outside ld.so's cache.
    for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do
        [[ -d "$d" ]] && LD_LIBRARY_PATH="$LD_LIBRARY_PATH:$d"
    done
    export VK_LAYER_PATH="$prefix/layers"
    export PLPLOT_DRV_DIR="$prefix/plplot/drivers" PLPLOT_LIB="$prefix/plplot/data"
    # Tests and benchmarks find their data through the source path compiled into them.
    local source_dir
    source_dir="$(cat "$prefix/source_dir")"
    if [[ ! -e "$source_dir/examples" ]]; then
        mkdir -p "$(dirname "$source_dir")" 2>/dev/null &&
            ln -sfn "$prefix/src" "$source_dir" 2>/dev/null ||
            echo "gpu-check: cannot link $source_dir; tests that read data files may fail" >&2
    fi
    export VPSIM_REQUIRE_GPU=1 VPSIM_CACHE_DIR="$prefix/cache"
    local bin="$prefix/bin"
    # Figures drawn by the packed PLplot? If not (its cairo driver's libraries or fonts), the
    # pipeline benchmarks run without them, and the summary says so.
    step figures 10 "$bin/vpsim" -q --backend cpu run examples/default.json --out "$prefix/figures"
    local outputs=()
    if [[ "$(cat "$results/figures.rc")" != 0 || ! -s "$prefix/figures/exposure_xy.png" ]]; then
        outputs=(--set 'simulation.outputs=["cured.stl","viewer"]')
        echo "gpu-check: figures failed; the pipeline benchmarks run without them" >&2
    fi
    step devices 10 "$bin/vpsim" devices --json
    if [[ "$(cat "$results/devices.rc")" != 0 ]]; then
        # What the loader saw, for the next try.
        echo "gpu-check: no device; VK_DRIVER_FILES=${VK_DRIVER_FILES:-} LD_LIBRARY_PATH=$LD_LIBRARY_PATH" >&2
        VK_LOADER_DEBUG=error,warn,driver "$bin/vpsim" devices --json 2>&1 | tail -40 >&2 || true
    fi
    step test_gpu 30 "$bin/test_gpu" "[gpu]"
    step test_exposure 35 "$bin/test_exposure" "[gpu]"
    step test_transport 30 "$bin/test_transport" "[gpu]"
    step bench_photon_mc 40 "$bin/bench_photon_mc" vulkan 0.1
    step bench_exposure 40 "$bin/bench_exposure" engines --repeats 2 --side 4
    step bench_pipeline 60 "$bin/bench_pipeline" --vulkan "${outputs[@]}"
    # The 20 x 20 x 10 mm block (4.2e9 voxels) in 5 GiB, shaders on the device.
    step bench_pipeline_20mm 40 env VPSIM_MEMORY_LIMIT=5G "$bin/bench_pipeline" --one 20 10 \
        --vulkan "${outputs[@]}"
    # Whole jobs, shaders on the device against the CPU path: their figures side by side.
    compare_runs 8
    summary >"$dir/summary.json"
    cat "$dir/summary.json"
    # Each step's output and errors, where asked (GPU_CHECK_SAVE=FILE.tar.gz).
    [[ -n "${GPU_CHECK_SAVE:-}" ]] && tar -C "$prefix" -czf "$GPU_CHECK_SAVE" results
    [[ "$source_dir" != "$prefix/src" && -L "$source_dir" ]] && rm -f "$source_dir"
    [[ -n "${GPU_CHECK_KEEP:-}" ]] || rm -rf "$prefix"  # GPU_CHECK_KEEP=1: keep it to look into
}

# Runs example jobs with --backend cpu and --backend vulkan (report.json and the pictures-free
# files only) within `limit` seconds each, into $results/runs.out: each job's figures per backend.
compare_runs() {
    local limit="$1" job backend name
    local jobs=("examples/default.json" "examples/seed001-holes.json"
        "examples/seed001-overhangs.json" "examples/default.json:kernel.use=tabulated")
    : >"$results/runs.list"
    for job in "${jobs[@]}"; do
        local file="${job%%:*}" extra=()
        [[ "$job" == *:* ]] && extra=(--set "${job#*:}")
        for backend in cpu vulkan; do
            name="$(basename "$file" .json)${extra:+-tabulated}-$backend"
            step "run-$name" "$limit" "$bin/vpsim" -v --backend "$backend" --set \
                'simulation.outputs=[]' "${extra[@]}" run "$file" --out "$prefix/runs/$name"
            echo "$name $prefix/runs/$name/report.json" >>"$results/runs.list"
        done
    done
    if command -v python3 >/dev/null; then
        python3 - "$results/runs.list" >"$results/runs.out" <<'PY' || echo null >"$results/runs.out"
import json, sys
out = {}
for line in open(sys.argv[1]):
    name, path = line.split()
    try:
        r = json.load(open(path))
        out[name] = {k: r.get(k) for k in ("backend", "iou", "cured_volume_mm3",
                                           "surface_deviation_mm", "stage_seconds")}
    except (OSError, ValueError) as e:
        out[name] = {"error": str(e)}
print(json.dumps(out))
PY
    else
        echo null >"$results/runs.out"
    fi
}

# One JSON object: the device, each test's verdict and each benchmark's own JSON.
summary() {
    local first=1 name
    printf '{\n  "commit": "%s",\n  "icd": "%s",\n  "seconds": %s,\n' "$(cat "$prefix/commit")" \
        "${VK_DRIVER_FILES:-loader default}" "$SECONDS"
    local figures_rc
    figures_rc="$(cat "$results/figures.rc")"
    printf '  "figures": {"rc": %s, "stderr": "%s"},\n' "$figures_rc" \
        "$( ((figures_rc == 0)) || tail -1 "$results/figures.err" | sed 's/["\\]/ /g')"
    printf '  "devices": %s,\n' "$(json_or_null devices)"
    printf '  "tests": {'
    for name in test_gpu test_exposure test_transport; do
        ((first)) || printf ','
        first=0
        local line
        line="$(grep -E 'All tests passed|test cases:' "$results/$name.out" | tail -1 |
            sed 's/"/\\"/g')"
        printf '\n    "%s": {"rc": %s, "seconds": %s, "result": "%s"}' "$name" \
            "$(cat "$results/$name.rc")" "$(cat "$results/$name.seconds")" "$line"
    done
    printf '\n  },\n  "benchmarks": {'
    first=1
    for name in bench_photon_mc bench_exposure bench_pipeline bench_pipeline_20mm; do
        ((first)) || printf ','
        first=0
        printf '\n    "%s": {"rc": %s, "seconds": %s, "output": %s}' "$name" \
            "$(cat "$results/$name.rc")" "$(cat "$results/$name.seconds")" "$(json_or_null "$name")"
    done
    printf '\n  },\n  "runs": %s\n}\n' "$(json_or_null runs)"
}

# The step's stdout if it is a JSON object, else null.
json_or_null() {
    local out="$results/$1.out"
    if [[ -s "$out" ]] && head -c1 "$out" | grep -q '[{[]'; then cat "$out"; else echo null; fi
}

case "$mode" in
    pack) pack ;;
    run) run ;;
    *) usage ;;
esac
