#!/usr/bin/env bash
# Installs a build into a temporary prefix and runs the installed cleanmap from another folder:
# demo, run and report must work without the source tree. Usage: bash scripts/check-install.sh BUILD_DIR
set -euo pipefail
build="$(cd "${1:-build}" && pwd)"
prefix="$(mktemp -d)"
work="$(mktemp -d)"
trap 'rm -rf "$prefix" "$work"' EXIT
cmake --install "$build" --prefix "$prefix" > /dev/null
cd "$work"
"$prefix/bin/cleanmap" --version
"$prefix/bin/cleanmap" demo --scans 3 --beams 16 --columns 256 --out demo > /dev/null 2>&1
"$prefix/bin/cleanmap" run --input demo/sequence --out run --config "$prefix/share/cleanmap/config/ouster-os1-64.yaml" \
  --use-given-poses > /dev/null 2>&1
"$prefix/bin/cleanmap" report run > /dev/null 2>&1
test -s run/report.html
# The 3D view's bundle is installed beside the script and found from there.
if [ -f "$build/apps/report/viewer.js" ]; then grep -q 'id="map3d"' run/report.html; fi
grep -q '"complete": true' run/summary.json
# The Python module, from the prefix's Python package folder (Debian's lib/python3/dist-packages).
if ls "$prefix"/lib/python3/dist-packages/cleanmap*.so > /dev/null 2>&1; then
  PYTHONPATH="$prefix/lib/python3/dist-packages" /usr/bin/python3 -c \
    "import cleanmap, sys; cfg = cleanmap.Config.from_preset(); assert 'scorer' in cfg.to_yaml(); sys.exit(0 if cleanmap.__file__.startswith('$prefix') else 1)"
fi
echo "check-install: $prefix/bin/cleanmap runs demo, run and report from $work"
