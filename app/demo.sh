#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @brief The main job on the embedded default (simulated robot, synthetic cameras, no headset):
#        shows what the landed pipeline can do, leaving its outputs in demo-out/.
#        Usage: bash app/demo.sh [BUILD_DIR [OUT_DIR]]   (setup.sh demo calls it; the readme_demo
#        test runs it on the same tree). Exit status: 0 when every part ran, else the first failure.
set -euo pipefail
build=$(realpath "${1:-build}")
out=$(realpath -m "${2:-demo-out}")
cd "$(dirname "$0")/.."  # the calibration and the programs' data are found from the repository root
bin=$build/bin
for program in telesphere-calib telesphere-bench telesphere-robot telesphere-xr telesphere-console telesphere-keys; do
  [[ -x $bin/$program ]] || { echo "demo: $bin/$program is missing: build first (bash setup.sh)" >&2; exit 1; }
done
mkdir -p "$out"
calib=calib/data/sim_calibration.yaml

echo "== The simulated stereo head: camera models and fields of view"
"$bin/telesphere-calib" info --calib "$calib"

echo
echo "== Rays through the left camera (x y z in its optical frame) -> pixels; 95° off-axis included"
# The rays are written before the pipeline starts: paste reads the file while the projection runs.
printf '0 0 1\n1 0 0\n0.99619 0 -0.08716\n0 0 -1\n' > "$out/rays.txt"
"$bin/telesphere-calib" model project --calib "$calib" --camera 0 < "$out/rays.txt" | paste "$out/rays.txt" - |
  awk -F'\t' '{printf "  %-22s -> %s\n", $1, $2}'

echo
echo "== Camera-model speed and accuracy (telesphere-bench models --quick)"
"$bin/telesphere-bench" models --quick

echo
echo "== The head loop: a 0.5 m/s operator head motion through the controller and the simulated xArm 6"
"$bin/telesphere-bench" head --quick --out "$out/head"

echo
echo "== The whole loop: telesphere-robot (simulated xArm 6, synthetic 195° cameras, 640x360 at 15 Hz),"
echo "   telesphere-xr offscreen (scripted head motion, both eyes at 720x800, 30 Hz) and the supervisor's"
echo "   telesphere-console (headless: live graphs, health, preview; a screenshot at the end) on loopback,"
echo "   every channel encrypted and authenticated (CURVE keys in $out/keys)"
port=${TELESPHERE_DEMO_PORT:-5760}
# Keys (DESIGN.md §10): made on the first run into $out/keys, kept for the next ones. The robot
# trusts the operator (the XR app) and the supervisor (the console); each holds the robot's .pub.
keys=$out/keys
if [[ ! -f $keys/robot/demo-robot.secret ]]; then
  echo "   (first run: making the demo's keys in $keys with telesphere-keys)"
  "$bin/telesphere-keys" generate --role robot --name demo-robot --out "$keys/robot" --force > /dev/null
  "$bin/telesphere-keys" generate --role operator --name demo-operator --out "$keys/operator" --force > /dev/null
  "$bin/telesphere-keys" generate --role supervisor --name demo-supervisor --out "$keys/supervisor" --force > /dev/null
  mkdir -p "$keys/robot/allowed"
  cp "$keys/operator/demo-operator.pub" "$keys/supervisor/demo-supervisor.pub" "$keys/robot/allowed/"
  cp "$keys/robot/demo-robot.pub" "$keys/operator/"
  cp "$keys/robot/demo-robot.pub" "$keys/supervisor/"
fi
"$bin/telesphere-robot" --keys "$keys/robot" --sim --size 640x360 --fps 15 --port "$port" --stats-period 2 \
  > "$out/robot.log" 2>&1 &
robot=$!
trap 'kill $robot 2>/dev/null || true' EXIT
"$bin/telesphere-console" --keys "$keys/supervisor" --port "$port" --duration 9 --screenshot "$out/console/console.png" \
  > "$out/console.log" 2>&1 &
console=$!
"$bin/telesphere-xr" offscreen --keys "$keys/operator" --calib "$calib" --port "$port" --eye-size 720x800 --rate 30 \
  --duration 8 --out "$out/xr"
console_rc=0
wait "$console" || console_rc=$?
kill -INT "$robot"
wait "$robot" || true
trap - EXIT
tail -n 3 "$out/robot.log"
if [ "$console_rc" -ne 0 ]; then
  echo "telesphere-console failed ($console_rc):"
  cat "$out/console.log"
  exit "$console_rc"
fi

echo
echo "demo outputs are in $out/ (head/: the motion trace as CSV and PNG; xr/: the operator's eyes"
echo "as the last frame showed them, eyes_last.png, and the loop's figures, stats.json; console/:"
echo "the supervisor's console as it looked at the end, console.png)"
