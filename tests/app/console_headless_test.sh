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
fail() { echo "FAIL: $*"; cat "$out"/*.log 2>/dev/null || true; echo "--- FAIL: $*"; exit 1; }  # the reason last too: CI shows the end

rc=0
"$bin/telesphere-console" --insecure --port "$port" --duration 1.5 --screenshot "$out/none.png" > "$out/none.log" 2>&1 || rc=$?
[ "$rc" -eq 3 ] || fail "without a robot: exit $rc, expected 3"
grep -q "never answered at tcp://127.0.0.1:$((port + 3))" "$out/none.log" || fail "no reason given"
[ -s "$out/none.png" ] || fail "no screenshot of the waiting window"

rc=0
"$bin/telesphere-console" --insecure --screenshot "$out/x.png" > "$out/args.log" 2>&1 || rc=$?
[ "$rc" -eq 1 ] || fail "--screenshot without --duration: exit $rc, expected 1"

"$bin/telesphere-robot" --insecure --sim --size 320x180 --fps 10 --port "$port" --stats-period 0 > "$out/robot.log" 2>&1 &
robot=$!
"$bin/telesphere-console" --insecure --port "$port" --duration 4 --screenshot "$out/console.png" > "$out/console.log" 2>&1 ||
  fail "beside a robot: exit $?"
size=$(stat -c %s "$out/console.png")
[ "$size" -gt 20000 ] || fail "console.png is only $size bytes"
# The study commands: import the paper's questionnaire answers, write the report; a bad CSV is
# refused with its line and nothing is imported.
src=$(cd "$(dirname "$0")/../.." && pwd)
"$bin/telesphere-console" study import --db "$out/study.sqlite" \
  --answers "$src/tests/console/data/paper_likert_answers.csv" > "$out/import.log" 2>&1 || fail "study import: exit $?"
grep -q "imported 0 trials and 147 answers" "$out/import.log" || fail "study import: $(cat "$out/import.log")"
"$bin/telesphere-console" study report --db "$out/study.sqlite" --out "$out/report" > "$out/report.log" 2>&1 ||
  fail "study report: exit $?"
for f in study-study_answers.csv study-study_table-i.md study-study_summary.json study-study_paper_likert.png \
         study-study_paper_likert.pdf study.sqlite; do
  [ -s "$out/report/$f" ] || fail "study report did not write $f"
done
printf 'participant,mode,instrument,item,value\nP1,full7d,paper_likert,fit,5\n' > "$out/bad.csv"
rc=0
"$bin/telesphere-console" study import --db "$out/study.sqlite" --answers "$out/bad.csv" > "$out/bad.log" 2>&1 || rc=$?
[ "$rc" -eq 1 ] || fail "a bad CSV: exit $rc, expected 1"
grep -q "bad.csv:2:" "$out/bad.log" || fail "the bad row's line is not named: $(cat "$out/bad.log")"
echo "PASS: telesphere-console headless"
