#!/usr/bin/env bash
# Renders a small comparison report (quad + fence at 64², four methods) and loads it in headless
# Chromium: no console message (the page logs nothing, so any message is an error), every image
# loaded (the page records data-images / data-images-broken on <body> once loaded), and a
# screenshot saved for a person to look at. Exits 77 (ctest: skipped) without Chromium.
#   browser_test.sh PENUMBRA_BINARY OUTPUT_DIR
set -uo pipefail
bin="$1"
out="$2"
browser=""
for b in chromium chromium-browser google-chrome; do
  if command -v "$b" >/dev/null 2>&1; then
    browser="$b"
    break
  fi
done
if [ -z "$browser" ]; then
  echo "SKIPPED: no chromium on PATH (scripts/setup.sh installs it)"
  exit 77
fi
rm -rf "$out"
mkdir -p "$out"
export PENUMBRA_NO_PROGRESS=1
if ! "$bin" report --scene quad --scene fence --method exact --method raytrace --method pcss \
  --method wedges --size 64x64 --samples 4 --out "$out/report" >"$out/report.log" 2>&1; then
  echo "FAIL: penumbra report failed:"
  cat "$out/report.log"
  exit 1
fi
page="file://$(cd "$out/report" && pwd)/index.html"
flags=(--headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run
  --user-data-dir="$out/profile" --virtual-time-budget=5000)
timeout 120 "$browser" "${flags[@]}" --enable-logging=stderr --v=0 --dump-dom "$page" \
  >"$out/dom.html" 2>"$out/browser.log"
timeout 120 "$browser" "${flags[@]}" --window-size=1400,2400 --screenshot="$out/screenshot.png" \
  "$page" >/dev/null 2>>"$out/browser.log"

failed=0
body="$(grep -o '<body[^>]*>' "$out/dom.html" | head -1)"
images="$(sed -n 's/.*data-images="\([0-9]*\)".*/\1/p' <<<"$body")"
broken="$(sed -n 's/.*data-images-broken="\([0-9]*\)".*/\1/p' <<<"$body")"
# 2 scenes x (4 beauty + 3 abs + 3 signed + 4 crops + 3 crop errors) = 34 images.
if [ "$images" != "34" ]; then
  echo "FAIL: the page has '${images:-?}' images once loaded, want 34 (body: $body)"
  failed=1
fi
if [ "$broken" != "0" ]; then
  echo "FAIL: ${broken:-?} images did not load (body: $body)"
  failed=1
fi
if grep -q 'CONSOLE' "$out/browser.log"; then
  echo "FAIL: console messages:"
  grep 'CONSOLE' "$out/browser.log"
  failed=1
fi
if grep -Eq "(src|href)=['\"]https?:" "$out/report/index.html"; then
  echo "FAIL: the page refers to the network"
  failed=1
fi
if [ ! -s "$out/screenshot.png" ]; then
  echo "FAIL: no screenshot"
  failed=1
fi
[ "$failed" -eq 0 ] && echo "OK: $images images loaded, no console message; screenshot $out/screenshot.png"
exit "$failed"
