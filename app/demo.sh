#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @brief The main job on the embedded default (simulated robot, synthetic cameras, no headset):
#        shows what the landed pipeline can do, leaving its outputs in demo-out/.
#        Usage: bash app/demo.sh BUILD_DIR   (setup.sh demo calls it)
set -euo pipefail
build=${1:-build}
bin=$build/bin
out=demo-out
mkdir -p "$out"
calib=calib/data/sim_calibration.yaml

echo "== The simulated stereo head: camera models and fields of view"
"$bin/telesphere-calib" info --calib "$calib"

echo
echo "== Rays through the left camera (x y z in its optical frame) -> pixels; 95° off-axis included"
printf '0 0 1\n1 0 0\n0.99619 0 -0.08716\n0 0 -1\n' | tee "$out/rays.txt" |
  "$bin/telesphere-calib" model project --calib "$calib" --camera 0 | paste "$out/rays.txt" - |
  awk -F'\t' '{printf "  %-22s -> %s\n", $1, $2}'

echo
echo "== Camera-model speed and accuracy (telesphere-bench models --quick)"
"$bin/telesphere-bench" models --quick

echo
echo "== The head loop: a 0.5 m/s operator head motion through the controller and the simulated xArm 6"
"$bin/telesphere-bench" head --quick --out "$out/head"

echo
echo "demo outputs are in $out/ (head/ holds the motion trace as CSV and PNG)"
