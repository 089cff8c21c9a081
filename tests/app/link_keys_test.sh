#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @brief The link with keys between real programs (DESIGN.md §10): keys made by telesphere-keys, a
#        telesphere-robot with --keys, and telesphere-console status/control with a supervisor key,
#        a viewer key, a key the robot does not know and no key at all. Each refused peer hears why,
#        the robot counts it by cause and address (shown by `status`), and a viewer's stop leaves
#        the arm as it was. A program without --keys or --insecure does not start.
#        Usage: link_keys_test.sh BIN_DIR PORT
set -euo pipefail
bin=$1
port=$2
out=$(mktemp -d -t telesphere-link-keys.XXXXXX)
robot=
cleanup() {
  [ -n "$robot" ] && kill "$robot" 2>/dev/null && wait "$robot" 2>/dev/null
  rm -rf "$out"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  [ -f "$out/robot.log" ] && { echo "--- robot.log (end)" >&2; tail -n 30 "$out/robot.log" >&2; }
  exit 1
}

keys=$out/keys
"$bin/telesphere-keys" generate --role robot --name lab-robot --out "$keys/robot" > /dev/null
mkdir -p "$keys/robot/allowed"
for who in supervisor:sam viewer:vic supervisor:mallory operator:olga operator:oscar; do
  role=${who%%:*}
  name=${who##*:}
  "$bin/telesphere-keys" generate --role "$role" --name "$name" --out "$keys/$name" > /dev/null
  cp "$keys/robot/lab-robot.pub" "$keys/$name/"
done
cp "$keys/sam/sam.pub" "$keys/vic/vic.pub" "$keys/olga/olga.pub" "$keys/robot/allowed/"  # not mallory's, not oscar's

# Neither --keys nor --insecure: the robot does not start, and says what to do.
rc=0
"$bin/telesphere-robot" --sim --port "$port" --duration 1 > "$out/nokeys.log" 2>&1 || rc=$?
[ "$rc" -eq 1 ] || fail "telesphere-robot without --keys or --insecure exited with $rc, not 1"
grep -q -- "--keys DIR" "$out/nokeys.log" && grep -q -- "--insecure" "$out/nokeys.log" ||
  fail "no hint at --keys and --insecure: $(cat "$out/nokeys.log")"

# A secret key the group or others may read is refused with the fix.
chmod 644 "$keys/robot/lab-robot.secret"
rc=0
"$bin/telesphere-robot" --keys "$keys/robot" --sim --port "$port" --duration 1 > "$out/mode.log" 2>&1 || rc=$?
[ "$rc" -eq 1 ] || fail "a readable secret key was accepted (exit $rc)"
grep -q "chmod 600 $keys/robot/lab-robot.secret" "$out/mode.log" || fail "no chmod hint: $(cat "$out/mode.log")"
chmod 600 "$keys/robot/lab-robot.secret"

"$bin/telesphere-robot" --keys "$keys/robot" --sim --size 320x180 --fps 10 --port "$port" --stats-period 0 \
  > "$out/robot.log" 2>&1 &
robot=$!
status() {  # status NAME|insecure [args]: the console's status with that key
  local who=$1
  shift
  if [ "$who" = insecure ]; then
    "$bin/telesphere-console" status --insecure --robot "tcp://127.0.0.1:$port" "$@"
  else
    "$bin/telesphere-console" status --keys "$keys/$who" --robot "tcp://127.0.0.1:$port" "$@"
  fi
}

status sam --wait 30 > "$out/sam.txt" 2>&1 || fail "the supervisor's status failed: $(cat "$out/sam.txt")"
grep -q "keys (CURVE): 3 allowed, operator seat: free" "$out/sam.txt" || fail "no trust line: $(cat "$out/sam.txt")"
joints_before=$(status sam --json 2>/dev/null | python3 -c 'import json,sys; s=json.load(sys.stdin)["state"]; print(s.get("joint_positions", s.get("jointPositions")))')

# No key: the robot expects CURVE; the console says the two disagree on keys (as soon as it
# knows: the wait is only an upper bound, kept long for a loaded machine).
rc=0
status insecure --wait 20 > "$out/plain.txt" 2>&1 || rc=$?
[ "$rc" -eq 3 ] || fail "a console without keys got an answer (exit $rc): $(cat "$out/plain.txt")"
grep -q "disagree on keys" "$out/plain.txt" || fail "no reason for the keyless console: $(cat "$out/plain.txt")"

# A key the robot does not know.
rc=0
status mallory --wait 20 > "$out/mallory.txt" 2>&1 || rc=$?
[ "$rc" -eq 3 ] || fail "an unknown key got an answer (exit $rc): $(cat "$out/mallory.txt")"
grep -q "refused this key" "$out/mallory.txt" || fail "no reason for the unknown key: $(cat "$out/mallory.txt")"

# A viewer sees the status but may not stop the arm.
status vic --wait 10 > "$out/vic.txt" 2>&1 || fail "the viewer's status failed: $(cat "$out/vic.txt")"
rc=0
"$bin/telesphere-console" control --keys "$keys/vic" --robot "tcp://127.0.0.1:$port" --wait 5 stop > "$out/stop.txt" 2>&1 ||
  rc=$?
[ "$rc" -eq 5 ] || fail "the viewer's stop was not refused by the robot (exit $rc): $(cat "$out/stop.txt")"
grep -q "a viewer key (vic) may not send arm_stop: supervisor keys only" "$out/stop.txt" ||
  fail "unexpected answer to the viewer's stop: $(cat "$out/stop.txt")"

status sam --wait 10 > "$out/after.txt" 2>&1 || fail "status after the refusals failed"
grep -q "^arm        ok" "$out/after.txt" || fail "the arm is not ok after a viewer's stop: $(cat "$out/after.txt")"
joints_after=$(status sam --json 2>/dev/null | python3 -c 'import json,sys; s=json.load(sys.stdin)["state"]; print(s.get("joint_positions", s.get("jointPositions")))')
# The simulated arm holds its pose within servo noise (about 1e-5 rad); a stop would brake it.
python3 -c '
import sys
a, b = eval(sys.argv[1]), eval(sys.argv[2])
assert max(abs(x - y) for x, y in zip(a, b)) < 1e-3, (a, b)
' "$joints_before" "$joints_after" || fail "the joints moved: $joints_before -> $joints_after"
grep -q "^refused    .*from 127.0.0.1" "$out/after.txt" || fail "the refusals are not shown: $(cat "$out/after.txt")"
status sam --json > "$out/after.json" 2>/dev/null
for cause in "unknown key" "role" "no key|broken handshake"; do  # (which end sees a keyless peer first is a race)
  grep -Eq "\"cause\": *\"($cause)\"" "$out/after.json" || fail "no refusal counted for '$cause': $(cat "$out/after.json")"
done

# An operator app with an operator key the robot does not know says so at once, not after its --wait.
rc=0
"$bin/telesphere-xr" offscreen --keys "$keys/oscar" --calib "$(dirname "$0")/../../calib/data/sim_calibration.yaml" \
  --port "$port" --eye-size 96x96 --rate 30 --duration 1 --wait 120 --out "$out/xr-oscar" > "$out/xr-oscar.log" 2>&1 ||
  rc=$?
[ "$rc" -eq 2 ] || fail "telesphere-xr with an unknown key exited with $rc, not 2: $(tail -n 5 "$out/xr-oscar.log")"
grep -q "refused this key" "$out/xr-oscar.log" || fail "telesphere-xr did not say why: $(tail -n 5 "$out/xr-oscar.log")"
grep -q "within 120000 ms" "$out/xr-oscar.log" && fail "telesphere-xr waited out its --wait on a refused key"

# The operator over the sealed UDP media path: its session key comes over the encrypted control
# channel; frames arrive whole, and the operator takes the seat.
"$bin/telesphere-xr" offscreen --keys "$keys/olga" --calib "$(dirname "$0")/../../calib/data/sim_calibration.yaml" \
  --port "$port" --video-link udp --eye-size 96x96 --rate 30 --duration 4 --wait 60 --out "$out/xr" \
  > "$out/xr.log" 2>&1 || fail "telesphere-xr over the sealed media path exited with $?: $(tail -n 20 "$out/xr.log")"
whole=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["media_frames_whole"])' "$out/xr/stats.json")
[ "$whole" -gt 10 ] || fail "only $whole whole frames over the sealed media path"
status sam --wait 10 > "$out/seat.txt" 2>&1 || fail "status after the operator failed"
grep -q "operator seat: olga" "$out/seat.txt" || fail "the operator did not take the seat: $(cat "$out/seat.txt")"
status sam --json 2>/dev/null | python3 -c '
import json, sys
media = json.load(sys.stdin)["health"]["media"]
assert int(media.get("frames_sent", 0)) > 10, media
' || fail "the robot sent no frames on the sealed media path"
cat "$out/after.txt"
echo "PASS: keys between real programs: refused peers told why, counted, shown; the arm unmoved"
