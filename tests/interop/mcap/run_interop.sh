#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# mcap_interop (ctest): sessions recorded by telesphere-robot --record (each chunk compression)
# are read by the MCAP project's TypeScript reader (check_mcap.mjs: every CRC, every message
# decoded through its embedded schema, the summary cross-checked), and its counts must equal what
# `telesphere-mcap summary --json` says; files written by the MCAP project's writer
# (write_mcap.mjs, each compression) pass `telesphere-mcap check` and give the same counts.
#   run_interop.sh SOURCE_DIR BUILD_DIR WORK_DIR        exit 77: skipped (no node/npm)
set -euo pipefail
src=$1 build=$2 work=$3
here=$src/tests/interop/mcap
command -v node >/dev/null && command -v npm >/dev/null || { echo "mcap_interop: no node/npm: skipped"; exit 77; }
mkdir -p "$work"
# The MCAP project's packages, installed once per build tree (again when the lockfile changes).
if ! cmp -s "$here/package-lock.json" "$work/package-lock.json" || [[ ! -d $work/node_modules/@mcap/core ]]; then
  rm -f "$work/package-lock.json"
  cp "$here/package.json" "$work/"
  cp "$here/package-lock.json" "$work/package-lock.json.new"
  mv "$work/package-lock.json.new" "$work/package-lock.json"
  # The lockfile's copy stays only once the install succeeded (the check above compares it).
  npm ci --no-audit --no-fund --ignore-scripts --prefix "$work" >"$work/npm.log" 2>&1 ||
    { rm -f "$work/package-lock.json"; echo "mcap_interop: npm ci failed:"; cat "$work/npm.log"; exit 1; }
fi
cp "$here/check_mcap.mjs" "$here/write_mcap.mjs" "$work/"
bin=$build/bin
fail() { echo "mcap_interop: $*" >&2; exit 1; }

# Our recordings, read by theirs.
port=28150
for compression in none lz4 zstd; do
  file=$work/session-$compression.mcap
  rm -f "$file"
  "$bin/telesphere-robot" --insecure --sim --port $port --size 320x180 --fps 15 --duration 3 --stats-period 0 \
    --record "$file" --record-compression $compression >"$work/robot-$compression.log" 2>&1 ||
    { cat "$work/robot-$compression.log"; fail "telesphere-robot --record failed ($compression)"; }
  theirs=$(node "$work/check_mcap.mjs" "$file") || fail "check_mcap.mjs refused our $compression recording"
  ours=$("$bin/telesphere-mcap" summary --json "$file") || fail "telesphere-mcap summary failed on $file"
  node - "$compression" "$theirs" "$ours" <<'JS'
const [compression, theirsText, oursText] = process.argv.slice(2);
const theirs = JSON.parse(theirsText), ours = JSON.parse(oursText);
const fail = (m) => { console.error(`mcap_interop (${compression}): ${m}`); process.exit(1); };
if (theirs.messages !== ours.messages || theirs.decoded !== theirs.messages) fail(`messages ${theirs.messages} decoded ${theirs.decoded} vs ours ${ours.messages}`);
const want = { "/stereo/frame": 20, "/stereo/left/compressed": 20, "/stereo/right/compressed": 20, "/robot/state": 100, "/robot/health": 4 };
for (const [topic, least] of Object.entries(want)) {
  const t = theirs.topics[topic];
  if (!t || t.count < least) fail(`${topic}: ${t ? t.count : 0} messages, expected at least ${least}`);
  if (t.count !== ours.channels[topic].messages) fail(`${topic}: ${t.count} vs ours ${ours.channels[topic].messages}`);
  if (t.schema !== ours.channels[topic].schema) fail(`${topic}: schema ${t.schema} vs ${ours.channels[topic].schema}`);
}
if (theirs.topics["/stereo/left/compressed"].schema !== "foxglove.CompressedImage") fail("images are not foxglove.CompressedImage");
if (theirs.topics["/stereo/left/compressed"].first.format !== "jpeg") fail("image format is not jpeg");
// What Foxglove needs beyond the images: poses on /tf, the date (log times on UTC), which robot,
// the calibration the frames were taken with.
const tf = theirs.topics["/tf"];
if (!tf || tf.count < 100 || tf.schema !== "foxglove.FrameTransform") fail(`/tf: ${JSON.stringify(tf && { count: tf.count, schema: tf.schema })}`);
const parent = tf.first.parent_frame_id ?? tf.first.parentFrameId;
if (parent !== "robot") fail(`/tf parent ${parent}`);
if (!(BigInt(theirs.start_ns) > 1700000000000000000n)) fail(`log times are not on UTC: start ${theirs.start_ns}`);
const meta = theirs.metadata.find((m) => m.name === "telesphere");
if (!meta || !meta.metadata.steady_to_utc_offset_ns || !meta.metadata.software || meta.metadata.arm !== "simulated xArm 6")
  fail(`metadata ${JSON.stringify(theirs.metadata)}`);
