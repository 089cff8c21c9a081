#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @brief telesphere-console headless, as the README's demo runs it: without a robot it exits 3
#        and says where it waited; beside telesphere-robot (sim) it writes the main window's
#        picture and exits 0; bad options exit 1.
# Usage: console_headless_test.sh BIN_DIR PORT
set -euo pipefail
bin=$1 port=$2
out=$(mktemp -d -t telesphere-console.XXXXXX)
robot=
cleanup() { [ -n "$robot" ] && kill "$robot" 2>/dev/null; rm -rf "$out"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; cat "$out"/*.log 2>/dev/null || true; exit 1; }

rc=0
"$bin/telesphere-console" --port "$port" --duration 1.5 --screenshot "$out/none.png" > "$out/none.log" 2>&1 || rc=$?
[ "$rc" -eq 3 ] || fail "without a robot: exit $rc, expected 3"
grep -q "never answered at tcp://127.0.0.1:$((port + 3))" "$out/none.log" || fail "no reason given"
[ -s "$out/none.png" ] || fail "no screenshot of the waiting window"

rc=0
"$bin/telesphere-console" --screenshot "$out/x.png" > "$out/args.log" 2>&1 || rc=$?
[ "$rc" -eq 1 ] || fail "--screenshot without --duration: exit $rc, expected 1"

"$bin/telesphere-robot" --sim --size 320x180 --fps 10 --port "$port" --stats-period 0 > "$out/robot.log" 2>&1 &
robot=$!
"$bin/telesphere-console" --port "$port" --duration 4 --screenshot "$out/console.png" > "$out/console.log" 2>&1 ||
  fail "beside a robot: exit $?"
size=$(stat -c %s "$out/console.png")
[ "$size" -gt 20000 ] || fail "console.png is only $size bytes"
echo "PASS: telesphere-console headless"
