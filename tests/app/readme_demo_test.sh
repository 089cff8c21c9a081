#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @brief README's first command, after its build: app/demo.sh on the Release tree that
#        `bash setup.sh` builds (the programs, not unity, not sanitized), into a scratch folder.
#        Checks that it ran through and left what the README says it leaves. Skipped (77), saying
#        why, when that tree has not been built (setup.sh test builds it first, so CI never skips).
# Usage: readme_demo_test.sh DEMO_TREE SOURCE_DIR SCRATCH PORT
set -euo pipefail
tree=$1 src=$2 scratch=$3 port=$4
if [[ ! -x $tree/bin/telesphere-robot ]]; then
  echo "readme_demo: no Release tree at $tree (build it with: bash setup.sh build)"
  exit 77
fi
rm -rf "$scratch"
mkdir -p "$scratch"
status=0
TELESPHERE_DEMO_PORT=$port timeout -k 10 600 bash "$src/app/demo.sh" "$tree" "$scratch/demo-out" > "$scratch/demo.log" 2>&1 || status=$?
cat "$scratch/demo.log"
[[ $status -eq 0 ]] || { echo "readme_demo: app/demo.sh exited with $status"; exit 1; }
fail=0
for file in head/head_latency.png head/head_latency.csv xr/eyes_last.png xr/stats.json console/console.png; do
  [[ -s $scratch/demo-out/$file ]] || { echo "readme_demo: demo-out/$file is missing or empty"; fail=1; }
done
if [[ -s $scratch/demo-out/xr/stats.json ]] && grep -Eq '"stereo_frames_shown": 0(,|$)' "$scratch/demo-out/xr/stats.json"; then
  echo "readme_demo: the operator's view showed no stereo frame from the robot"; fail=1
fi
exit $fail
