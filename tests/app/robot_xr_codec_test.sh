#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @brief H.264 and HEVC end to end (#34), real programs on loopback: telesphere-robot --codec
#        (simulated arm, synthetic cameras, recording) and telesphere-xr offscreen live against it.
#        For each codec: the robot says which encoder it uses; the operator app shows camera
#        images (stats.json names the codec; a join part way asks for a key frame and gets it);
#        the recording replays twice into byte-equal PNGs with nothing undecodable, every recorded
#        frame shown; and every PNG of the live run, rendered again from the recording with the
#        frame and head pose it showed (views.csv), is byte-equal to the live one: the operator
#        saw what the recording holds. The supervisor switches a running robot from MJPEG to HEVC
#        (`telesphere-console control codec`) over the UDP media path and the operator app follows
#        without a gap. Refused with the reason: an unknown codec.
# Usage: robot_xr_codec_test.sh BIN_DIR SOURCE_DIR PORT
set -euo pipefail
bin=$1 src=$2 port=$3
out=$(mktemp -d -t telesphere-codec.XXXXXX)
robot=
xr=
cleanup() { [ -n "$robot" ] && kill "$robot" 2>/dev/null; [ -n "$xr" ] && kill "$xr" 2>/dev/null; rm -rf "$out"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; echo "--- robot log"; cat "$out/robot.log" || true; echo "--- FAIL: $*"; exit 1; }  # the reason last too: CI shows the end
json() { sed -n "s/^ *\"$2\": \"\{0,1\}\([^\",]*\)\"\{0,1\},\{0,1\}$/\1/p" "$1"; }
export EGL_PLATFORM=surfaceless
calib="$src/calib/data/sim_calibration.yaml"

# Refused before anything starts.
if "$bin/telesphere-robot" --insecure --codec vp9 --no-media --port "$port" --duration 1 > "$out/vp9.log" 2>&1; then
  fail "--codec vp9 was taken"
fi

