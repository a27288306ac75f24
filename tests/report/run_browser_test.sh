#!/usr/bin/env bash
# The reports in a real browser (issue 24 item 5): runs the default job (kernel photons cut to
# keep it short; a name with markup to check escaping), seed 001's holes and a comparison of both,
# opens each index.html in headless Chromium (Debian's `chromium`; WebGL through SwiftShader, no
# flag that loosens file:// access) and fails on any console message or failed load, on a 3D
# canvas without data-rendered="1", on a blank 3D view in a screenshot, on unescaped quoted text
# and on anything loaded from the network; the per-layer section canvas must draw and redraw when
# the layer slider moves, and the kernel map must be there when the run has a Monte Carlo kernel.
# Usage: run_browser_test.sh VPSIM SOURCE_DIR
set -euo pipefail
vpsim="$1"; source="$2"
chromium="$(command -v chromium || true)"
[[ -n "$chromium" ]] || { echo "browser: chromium is not installed (tools/install-deps.sh)"; exit 1; }
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
export VPSIM_CACHE_DIR="$work/cache" HOME="$work/home"
mkdir -p "$HOME"
flags=(--headless --use-angle=swiftshader --enable-unsafe-swiftshader --enable-logging=stderr
       --v=0 --hide-scrollbars --no-first-run --virtual-time-budget=10000
       --user-data-dir="$work/profile")
[[ "$(id -u)" == 0 ]] && flags+=(--no-sandbox)
failed=0
fail() { echo "browser: FAIL: $*"; failed=$((failed + 1)); }

name="<b id=injected>quoted & 'escaped'</b>"
"$vpsim" -q run "$source/examples/default.json" --out "$work/default" \
  --set kernel.photons=20000 --set "name=$name" >"$work/default.log" 2>&1 ||
  { cat "$work/default.log"; exit 1; }
"$vpsim" -q run "$source/examples/seed001-holes.json" --out "$work/seed001" >"$work/seed001.log" 2>&1 ||
  { cat "$work/seed001.log"; exit 1; }
"$vpsim" compare "$work/default" "$work/seed001" --out "$work/compare" >/dev/null

# A directory whose files do not match its manifest is refused.
cp -r "$work/default" "$work/tampered"
echo "changed" >>"$work/tampered/report.json"
if "$vpsim" compare "$work/tampered" --out "$work/compare-bad" 2>"$work/bad.log"; then
  fail "compare accepted a directory whose report.json differs from its manifest"
fi
grep -q "manifest" "$work/bad.log" || fail "compare's refusal does not name the manifest: $(cat "$work/bad.log")"

open_page() {  # page, action (dump-dom|screenshot=FILE), output
  timeout 120 "$chromium" "${flags[@]}" --window-size=1100,900 "--$2" "file://$1" >"$3" 2>"$3.log" || true
  # Console messages of the page (errors, warnings, logs) and failed loads: none expected.
  if grep -E "CONSOLE|Failed to load|ERR_FILE|net::ERR" "$3.log" >/dev/null; then
    fail "$1: console or load messages:"; grep -E "CONSOLE|Failed to load|ERR_FILE|net::ERR" "$3.log" | head -5
  fi
}
for page in default seed001 compare; do
  html="$work/$page/index.html"
  [[ -f "$html" ]] || { fail "$page: no index.html"; continue; }
  grep -Eiq "(src|href)=['\"]?(https?:)?//" "$html" && fail "$page: loads something from the network"
  open_page "$html" dump-dom "$work/$page.dom"
  grep -q "</html>" "$work/$page.dom" || fail "$page: no DOM dumped"
  if [[ "$page" != compare ]]; then
    grep -q 'data-rendered="1"' "$work/$page.dom" || fail "$page: the 3D canvas did not render"
    for figure in exposure_xz exposure_xy deviation_map_top; do
      for ext in svg png; do
        grep -q "\"$figure.$ext\"" "$work/$page/manifest.json" || fail "$page: $figure.$ext not in the manifest"
        grep -q ">$figure.$ext<" "$html" || fail "$page: $figure.$ext not in the file list"
      done
      grep -q "<text" "$work/$page/$figure.svg" || fail "$page: $figure.svg has no text (axes)"
    done
  fi
