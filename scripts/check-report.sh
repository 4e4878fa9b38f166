#!/usr/bin/env bash
# Renders OUT/report.html in headless Chromium (Debian's `chromium`, driven by playwright-core
# from apps/report/node_modules) and checks the whole page as a person sees it at 1280 px:
# plots loaded and inside the window, nothing cut off below, the 3D view drawn (non-blank canvas
# pixels in the full-page screenshot), no script error. Usage: check-report.sh OUT
set -euo pipefail
out="${1:?usage: check-report.sh OUT}"
page="$(cd "$out" && pwd)/report.html"
here="$(cd "$(dirname "$0")" && pwd)"
[ -f "$page" ] || { echo "check-report: $page: no such file (run: cleanmap report $out)" >&2; exit 1; }
command -v chromium > /dev/null || { echo "check-report: chromium missing (bash scripts/install-deps.sh)" >&2; exit 1; }
[ -d "$here/../apps/report/node_modules/playwright-core" ] ||
  { echo "check-report: playwright-core missing (bash scripts/install-deps.sh runs npm ci in apps/report)" >&2; exit 1; }
node "$here/check-report.mjs" "$page" "$(cd "$out" && pwd)/report/screenshot.png"
