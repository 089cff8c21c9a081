#!/bin/sh
# SPDX-License-Identifier: MIT
## @brief Runs a command on a private virtual X server: starts Xvfb, which picks a free display
##        number itself and reports it once it accepts clients (-displayfd: no race with other
##        servers starting at the same time), runs CMD with DISPLAY set, stops the server and exits
##        with CMD's status (77 when Xvfb is not installed, 125 when it did not start).
## Usage: with_xvfb.sh CMD [ARGS...]
set -eu
command -v Xvfb >/dev/null 2>&1 || { echo "with_xvfb: Xvfb is not installed (apt install xvfb)" >&2; exit 77; }
W=$(mktemp -d /tmp/with_xvfb.XXXXXX)
XVFB_PID=
cleanup() {
  if [ -n "$XVFB_PID" ]; then kill "$XVFB_PID" 2>/dev/null || true; wait "$XVFB_PID" 2>/dev/null || true; fi
  rm -rf "$W"
}
trap cleanup EXIT
Xvfb -displayfd 3 -screen 0 1280x800x24 -nolisten tcp 3>"$W/display" >"$W/xvfb.log" 2>&1 &
XVFB_PID=$!
i=0
until grep -q '^[0-9][0-9]*$' "$W/display" 2>/dev/null; do
  kill -0 "$XVFB_PID" 2>/dev/null || { cat "$W/xvfb.log" >&2; echo "with_xvfb: Xvfb exited at start" >&2; exit 125; }
  i=$((i + 1)); [ $i -le 100 ] || { echo "with_xvfb: Xvfb did not start within 10 s" >&2; exit 125; }
  sleep 0.1
done
export DISPLAY=":$(cat "$W/display")"
set +e
"$@"
status=$?
exit "$status"
