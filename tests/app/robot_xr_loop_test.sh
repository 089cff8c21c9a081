#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @brief The whole loop on loopback, as the README's demo runs it: telesphere-robot (simulated arm,
#        synthetic cameras) and telesphere-xr offscreen (scripted head, EGL). Checks that stereo
#        frames reach the operator and are rendered, that head targets reach the robot (the
#        nominal pose is captured from them), that the statistics and the eye images are written,
#        and that both programs exit cleanly (the robot on SIGINT).
# Usage: robot_xr_loop_test.sh BIN_DIR SOURCE_DIR PORT
set -euo pipefail
bin=$1 src=$2 port=$3
out=$(mktemp -d -t telesphere-loop.XXXXXX)
robot=
cleanup() { [ -n "$robot" ] && kill "$robot" 2>/dev/null; rm -rf "$out"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; echo "--- robot log"; cat "$out/robot.log" || true; exit 1; }

"$bin/telesphere-robot" --sim --size 320x180 --fps 15 --port "$port" --duration 120 \
  --stats-period 1 > "$out/robot.log" 2>&1 &
robot=$!
"$bin/telesphere-xr" offscreen --calib "$src/calib/data/sim_calibration.yaml" --port "$port" \
  --eye-size 160x176 --rate 30 --duration 4 --out "$out" --wait 60 | tee "$out/xr.txt" ||
  fail "telesphere-xr offscreen exited with $?"

kill -INT "$robot"
rc=0; wait "$robot" || rc=$?
robot=
[ "$rc" -eq 0 ] || fail "telesphere-robot exited with $rc after SIGINT"

grep -q '"stereo_frames_shown": [1-9]' "$out/stats.json" || fail "no camera frame shown: $(cat "$out/stats.json")"
grep -q '"head_targets_sent": [1-9]' "$out/stats.json" || fail "no head target sent"
grep -q '"nominal_from_robot": true' "$out/stats.json" || fail "the robot never published the nominal mapping"
grep -q 'nominal pose captured' "$out/robot.log" || fail "head targets did not reach the robot"
grep -q 'stopped after' "$out/robot.log" || fail "robot did not stop cleanly"
size=$(stat -c %s "$out/eyes_last.png")
[ "$size" -gt 2000 ] || fail "eyes_last.png is only $size bytes (blank?)"
echo "PASS: robot + offscreen operator loop"
