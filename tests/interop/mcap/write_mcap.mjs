#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Writes a reference MCAP file with the MCAP project's own writer (@mcap/core McapWriter), so that
// our C++ reader can be tested on a file it did not write.
//
//   node write_mcap.mjs OUT.mcap [--compression none|zstd|lz4] [--proto PATH] [--chunk-size BYTES]
//
// Content: schema telesphere.link.proto.RobotState and .HeadTarget (encoding "protobuf", data a
// binary google.protobuf.FileDescriptorSet made from telesphere_link.proto by protobufjs),
// channel /robot_state (500 RobotState, log_time = 1e9 + i*10e6 ns, sequence i, t_ns = log_time,
// joint_positions[j] = i*0.001 + j for 6 joints) and channel /head_target (100 HeadTarget,
// log_time = 1e9 + k*50e6 + 5e6 ns). publish_time = log_time. Chunked (default 4 KiB chunks), with
// message indexes, chunk indexes, statistics, summary offsets and every CRC.
// --proto defaults to $TELESPHERE_LINK_PROTO, then to robot/link/telesphere_link.proto of the
// source tree this script sits in (tests/interop/mcap/); pass it when running from a copy.
// Prints {"messages": 600, "topics": {...}, ...} on stdout; exits 1 with one line on stderr on error.
import { open, readFile } from "node:fs/promises";
import { basename } from "node:path";
import { fileURLToPath } from "node:url";
import { McapWriter } from "@mcap/core";
import { FileHandleWritable } from "@mcap/nodejs";
import protobuf from "protobufjs";
import descriptor from "protobufjs/ext/descriptor/index.js";
import zstd from "@foxglove/wasm-zstd";
import lz4js from "lz4js";

function fail(message) {
  process.stderr.write(`write_mcap: ${String(message).replace(/\s*\n\s*/g, " ")}\n`);
  process.exit(1);
}

function parseArgs(argv) {
  const args = { out: undefined, compression: "none", chunkSize: 4096,
                 proto: process.env.TELESPHERE_LINK_PROTO ||
                        fileURLToPath(new URL("../../../robot/link/telesphere_link.proto", import.meta.url)) };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    if (a === "--compression") args.compression = argv[++i];
    else if (a === "--proto") args.proto = argv[++i];
    else if (a === "--chunk-size") args.chunkSize = Number(argv[++i]);
    else if (a.startsWith("--") || args.out !== undefined) fail(`unknown argument ${a}`);
    else args.out = a;
  }
  if (!args.out) fail("usage: write_mcap.mjs OUT.mcap [--compression none|zstd|lz4] [--proto PATH] [--chunk-size BYTES]");
  if (!["none", "zstd", "lz4"].includes(args.compression)) fail(`unknown compression ${args.compression}`);
  if (!(args.chunkSize > 0)) fail("--chunk-size must be a positive number");
  return args;
}

// Both codecs write one complete frame per chunk: a zstd frame, an LZ4 *frame* (not a raw block).
function chunkCompressor(name) {
  if (name === "zstd") return (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) });
  if (name === "lz4") return (data) => ({ compression: "lz4", compressedData: Uint8Array.from(lz4js.compress(data)) });
  return undefined; // compression "" (records stored as they are)
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  await zstd.isLoaded;

  // keepCase: field names stay as written in the .proto (t_ns, not tNs), also in the descriptor.
  // The FileDescriptorProto is named after the .proto file (protobufjs would say telesphere_link_proto.proto).
  let root;
  try {
    const parsed = protobuf.parse(await readFile(args.proto, "utf8"), { keepCase: true });
    root = parsed.root.resolveAll();
    root.lookup(parsed.package).filename = basename(args.proto);
  } catch (e) {
    fail(`cannot load ${args.proto} (pass --proto PATH): ${e.message}`);
  }
  const schemaData = descriptor.FileDescriptorSet.encode(root.toDescriptor("proto3")).finish();
  const RobotState = root.lookupType("telesphere.link.proto.RobotState");
  const HeadTarget = root.lookupType("telesphere.link.proto.HeadTarget");

  const fh = await open(args.out, "w");
  const writer = new McapWriter({
    writable: new FileHandleWritable(fh),
    chunkSize: args.chunkSize,
    compressChunk: chunkCompressor(args.compression),
  });
  await writer.start({ profile: "", library: "telesphere tests/interop/mcap/write_mcap.mjs" });
  const channels = {};
  for (const [topic, type] of [["/robot_state", RobotState], ["/head_target", HeadTarget]]) {
    const schemaId = await writer.registerSchema({
      name: type.fullName.slice(1), encoding: "protobuf", data: schemaData });
    channels[topic] = await writer.registerChannel({
      schemaId, topic, messageEncoding: "protobuf", metadata: new Map() });
  }

  // Messages in log-time order: RobotState every 10 ms, HeadTarget every 50 ms (5 ms after one).
  const messages = [];
  for (let i = 0; i < 500; ++i) {
    const t = 1_000_000_000n + BigInt(i) * 10_000_000n;
    messages.push({ topic: "/robot_state", sequence: i, logTime: t, data: RobotState.encode(RobotState.fromObject({
      t_ns: t.toString(),
      joint_positions: Array.from({ length: 6 }, (_, j) => i * 0.001 + j),
      T_robot_flange: { tz: 0.5, qw: 1 },
      visual_mode: "VISUAL_MODE_FULL6D",
      arm_ok: true,
      sphere_radius: 2.5,
      calibration_generation: 1,
    })).finish() });
  }
  for (let k = 0; k < 100; ++k) {
    const t = 1_005_000_000n + BigInt(k) * 50_000_000n;
    messages.push({ topic: "/head_target", sequence: k, logTime: t, data: HeadTarget.encode(HeadTarget.fromObject({
      t_ns: t.toString(),
      predicted_display_ns: (t + 20_000_000n).toString(),
      T_vr_hmd: { ty: 1.6, qw: 1 },
      valid: true,
      t_robot_ns: t.toString(),
      sender_instance: "18364758544493064720", // 0xfedcba9876543210: above 2^63
    })).finish() });
  }
  messages.sort((a, b) => (a.logTime < b.logTime ? -1 : a.logTime > b.logTime ? 1 : 0));

  const topics = {};
  for (const m of messages) {
    await writer.addMessage({ channelId: channels[m.topic], sequence: m.sequence,
                              logTime: m.logTime, publishTime: m.logTime, data: m.data });
    topics[m.topic] = (topics[m.topic] ?? 0) + 1;
  }
  await writer.end();
  const bytes = (await fh.stat()).size;
  await fh.close();
  process.stdout.write(JSON.stringify({ file: args.out, bytes, compression: args.compression,
                                        messages: messages.length, topics }) + "\n");
}

main().catch((e) => fail(e?.message ?? e));