const calibration = theirs.attachments.find((a) => a.name === "calibration-generation-1.yaml");
if (!calibration || calibration.media_type !== "application/yaml" || calibration.size < 200) fail(`attachments ${JSON.stringify(theirs.attachments)}`);
if (ours.attachments !== theirs.attachments.length || ours.metadata !== theirs.metadata.length) fail(`attachments/metadata ${ours.attachments}/${ours.metadata} vs theirs ${theirs.attachments.length}/${theirs.metadata.length}`);
const crc = theirs.crc_checked || {};
if (!crc.data_section || !crc.summary || !(crc.chunks > 0)) fail(`not every CRC was there to check: ${JSON.stringify(crc)}`);
const c = compression === "none" ? "" : compression;
if (JSON.stringify(ours.compression) !== JSON.stringify([compression])) fail(`compression ${ours.compression}`);
console.log(`ours (${compression}): ${theirs.messages} messages on ${Object.keys(theirs.topics).length} topics, ` +
            `${theirs.chunks} chunks, every CRC checked and every message decoded by @mcap/core + protobufjs` + (c ? "" : ""));
JS
done

# Theirs, read by ours.
for compression in none lz4 zstd; do
  file=$work/theirs-$compression.mcap
  theirs=$(node "$work/write_mcap.mjs" "$file" --compression $compression --proto "$src/robot/link/telesphere_link.proto") ||
    fail "write_mcap.mjs failed ($compression)"
  "$bin/telesphere-mcap" check "$file" >"$work/check-$compression.log" 2>&1 ||
    { cat "$work/check-$compression.log"; fail "telesphere-mcap check refused their $compression file"; }
  ours=$("$bin/telesphere-mcap" summary --json "$file") || fail "summary of their $compression file"
  scanned=$("$bin/telesphere-mcap" summary --json --scan "$file") || fail "scan of their $compression file"
  node - "$compression" "$theirs" "$ours" "$scanned" <<'JS'
const [compression, theirsText, oursText, scannedText] = process.argv.slice(2);
const theirs = JSON.parse(theirsText), ours = JSON.parse(oursText), scanned = JSON.parse(scannedText);
const fail = (m) => { console.error(`mcap_interop (theirs, ${compression}): ${m}`); process.exit(1); };
for (const s of [ours, scanned]) {
  if (s.messages !== theirs.messages) fail(`${s.messages} messages read, ${theirs.messages} written`);
  for (const [topic, n] of Object.entries(theirs.topics)) {
    const got = s.channels[topic] ? s.channels[topic].messages : 0;
    if (got !== n) fail(`${topic}: ${got} read, ${n} written`);
  }
}
console.log(`theirs (${compression}): ${theirs.messages} messages read back by telesphere-mcap (summary and full scan)`);
JS
done
echo "mcap_interop: passed"
