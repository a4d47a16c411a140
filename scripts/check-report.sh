#!/usr/bin/env bash
# Renders geardyn's report pages as a reader sees them, in headless Chromium: every preset page
# linked from the top index is opened and scrolled (lazy figures load), and the check fails on a
# figure that does not load, a broken link, a console error or a missing claims table. One
# screenshot per page goes to target/report-check/screens/.
#
# Usage: scripts/check-report.sh [--install] [--dir REPORT_DIR] [PRESET ...]
#   PRESET ...   presets whose quick report is made first (default: classic internal breakage)
#   --dir DIR    check an existing report folder (the --out of `geardyn report`) instead
#   --install    install what is missing without asking: Debian's chromium (apt-get) and
#                playwright-core (npm, into scripts/report-check/node_modules)
# Without --install, a missing Chromium is installed only after you answer yes (never in a
# non-interactive shell).
set -euo pipefail
cd "$(dirname "$0")/.."
install=0
dir=""
presets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --install) install=1 ;;
    --dir) dir="$2"; shift ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) presets+=("$1") ;;
  esac
  shift
done
chromium_bin="${CHROMIUM:-/usr/bin/chromium}"
if [ ! -x "$chromium_bin" ]; then
  if [ "$install" = 0 ]; then
    if [ -t 0 ]; then
      read -r -p "Chromium is not installed. Install Debian's chromium package with apt-get now? [y/N] " yes
      case "$yes" in y|Y|yes) install=1 ;; esac
    fi
    if [ "$install" = 0 ]; then
      echo "check-report: Chromium missing; install it (apt-get install chromium) or rerun with --install" >&2
      exit 3
    fi
  fi
  sudo=""
  [ "$(id -u)" = 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq chromium >/dev/null
fi
if [ ! -d scripts/report-check/node_modules/playwright-core ]; then
  (cd scripts/report-check && npm install --no-audit --no-fund --silent)
fi
if [ -z "$dir" ]; then
  [ ${#presets[@]} -gt 0 ] || presets=(classic internal breakage)
  dir="target/report-check/report"
  bin=target/release/geardyn
  [ -x "$bin" ] || cargo build --release -q -p geardyn-cli
  for p in "${presets[@]}"; do
    "$bin" report --preset "$p" --quick --out "$dir" >/dev/null 2>&1 || {
      echo "check-report: geardyn report --preset $p --quick failed" >&2
      exit 1
    }
  done
fi
node scripts/report-check/check.mjs "$dir" target/report-check/screens
