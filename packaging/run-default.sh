#!/usr/bin/env bash
# Installs dependencies, builds Atelier (Release) and runs its main job on the bundled
# default: draping assets/garments/tshirt.atelier on the default mannequin, writing the draped
# garment (out/tshirt.obj; the body beside it, out/tshirt.body.obj) and the report.
# At the project's own resolution (10 mm, 16.2k triangles) it comes to rest in about 10 s of
# draping on 2 cores; PARTICLE_DISTANCE_MM overrides it (20 for a quick look, about 4 s).
# Figures: docs/benchmarks.md.
set -euo pipefail
cd "$(dirname "$0")/.."

bash packaging/install-deps.sh
cmake --preset release -DATELIER_BUILD_TESTS=OFF
cmake --build --preset release -j "$(nproc)" --target atelier-cli
mkdir -p out
args=()
if [ -n "${PARTICLE_DISTANCE_MM:-}" ]; then
  args+=(--particle-distance "$PARTICLE_DISTANCE_MM")
fi
./build/release/app/atelier-cli drape assets/garments/tshirt.atelier "${args[@]}" \
  --out out/tshirt.obj --report out/tshirt.report.json
echo "wrote out/tshirt.obj and out/tshirt.report.json"
