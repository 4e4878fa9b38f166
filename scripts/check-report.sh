#!/usr/bin/env bash
# Renders OUT/report.html in headless Chromium (Debian's `chromium` package) and checks that a
# page came out: a screenshot of reasonable size and no error text. Usage: check-report.sh OUT
set -euo pipefail
out="${1:?usage: check-report.sh OUT}"
page="$(cd "$out" && pwd)/report.html"
[ -f "$page" ] || { echo "check-report: $page: no such file (run: cleanmap report $out)" >&2; exit 1; }
command -v chromium > /dev/null || { echo "check-report: chromium missing (apt-get install chromium)" >&2; exit 1; }
shot="$out/report/screenshot.png"
profile="$(mktemp -d)"
trap 'rm -rf "$profile"' EXIT
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$profile" --window-size=1280,2400 --screenshot="$shot" "file://$page" \
  > /dev/null 2>&1
text="$(chromium --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking \
  --disable-component-update --disable-sync --user-data-dir="$profile" --dump-dom "file://$page" 2> /dev/null)"
size=$(stat -c %s "$shot" 2> /dev/null || echo 0)
images=$(grep -o '<img' <<< "$text" | wc -l)
if [ "$size" -lt 20000 ] || [ "$images" -lt 4 ] || ! grep -q "cleanmap report" <<< "$text"; then
  echo "check-report: $page did not render (screenshot $size bytes, $images images)" >&2
  exit 1
fi
echo "check-report: $page renders ($images plots, screenshot $shot, $size bytes)"
