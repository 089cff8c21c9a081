#!/bin/sh
# SPDX-License-Identifier: MIT
## @brief Runs a command on a private virtual X server: starts Xvfb on a free display (:70…:89),
##        waits until it accepts clients, runs CMD with DISPLAY set, stops the server and exits
##        with CMD's status (77 when Xvfb is not installed, 125 when it did not start).
## Usage: with_xvfb.sh CMD [ARGS...]
set -eu
command -v Xvfb >/dev/null 2>&1 || { echo "with_xvfb: Xvfb is not installed (apt install xvfb)" >&2; exit 77; }
n=70
while [ -e "/tmp/.X11-unix/X$n" ] || [ -e "/tmp/.X$n-lock" ]; do
  n=$((n + 1))
  [ "$n" -le 89 ] || { echo "with_xvfb: no free display in :70..:89" >&2; exit 125; }
done
Xvfb ":$n" -screen 0 1280x800x24 -nolisten tcp >/dev/null 2>&1 &
XVFB_PID=$!
trap 'kill "$XVFB_PID" 2>/dev/null || true; wait "$XVFB_PID" 2>/dev/null || true' EXIT
i=0
until [ -S "/tmp/.X11-unix/X$n" ]; do
  kill -0 "$XVFB_PID" 2>/dev/null || { echo "with_xvfb: Xvfb :$n exited at start" >&2; exit 125; }
  i=$((i + 1)); [ $i -le 100 ] || { echo "with_xvfb: Xvfb :$n did not start within 10 s" >&2; exit 125; }
  sleep 0.1
done
export DISPLAY=":$n"
set +e
"$@"
status=$?
exit "$status"
