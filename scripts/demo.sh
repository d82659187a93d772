#!/usr/bin/env bash
# The main job on the bundled sample: build libbrdffit and the brdffit
# command, fit the sample car-paint measurement and draw a preview.
#
#   bash scripts/demo.sh [MODEL]
#
# Installs the build tools with apt-get when they are missing, builds in
# build-demo/ (Release, no tests) and writes sample-preview.png next to this
# repository's README. MODEL defaults to ashikhmin-shirley.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
. scripts/common.sh

model=${1:-ashikhmin-shirley}
install_packages demo.sh cmake make gcc libc6-dev libcairo2-dev fonts-dejavu-core pkg-config

log "build (build-demo)"
cmake -S . -B build-demo -DCMAKE_BUILD_TYPE=Release -DBRDFFIT_BUILD_TESTS=OFF > /dev/null
cmake --build build-demo -j2 > /dev/null

log "brdffit fit data/sample-carpaint.csv --model $model --preview sample-preview.png"
build-demo/tools/brdffit fit data/sample-carpaint.csv --model "$model" \
    --preview sample-preview.png
echo
echo "demo.sh: wrote sample-preview.png (measured, model and difference textures,"
echo "         spheres under a point light, and the cost per iteration)"
