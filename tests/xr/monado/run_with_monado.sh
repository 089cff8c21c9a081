#!/bin/sh
# SPDX-License-Identifier: MIT
## @brief Runs a command against a headless Monado OpenXR runtime from a Debian trixie root.
##
## Usage: run_with_monado.sh [--stop-service-after S] [--restart-service-after S] [--timeout S] [--preload LIBS] ROOT -- CMD [ARGS...]
##   ROOT   a tree made by build_trixie_root.sh (no root privileges needed to run)
##   --stop-service-after S   stop monado-service S seconds after CMD started (to test that CMD
##                            notices the runtime going away and exits by itself)
##   --restart-service-after S  stop monado-service S seconds after CMD started and start it
##                            again 2 s later (to test that CMD reconnects to the new runtime)
##   --timeout S              seconds to wait for the service's socket (default 30)
##   --preload LIBS           libraries (colon-separated paths) the loader preloads into CMD only,
##                            never into the service (the leak test's deliberate leak)
## Starts monado-service (null compositor, simulated HMD, no stdin) in a private short
## XDG_RUNTIME_DIR, waits for its IPC socket, runs CMD through trixie's dynamic loader with
## trixie's library folders first (Monado's client library needs trixie's libc), stops the
## service and exits with CMD's exit status (125 when the service could not be started).
## The service log is printed to stderr when the service fails; keep it with
## TELESPHERE_MONADO_LOG=FILE. Extra service environment (e.g. XRT_LOG=debug) passes through.
set -eu

say() { printf 'run_with_monado: %s\n' "$*" >&2; }
die() { say "error: $*"; exit 125; }

STOP_AFTER=
RESTART_AFTER=
WAIT_S=30
PRELOAD=
while [ $# -gt 0 ]; do
  case "$1" in
    --stop-service-after) [ $# -ge 2 ] || die "--stop-service-after needs SECONDS"; STOP_AFTER=$2; shift 2 ;;
    --restart-service-after) [ $# -ge 2 ] || die "--restart-service-after needs SECONDS"; RESTART_AFTER=$2; shift 2 ;;
    --timeout) [ $# -ge 2 ] || die "--timeout needs SECONDS"; WAIT_S=$2; shift 2 ;;
    --preload) [ $# -ge 2 ] || die "--preload needs LIBS"; PRELOAD=$2; shift 2 ;;
    -h|--help) sed -n 's/^## \{0,1\}//p' "$0"; exit 0 ;;
    --) die "ROOT missing before --" ;;
    -*) die "unknown option '$1' (see --help)" ;;
    *) break ;;
  esac
