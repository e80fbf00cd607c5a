#!/usr/bin/env bash
# System libraries for offscreen rendering on CPU (EGL via Mesa llvmpipe; OSMesa as a fallback), and a
# headless Chromium for the results page's screenshot and its browser test (`rle index --screenshot`).
set -euo pipefail
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
$SUDO apt-get update
$SUDO apt-get install -y --no-install-recommends libegl1 libgl1-mesa-dri libosmesa6 chromium-headless-shell
