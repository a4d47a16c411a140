#!/usr/bin/env bash
# Opt-in: render the report as a person would see it, in headless Chromium, and check that every
# figure loads and no console error appears. Installs Debian's chromium and playwright-core (npm)
# when missing. Usage: scripts/check-report.sh [preset]
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-breakage}"
if ! command -v chromium >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then apt-get update -qq && apt-get install -y -qq chromium >/dev/null; else sudo apt-get install -y chromium; fi
fi
(cd scripts/report-check && npm install --no-audit --no-fund --silent)
out="target/report-check-$preset"
cargo run --release -q -p geardyn-cli -- report --preset "$preset" --quick --out "$out"
node scripts/report-check/check.mjs "$out/index.html"
