#!/bin/bash
# The main job on a bundled example: installs what ProgSurf needs, then builds a surface from
# examples/clean4.xyz -> out/demo.step, a picture out/demo.png and a report out/demo.json.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
./install.sh
mkdir -p out
.venv/bin/python -m ProgSurf build examples/clean4.xyz -o out/demo.step --iges out/demo.igs \
    --png out/demo.png --report out/demo.json "$@"