# 2 Mbit/s for 320x180 at 15 Hz (the default 20 made x265 under ASan spend 70-215 ms on 127 kB
# pairs on a loaded CI machine, and the operator app showed 22 frames in 4 s).
for codec in h264 hevc; do
  "$bin/telesphere-robot" --insecure --sim --codec "$codec" --video-mbit 2 --no-media --size 320x180 --fps 15 --port "$port" \
    --duration 120 --stats-period 1 --record "$out/$codec.mcap" > "$out/robot.log" 2>&1 &
  robot=$!
  sleep 1  # the operator app joins a stream part way, as it does in the field
  "$bin/telesphere-xr" offscreen --insecure --calib "$calib" --port "$port" --eye-size 160x176 --rate 30 --duration 4 \
    --wait 60 --png-every 10 --out "$out/$codec-live" > "$out/$codec-live.txt" || fail "$codec: telesphere-xr offscreen exited with $?"
  kill -INT "$robot"
  rc=0
  wait "$robot" || rc=$?
  robot=
  [ "$rc" -eq 0 ] || fail "$codec: telesphere-robot exited with $rc after SIGINT"
  encoder=$([ "$codec" = h264 ] && echo libx264 || echo libx265)
  grep -q "video $codec ($encoder)" "$out/robot.log" || fail "$codec: the robot did not say it encodes with $encoder"
  live="$out/$codec-live/stats.json"
  [ "$(json "$live" video_codec)" = "$codec" ] || fail "$codec: the operator app decoded $(json "$live" video_codec)"
  shown=$(json "$live" stereo_frames_shown)
  [ "$shown" -ge 30 ] || fail "$codec: $shown camera frames shown in 4 s of a 15 Hz stream (60 when idle)"
  # Joined part way: the first frames it saw were predicted ones; it asked for a key frame (unless it
  # happened to join on one) and every frame from there decoded.
  awaiting=$(json "$live" frames_awaiting_key_frame)
  requested=$(json "$live" key_frames_requested)
  [ "$awaiting" -eq 0 ] || [ "$requested" -ge 1 ] || fail "$codec: $awaiting frames waited for a key frame nobody asked for"
  grep -q "asked for by the operator or the media path)" "$out/robot.log" || fail "$codec: no key-frame figures in the robot's log"

  replay() {  # replay NAME [options]
    local name=$1
    shift
    "$bin/telesphere-xr" offscreen --calib "$calib" --replay "$out/$codec.mcap" --eye-size 160x176 --rate 30 \
      --png-every 10 --out "$out/$codec-$name" "$@" > "$out/$codec-$name.txt" || { cat "$out/$codec-$name.txt"; fail "$codec: replay $name exited"; }
  }
  replay first
  replay second
  stats="$out/$codec-first/stats.json"
  [ "$(json "$stats" undecodable)" -eq 0 ] || fail "$codec: $(json "$stats" undecodable) recorded frames did not decode"
  [ "$(json "$stats" awaiting_key_frame)" -eq 0 ] || fail "$codec: the recording (begun with the stream) waited for a key frame"
  recorded=$(json "$stats" recorded_frames)
  replay_shown=$(json "$stats" stereo_frames_shown)
  replaced=$(json "$stats" replaced_unshown)
  [ "$recorded" -ge 30 ] && [ $((replay_shown + replaced)) -eq "$recorded" ] ||
    fail "$codec: $replay_shown of $recorded recorded frames shown, $replaced replaced unshown"
  pngs=0
  for png in "$out/$codec-first"/*.png; do
    cmp -s "$png" "$out/$codec-second/$(basename "$png")" || fail "$codec: $(basename "$png") differs between two replays"
    pngs=$((pngs + 1))
  done
  [ "$pngs" -ge 8 ] || fail "$codec: only $pngs PNGs from the replay"
  replay views --views "$out/$codec-live/views.csv"
  views=$(tail -n +2 "$out/$codec-live/views.csv" | grep -c . || true)
  # 9-10 views here under ASan, 7 on a loaded CI machine (the app renders fewer display frames in
  # its 4 s): what matters is that every one of them equals the replay, and that there are some.
  [ "$views" -ge 4 ] || fail "$codec: only $views views logged by the live run"
  while IFS=, read -r png _; do
    [ "$png" = png ] && continue
    cmp -s "$out/$codec-live/$png" "$out/$codec-views/$png" || fail "$codec: $png: the replay differs from what the live run showed"
  done < "$out/$codec-live/views.csv"
  echo "$codec: $shown frames shown live ($requested key frames asked for, $awaiting frames waited), $recorded recorded, $pngs PNGs twice, $views live views equal"
done
# The supervisor's choice, live, over the UDP media path: the robot starts with MJPEG; two seconds
# into the operator's run the console switches it to HEVC, whose rate then follows the path's
# budget; the operator app follows (the new stream starts with a key frame) and ends showing HEVC
# frames, having shown frames all along.
"$bin/telesphere-robot" --insecure --sim --size 320x180 --fps 15 --port "$port" --duration 120 \
  --stats-period 1 > "$out/robot.log" 2>&1 &
robot=$!
"$bin/telesphere-xr" offscreen --insecure --calib "$calib" --port "$port" --video-link udp --eye-size 160x176 --rate 30 \
  --duration 6 --wait 60 --out "$out/switch" > "$out/switch.txt" &
xr=$!
for _ in $(seq 100); do grep -q "nominal pose captured" "$out/robot.log" && break; sleep 0.1; done
sleep 2
"$bin/telesphere-console" control codec hevc --insecure --robot "tcp://127.0.0.1:$port" > "$out/control.txt" 2>&1 ||
  { cat "$out/control.txt"; fail "the console could not switch the codec"; }
wait "$xr" || fail "switch: telesphere-xr offscreen exited with $?"
xr=
"$bin/telesphere-console" status --insecure --robot "tcp://127.0.0.1:$port" > "$out/status.txt" 2>&1 || true
kill -INT "$robot"
wait "$robot" || true
robot=
grep -q "video      hevc (libx265)" "$out/status.txt" || { cat "$out/status.txt"; fail "the status does not show the chosen codec"; }
[ "$(json "$out/switch/stats.json" video_codec)" = hevc ] || fail "after the switch the operator app decoded $(json "$out/switch/stats.json" video_codec)"
shown=$(json "$out/switch/stats.json" stereo_frames_shown)
[ "$shown" -ge 45 ] || fail "switch: $shown camera frames shown in 6 s of a 15 Hz stream (90 when idle)"
grep -q "media path: receiver" "$out/robot.log" || fail "switch: the operator app never listened on the media path"
grep -q "frames whole" "$out/switch.txt" || { cat "$out/switch.txt"; fail "switch: the operator app did not report the media path"; }
echo "switch: MJPEG then HEVC over the media path, $shown frames shown in 6 s"
echo "PASS: H.264 and HEVC from the robot to the operator app and from the recording; the codec switched live"
