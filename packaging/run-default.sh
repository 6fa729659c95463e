#!/usr/bin/env bash
# Installs dependencies, builds Atelier (Release) and runs its main job on the bundled
# default: simulating assets/scenes/hanging-sheet.json, writing the mesh and the report to out/.
set -euo pipefail
cd "$(dirname "$0")/.."

bash packaging/install-deps.sh
cmake --preset release -DATELIER_BUILD_TESTS=OFF
cmake --build --preset release -j "$(nproc)" --target atelier-cli
mkdir -p out
./build/release/app/atelier-cli simulate assets/scenes/hanging-sheet.json \
  --out out/hanging-sheet.obj --report out/hanging-sheet.report.json
echo "wrote out/hanging-sheet.obj and out/hanging-sheet.report.json"
