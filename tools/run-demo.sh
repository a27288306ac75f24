#!/usr/bin/env bash
# The README's main command: set up, build, and run the main job on the bundled default example
# (the seed-000 alumina slurry): slurry optics, the photon Monte Carlo beam kernel with its
# pictures, a test part sliced into layers, and the cure calibration of seed 001. Results go to
# out/demo/ (override with the first argument).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/demo}"
bash "$root/tools/build.sh"
vpsim="$root/build/vpsim"
material="$root/examples/materials/alumina-seed000.json"
mkdir -p "$out"

step() { echo; echo "== $*"; }
step "Vulkan devices"
"$vpsim" devices
step "Slurry optics (Lorenz-Mie)"
"$vpsim" mie --material "$material" --cdf-angles 1,5,10,30 --json | tee "$out/slurry_optics.json"
step "Beam kernel from the photon Monte Carlo"
"$vpsim" kernel --material "$material" --power 10mW --w0 50um --out "$out/kernel"
step "Test part and slices"
"$vpsim" part make holes --out "$out/holes.stl"
"$vpsim" slice "$out/holes.stl" --layer 50um --layers 0,40,80 --out "$out/slices" --json > "$out/slices.json"
step "Cure calibration from the seed-001 working curve"
if [[ -f "$root/../shared/reference/seed001_table1_working_curve.csv" ]]; then
  "$vpsim" calibrate --working-curve "$root/../shared/reference/seed001_table1_working_curve.csv" \
    --gel-point 0.276 --json | tee "$out/calibration.json"
fi
echo
echo "Results in $out (kernel pictures in $out/kernel, slices in $out/slices)"