done
[ $# -ge 3 ] && [ "$2" = "--" ] || die "usage: run_with_monado.sh [options] ROOT -- CMD [ARGS...] (see --help)"
T=$1
shift 2
case "$T" in /*) ;; *) T=$(pwd)/$T ;; esac

LD=$T/lib64/ld-linux-x86-64.so.2
M=$T/usr/lib/x86_64-linux-gnu
[ -e "$LD" ] && [ -x "$T/usr/bin/monado-service" ] && [ -e "$M/libopenxr_monado.so" ] ||
  die "$T is not a Monado trixie root (make one with tests/xr/monado/build_trixie_root.sh $T)"

# The IPC socket path must fit sockaddr_un (108 bytes): keep the folder short.
W=$(mktemp -d /tmp/xrrun.XXXXXX)
mkdir -m 700 "$W/xdg"
TIMER_PID=
CMD_PID=
# The service's pid lives in a file: a service restarted by the timer is still stopped by cleanup.
service_pid() { cat "$W/service.pid" 2>/dev/null || true; }
# Running and not a zombie (a service stopped by the timer subshell stays a zombie until we reap it).
alive() { kill -0 "$1" 2>/dev/null && ! grep -q '^[0-9]* ([^)]*) Z' "/proc/$1/stat" 2>/dev/null; }
stop_service() {
  pid=$(service_pid)
  if [ -n "$pid" ] && alive "$pid"; then
    kill -TERM "$pid" 2>/dev/null || true
    i=0
    while alive "$pid" && [ $i -lt 50 ]; do sleep 0.1; i=$((i + 1)); done
    kill -KILL "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  fi
  rm -f "$W/service.pid"
}
cleanup() {
  [ -z "$TIMER_PID" ] || kill "$TIMER_PID" 2>/dev/null || true
  stop_service
  if [ -n "${TELESPHERE_MONADO_LOG:-}" ] && [ -f "$W/service.log" ]; then cp "$W/service.log" "$TELESPHERE_MONADO_LOG"; fi
  rm -rf "$W"
}
trap cleanup EXIT
# Ctrl-C / TERM go to CMD (it is in our process group); we wait for it to finish.
trap 'if [ -n "$CMD_PID" ]; then kill -INT "$CMD_PID" 2>/dev/null || true; fi' INT
trap 'if [ -n "$CMD_PID" ]; then kill -TERM "$CMD_PID" 2>/dev/null || true; fi' TERM

LP=$M/pulseaudio:$M/blas:$M/lapack:$M:$T/lib/x86_64-linux-gnu:$T/usr/lib
printf '{"file_format_version":"1.0.0","runtime":{"name":"Monado","library_path":"%s"}}\n' \
  "$M/libopenxr_monado.so" > "$W/monado.json"
export XDG_RUNTIME_DIR="$W/xdg" XR_RUNTIME_JSON="$W/monado.json"
export VK_ICD_FILENAMES="$T/usr/share/vulkan/icd.d/lvp_icd.json"
export __EGL_VENDOR_LIBRARY_DIRS="$T/usr/share/glvnd/egl_vendor.d"
export XRT_COMPOSITOR_NULL=1 SIMULATED_ENABLE=1 XRT_NO_STDIN=1
# Told to the command so it can say which runtime it ran against.
export TELESPHERE_MONADO_ROOT_USED="$T"

start_service() {
  rm -f "$W/xdg/monado_comp_ipc"
  "$LD" --library-path "$LP" "$T/usr/bin/monado-service" >> "$W/service.log" 2>&1 < /dev/null &
  pid=$!
  echo "$pid" > "$W/service.pid"
  i=0
  limit=$((WAIT_S * 10))
  until [ -S "$W/xdg/monado_comp_ipc" ]; do
    if ! alive "$pid"; then
      tail -n 30 "$W/service.log" >&2 || true
      rm -f "$W/service.pid"
      die "monado-service exited before its socket appeared (log above)"
    fi
    i=$((i + 1))
    if [ $i -gt "$limit" ]; then
      tail -n 30 "$W/service.log" >&2 || true
      die "monado-service did not create $W/xdg/monado_comp_ipc within ${WAIT_S} s (log above)"
    fi
    sleep 0.1
  done
}
start_service

if [ -n "$PRELOAD" ]; then
  "$LD" --library-path "$LP" --preload "$PRELOAD" "$@" &
else
  "$LD" --library-path "$LP" "$@" &
fi
CMD_PID=$!
if [ -n "$STOP_AFTER" ]; then
  ( sleep "$STOP_AFTER"; stop_service; say "stopped monado-service after ${STOP_AFTER} s" ) &
  TIMER_PID=$!
elif [ -n "$RESTART_AFTER" ]; then
  ( sleep "$RESTART_AFTER"; stop_service; say "stopped monado-service after ${RESTART_AFTER} s"
    sleep 2; start_service; say "started monado-service again" ) &
  TIMER_PID=$!
fi
# `wait` returns early when a trapped signal arrives: wait again until CMD is really gone.
set +e
while :; do
  wait "$CMD_PID"
  STATUS=$?
  kill -0 "$CMD_PID" 2>/dev/null || break
done
set -e
CMD_PID=
exit "$STATUS"
