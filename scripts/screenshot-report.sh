#!/usr/bin/env bash
# Renders a geartopo report (index.html) in Debian's headless Chromium and saves a screenshot, the way a person would
# see the page. Installs chromium if it is missing (Debian package; needs root or sudo).
#   usage: bash scripts/screenshot-report.sh out/run/index.html [out/run/screenshot.png]
set -euo pipefail
page=$(realpath "${1:?usage: screenshot-report.sh INDEX_HTML [PNG]}")
png=$(realpath -m "${2:-$(dirname "$page")/screenshot.png}")
if ! command -v chromium >/dev/null 2>&1; then
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends chromium >/dev/null
fi
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
# No network here: background networking off, a fresh profile, no GPU, no sandbox (root in CI).
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking \
  --disable-component-update --disable-sync --user-data-dir="$profile" --hide-scrollbars \
  --window-size=1500,4200 --screenshot="$png" "file://$page" 2>/dev/null
[ -s "$png" ] || { echo "screenshot-report: no screenshot written" >&2; exit 1; }
echo "screenshot-report: wrote $png"
