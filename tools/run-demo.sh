#!/usr/bin/env bash
# The README's main command: set up, build, and run the main job on the bundled default example,
# examples/default.json (seed 000's alumina slurry, ACES hatching of a small L-shaped part):
# Monte Carlo beam kernel -> slice -> plan -> expose -> cure -> validate. Results go to out/demo
# (override with the first argument); open out/demo/index.html.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/demo}"
bash "$root/tools/build.sh"
"$root/build/vpsim" devices
"$root/build/vpsim" run "$root/examples/default.json" --out "$out"
echo "Open $out/index.html for the report and pictures."
