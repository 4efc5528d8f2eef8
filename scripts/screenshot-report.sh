#!/usr/bin/env bash
# Renders a geartopo report (index.html) in Debian's headless Chromium the way a person sees it: a screenshot of the
# page in a 1400 px wide window, and the PDF customers file (Chromium's print-to-PDF, A4 per the page's @page rule).
# Installs chromium if it is missing and root/sudo is available; otherwise says so and exits 0 without output files
# (GEARTOPO_REQUIRE_CHROMIUM=1 makes that an error).
#   usage: bash scripts/screenshot-report.sh out/run/index.html [out/run/screenshot.png] [out/run/report.pdf]
set -euo pipefail
page=$(realpath "${1:?usage: screenshot-report.sh INDEX_HTML [PNG] [PDF]}")
png=$(realpath -m "${2:-$(dirname "$page")/screenshot.png}")
pdf=$(realpath -m "${3:-$(dirname "$page")/report.pdf}")
if ! command -v chromium >/dev/null 2>&1; then
  if [ "$(id -u)" -eq 0 ] || command -v sudo >/dev/null 2>&1; then
    bash "$(dirname "$0")/install-deps.sh" chromium || true
  fi
fi
if ! command -v chromium >/dev/null 2>&1; then
  echo "screenshot-report: chromium is not installed (Debian package 'chromium'): no screenshot, no PDF" >&2
  [ "${GEARTOPO_REQUIRE_CHROMIUM:-0}" = 1 ] && exit 1
  exit 0
fi
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
# No network here: background networking off, a fresh profile, no GPU, no sandbox (root in CI).
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
  --disable-component-update --disable-sync --user-data-dir="$profile" --hide-scrollbars)
# Written next to the target and renamed: a failed run leaves no half-written file.
chromium "${flags[@]}" --window-size=1400,4200 --screenshot="$png.tmp.png" "file://$page" 2>/dev/null
[ -s "$png.tmp.png" ] || { echo "screenshot-report: no screenshot written" >&2; exit 1; }
mv "$png.tmp.png" "$png"
chromium "${flags[@]}" --no-pdf-header-footer --print-to-pdf="$pdf.tmp.pdf" "file://$page" 2>/dev/null
[ -s "$pdf.tmp.pdf" ] || { echo "screenshot-report: no PDF written" >&2; exit 1; }
mv "$pdf.tmp.pdf" "$pdf"
echo "screenshot-report: wrote $png and $pdf"
