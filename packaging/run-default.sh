#!/usr/bin/env bash
# Installs dependencies, builds Atelier (Release) and runs its main job on the bundled
# default: draping assets/garments/tshirt.atelier on the default mannequin, writing the draped
# garment (out/tshirt.obj; the body beside it, out/tshirt.body.obj) and the report.
# PARTICLE_DISTANCE_MM (default 20) sets the mesh resolution: the project's own 10 mm gives
# ~16k triangles and takes minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."

bash packaging/install-deps.sh
cmake --preset release -DATELIER_BUILD_TESTS=OFF
cmake --build --preset release -j "$(nproc)" --target atelier-cli
mkdir -p out
./build/release/app/atelier-cli drape assets/garments/tshirt.atelier \
  --particle-distance "${PARTICLE_DISTANCE_MM:-20}" \
  --out out/tshirt.obj --report out/tshirt.report.json
echo "wrote out/tshirt.obj and out/tshirt.report.json"