done
grep -q "Features (mm)" "$work/seed001/index.html" || fail "seed001: no features table"

# The per-layer section (drawn once at load) and the kernel map: default has a Monte Carlo
# kernel, seed 001 (DLP) none.
canvas() { grep -o "<canvas id=\"$2\"[^>]*>" "$1" || true; }
for page in default seed001; do
  section="$(canvas "$work/$page.dom" section2d)"
  [[ "$section" == *'data-rendered="1"'* ]] || fail "$page: the section canvas did not draw: $section"
  [[ "$section" == *'data-draws="1"'* ]] || fail "$page: the section canvas drew other than once at load: $section"
done
[[ "$(canvas "$work/default.dom" kernel2d)" == *'data-rendered="1"'* ]] ||
  fail "default: no kernel map drawn although the run has a Monte Carlo kernel"
grep -q 'kernel-panel' "$work/seed001.dom" && fail "seed001: a kernel panel without a kernel"
# A slider change redraws: #layer=2 moves the slider once the page has drawn.
open_page "$work/default/index.html#layer=2" dump-dom "$work/layer2.dom"
section="$(canvas "$work/layer2.dom" section2d)"
[[ "$section" == *'data-layer="2"'* && "$section" == *'data-draws="2"'* ]] ||
  fail "default: moving the layer slider to 2 did not redraw the section: $section"
# Every figure the reports list: axis labels, units, colour bar and legend as SVG text, and a PNG.
python3 "$source/tests/report/check_figures.py" "$work/default" "$work/seed001" ||
  fail "figures without their labels, colour bar or legend (above)"
for page in default compare; do
  grep -Eq "<b id=\"?injected" "$work/$page.dom" && fail "$page: the job name was not escaped"
  grep -q "&lt;b id=injected&gt;quoted &amp; " "$work/$page.dom" || fail "$page: the escaped job name is missing"
done

# The 3D view in a screenshot (view3d.html, the same view alone): the canvas must show the part
# (coloured pixels: the deviation colours; the background and text are grey).
open_page "$work/default/view3d.html" screenshot="$work/view.png" "$work/shot.out"
python3 - "$work/view.png" <<'PY' || fail "default: the 3D view is blank in the screenshot"
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n"
pos, idat, width = 8, b"", 0
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b"IHDR":
        width, height, depth, colour = struct.unpack(">IIBB", body[:10])
        assert depth == 8 and colour in (2, 6), (depth, colour)
        bpp = 3 if colour == 2 else 4
    elif kind == b"IDAT":
        idat += body
    pos += 12 + n
raw, stride, prev, coloured = zlib.decompress(idat), width * bpp, None, 0
for y in range(height):
    f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = line[i - bpp] if i >= bpp else 0
        b = prev[i] if prev else 0
        c = prev[i - bpp] if prev and i >= bpp else 0
        p = a + b - c
        pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c) else (b if abs(p - b) <= abs(p - c) else c)][f]
        line[i] = (line[i] + pred) & 255
    for x in range(0, stride, bpp):
        r, g, b2 = line[x], line[x + 1], line[x + 2]
        if max(r, g, b2) - min(r, g, b2) > 12:  # coloured: the deviation colours and shading
            coloured += 1
    prev = line
print(f"browser: 3D view screenshot: {coloured} coloured pixels of {width * height}")
sys.exit(0 if coloured > 5000 else 1)
PY
[[ $failed -eq 0 ]] || { echo "browser: $failed failure(s)"; exit 1; }
echo "browser: default, seed001 and compare reports open without console errors; 3D view rendered"
