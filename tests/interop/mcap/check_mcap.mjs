#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Checks an MCAP file with the MCAP project's own reader (@mcap/core), independently of our C++ code.
//
//   node check_mcap.mjs FILE
//
// 1. The MCAP magic at both ends (our own check, for a clear message on a truncated file).
// 2. McapIndexedReader.Initialize: Header, Footer, DataEnd right before summary_start, the summary
//    records, and the summary CRC (the library checks it when the Footer's summary_crc is not 0).
//    A summary (summary_start != 0) and a Statistics record are required.
// 3. Every schema: encoding "protobuf", data a binary FileDescriptorSet that defines the schema's
//    name; every channel: message_encoding "protobuf" and a schema in the summary.
// 4. readMessages({validateCrcs: true}): every chunk reached through a Chunk Index, with its
//    uncompressed_crc, and every message through the Message Index offsets (relative to the
//    uncompressed chunk records); each message is walked on the wire and decoded with its type.
// 5. McapStreamReader({validateCrcs: true}) over the whole file, linearly: every chunk's CRC again
//    (chunks without messages too), the records inside chunks, Footer, trailing magic, no extra bytes.
// 6. The DataEnd data_section_crc over bytes [0, offset of DataEnd): the library does not check it.
// 7. Summary layout (our own check): records grouped by opcode, every Summary Offset group holding
//    only its opcode, the Footer's summary_offset_start at the first Summary Offset record.
// 8. Cross-checks: both readers see the same messages per channel; the Statistics message, channel,
//    schema and chunk counts, channel_message_counts and start/end times match what was read.
// 9. Attachments and metadata: read linearly (every attachment's CRC validated) and through their
//    Attachment and Metadata Index records (again with CRCs); the same ones both ways, as many as
//    Statistics says.
// Prints one JSON object on stdout; exits 1 with one line on stderr on any error.
import { open, readFile } from "node:fs/promises";
import { crc32 } from "node:zlib";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { FileHandleReadable } from "@mcap/nodejs";
import protobuf from "protobufjs";
import descriptor from "protobufjs/ext/descriptor/index.js";
import zstd from "@foxglove/wasm-zstd";
import lz4 from "@foxglove/wasm-lz4";

let dataCrcNote = ""; // set when the data section CRC is known to be wrong, added to any earlier error
function fail(message) {
  process.stderr.write(`check_mcap: ${String(message).replace(/\s*\n\s*/g, " ")}${dataCrcNote}\n`);
  process.exit(1);
}
function check(ok, message) {
  if (!ok) fail(message);
}

// zstd: one zstd frame; lz4: one LZ4 frame (LZ4F, not a raw block), as the MCAP libraries write them.
function decompress(name, fn, buf, size) {
  let out;
  try {
    out = fn(buf, Number(size));
  } catch (e) {
    fail(`${name} chunk (${buf.byteLength} bytes) does not decompress to ${size} bytes: ${e.message}`);
  }
  check(out.byteLength === Number(size), `${name} chunk decompressed to ${out.byteLength} bytes, uncompressed_size says ${size}`);
  return new Uint8Array(out); // a copy that owns its memory
}
const decompressHandlers = {
  zstd: (buf, size) => decompress("zstd", zstd.decompress, buf, size),
  lz4: (buf, size) => decompress("lz4", lz4, buf, size),
};

// protobufjs decodes leniently (it does not check wire types of known fields and accepts a truncated
// 64-bit varint at the end), so every message is first walked on the wire against its type: known
// field numbers only, wire types that fit the field (packed repeated scalars allowed), varints and
// lengths within the buffer, valid UTF-8 in strings, nested messages likewise. Field order is free.
const fixedWire = { double: 1, fixed64: 1, sfixed64: 1, float: 5, fixed32: 5, sfixed32: 5, string: 2, bytes: 2 };
const utf8 = new TextDecoder("utf-8", { fatal: true });
function varint(b, p, what) {
  for (let n = 0; n < 10; ++n) {
    if (p + n >= b.length) throw new Error(`${what}: truncated varint`);
    if (b[p + n] < 0x80) return p + n + 1;
  }
  throw new Error(`${what}: varint longer than 10 bytes`);
}
function varintValue(b, p) { // only after varint() has checked that it ends in the buffer
  let v = 0n;
  for (let shift = 0n; ; shift += 7n) { v |= BigInt(b[p] & 0x7f) << shift; if (b[p++] < 0x80) return v; }
}
function checkWire(type, b, path) {
  for (let p = 0; p < b.length; ) {
    const tagEnd = varint(b, p, `${path} tag`), tag = varintValue(b, p);
    p = tagEnd;
    const id = Number(tag >> 3n), wire = Number(tag & 7n), field = type.fieldsById[id];
    const name = `${path}.${field?.name ?? id}`;
    if (!field) throw new Error(`${name}: field number ${id} is not in ${type.fullName.slice(1)}`);
    const isMessage = field.resolvedType instanceof protobuf.Type || field.map;
    const want = isMessage ? 2 : fixedWire[field.type] ?? 0; // varint: ints, bool, enums
    const packed = field.repeated && wire === 2 && want !== 2;
    if (wire !== want && !packed) throw new Error(`${name}: wire type ${wire}, but ${field.type} needs ${want}`);
    if (wire === 0) { p = varint(b, p, name); continue; }
    let len = wire === 1 ? 8 : 4;
    if (wire === 2) { const lenEnd = varint(b, p, name); len = Number(varintValue(b, p)); p = lenEnd; }
    if (p + len > b.length) throw new Error(`${name}: ${len} bytes run past the end of the message`);
    const body = b.subarray(p, p += len);
    if (field.map) continue;
    if (isMessage) checkWire(field.resolvedType, body, name);
    else if (field.type === "string") try { utf8.decode(body); } catch { throw new Error(`${name}: not valid UTF-8`); }
    else if (packed && want === 0) for (let q = 0; q < body.length; ) q = varint(body, q, name);
    else if (packed && body.length % (want === 1 ? 8 : 4) !== 0) throw new Error(`${name}: packed length ${body.length}`);
  }
}

// toObject options for the "first" message: longs and enums as strings, NaN/Infinity as strings,
// bytes as base64 cut to 64 characters, defaults included so that every field is present.
const toObjectOptions = { longs: String, enums: String, bytes: String, defaults: true, arrays: true, json: true };
function shortenBytes(type, obj) {
  for (const field of type.fieldsArray) {
    const v = obj[field.name];
    if (v == null || field.map) continue;
    const values = Array.isArray(v) ? v : [v];
    if (field.type === "bytes") {
      const cut = values.map((s) => s.slice(0, 64));
      obj[field.name] = Array.isArray(v) ? cut : cut[0];
    } else if (field.resolvedType instanceof protobuf.Type) {
      for (const m of values) shortenBytes(field.resolvedType, m);
    }
  }
  return obj;
}

// Records [opcode u8][content length u64 LE][content], back to back from start to end.
function records(bytes, start, end, what) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const list = [];
  for (let pos = start; pos < end; pos += 9 + Number(view.getBigUint64(pos + 1, true))) {
    check(pos + 9 <= end, `${what}: a record header at ${pos} runs past ${end}`);
    list.push({ opcode: bytes[pos], pos });
  }
  check(end === (list.length ? list.at(-1).pos + 9 + Number(view.getBigUint64(list.at(-1).pos + 1, true)) : start),
        `${what} does not end on a record boundary at ${end}`);
  return list;
}
function checkSummaryLayout(bytes, reader) {
  const hex = (op) => `0x${op.toString(16).padStart(2, "0")}`;
  const footerPos = bytes.length - 8 - 29; // Footer: opcode, length, 8 + 8 + 4 bytes; then magic
  const summary = records(bytes, Number(reader.footer.summaryStart), footerPos, "summary section");
  const seen = new Set();
  summary.forEach((r, i) => {
    check(i === 0 || r.opcode === summary[i - 1].opcode || !seen.has(r.opcode),
          `summary records of opcode ${hex(r.opcode)} are not grouped together (again at ${r.pos})`);
    seen.add(r.opcode);
  });
  const firstOffset = summary.find((r) => r.opcode === 0x0e)?.pos ?? 0;
  check(BigInt(firstOffset) === reader.footer.summaryOffsetStart,
        `Footer summary_offset_start ${reader.footer.summaryOffsetStart}, the first Summary Offset record is at ${firstOffset}`);
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const groups = new Set();
  for (const so of summary.filter((r) => r.opcode === 0x0e)) { // group_opcode u8, group_start u64, group_length u64
    const opcode = bytes[so.pos + 9], start = Number(view.getBigUint64(so.pos + 10, true));
    const length = Number(view.getBigUint64(so.pos + 18, true));
    const what = `summary offset group ${hex(opcode)} [${start}, +${length})`;
    check(!groups.has(opcode), `two Summary Offset records for opcode ${hex(opcode)}`);
    groups.add(opcode);
    check(start >= Number(reader.footer.summaryStart) && start + length <= footerPos, `${what} lies outside the summary`);
    const inGroup = records(bytes, start, start + length, what);
    for (const r of inGroup) check(r.opcode === opcode, `${what} holds a record of opcode ${hex(r.opcode)} at ${r.pos}`);
    check(inGroup.length === summary.filter((r) => r.opcode === opcode).length, `${what} does not cover every ${hex(opcode)} record of the summary`);
  }
}

async function main() {
  const file = process.argv[2];
  check(file && process.argv.length === 3, "usage: check_mcap.mjs FILE");
  await zstd.isLoaded;
  await lz4.isLoaded;
  const bytes = await readFile(file);
  // --- 1. magic ---
  const magic = Buffer.from([0x89, 0x4d, 0x43, 0x41, 0x50, 0x30, 0x0d, 0x0a]); // \x89 M C A P 0 \r \n
  check(bytes.length >= 8 && bytes.subarray(0, 8).equals(magic), `${file} does not start with the MCAP magic`);
  check(bytes.length >= 16 && bytes.subarray(-8).equals(magic),
        `${file} (${bytes.length} bytes) does not end with the MCAP magic: truncated, or its writer did not finish`);

  // --- 2. indexed reading: header, footer, summary ---
  const fh = await open(file, "r");
  const reader = await McapIndexedReader.Initialize({ readable: new FileHandleReadable(fh), decompressHandlers });
  check(reader.statistics, "no Statistics record in the summary");

  const dataCrc = crc32(bytes.subarray(0, Number(reader.dataEndOffset)));
  if (reader.dataSectionCrc !== undefined && dataCrc !== reader.dataSectionCrc) {
    dataCrcNote = `; Incorrect data section CRC ${dataCrc} (expected ${reader.dataSectionCrc}) over bytes [0, ${reader.dataEndOffset})`;
  }

  // --- 3. schemas and channels ---
  const types = new Map(); // schema id -> protobufjs Type
  for (const schema of reader.schemasById.values()) {
    check(schema.encoding === "protobuf", `schema ${schema.id} (${schema.name}) has encoding "${schema.encoding}", not "protobuf"`);
    let type;
    try {
      const root = protobuf.Root.fromDescriptor(descriptor.FileDescriptorSet.decode(schema.data));
      type = root.lookupType(schema.name);
    } catch (e) {
      fail(`schema ${schema.id} (${schema.name}): ${e.message}`);
    }
    types.set(schema.id, type);
  }
  const topics = {};
  for (const channel of reader.channelsById.values()) {
    check(channel.messageEncoding === "protobuf", `channel ${channel.id} (${channel.topic}) has message_encoding "${channel.messageEncoding}"`);
    check(types.has(channel.schemaId), `channel ${channel.id} (${channel.topic}) refers to schema ${channel.schemaId}, not in the summary`);
    topics[channel.topic] = { count: 0, schema: reader.schemasById.get(channel.schemaId).name, schema_encoding: "protobuf",
                              message_encoding: channel.messageEncoding, first: null };
  }

  // --- 4. every message, in log-time order, through the Chunk Indexes and Message Indexes ---
  const perChannel = new Map();
  let messages = 0, decoded = 0, start, end;
  for await (const msg of reader.readMessages({ validateCrcs: true })) {
    const channel = reader.channelsById.get(msg.channelId);
    check(channel, `message on channel ${msg.channelId}, which is not in the summary`);
    const type = types.get(channel.schemaId);
    let value;
    try {
      checkWire(type, msg.data, type.name);
      value = type.decode(msg.data);
    } catch (e) {
      fail(`message ${messages} on ${channel.topic} (log_time ${msg.logTime}) does not decode as ${type.fullName.slice(1)}: ${e.message}`);
    }
    ++messages; ++decoded;
    const topic = topics[channel.topic];
    if (topic.count++ === 0) topic.first = shortenBytes(type, type.toObject(value, toObjectOptions));
    perChannel.set(msg.channelId, (perChannel.get(msg.channelId) ?? 0n) + 1n);
    if (start === undefined || msg.logTime < start) start = msg.logTime;
    if (end === undefined || msg.logTime > end) end = msg.logTime;
  }
  await fh.close();

  // --- 5. linear reading ---
  const stream = new McapStreamReader({ validateCrcs: true, includeChunks: true, decompressHandlers });
  stream.append(bytes);
  const streamPerChannel = new Map();
  let streamMessages = 0, streamChunks = 0, chunksWithCrc = 0, dataEndSeen = false;
  const streamAttachments = [], streamMetadata = [];
  for (let record; (record = stream.nextRecord()); ) {
    if (record.type === "Message") {
      ++streamMessages;
      streamPerChannel.set(record.channelId, (streamPerChannel.get(record.channelId) ?? 0n) + 1n);
    } else if (record.type === "Chunk") {
      ++streamChunks;
      if (record.uncompressedCrc !== 0) ++chunksWithCrc;
    } else if (record.type === "DataEnd") {
      dataEndSeen = true;
    } else if (record.type === "Attachment") {
      streamAttachments.push({ name: record.name, media_type: record.mediaType, log_time: String(record.logTime),
                               size: record.data.byteLength });
    } else if (record.type === "Metadata") {
      streamMetadata.push({ name: record.name, metadata: Object.fromEntries(record.metadata) });
    }
  }
  check(stream.done(), `the file ends before the Footer and trailing magic (${stream.bytesRemaining()} bytes unparsed): truncated?`);
  check(dataEndSeen, "no DataEnd record");
  if (dataCrcNote) { // --- 6. (computed above, so that an earlier error mentions it too)
    const message = dataCrcNote.slice(2);
    dataCrcNote = "";
    fail(message);
  }

  // --- 7. summary layout ---
  checkSummaryLayout(bytes, reader);

  // --- 8. cross-checks ---
  const stats = reader.statistics;
  check(streamMessages === messages, `the linear read found ${streamMessages} messages, the indexed read ${messages}`);
  for (const [id, n] of streamPerChannel) check(perChannel.get(id) === n, `channel ${id}: ${n} messages read linearly, ${perChannel.get(id) ?? 0} through the index`);
  check(stats.messageCount === BigInt(messages), `Statistics message_count ${stats.messageCount}, read ${messages}`);
  check(stats.chunkCount === reader.chunkIndexes.length && stats.chunkCount === streamChunks,
        `Statistics chunk_count ${stats.chunkCount}, ${reader.chunkIndexes.length} Chunk Index records, ${streamChunks} Chunk records`);
  check(stats.channelCount === reader.channelsById.size, `Statistics channel_count ${stats.channelCount}, ${reader.channelsById.size} channels in the summary`);
  check(stats.schemaCount === reader.schemasById.size, `Statistics schema_count ${stats.schemaCount}, ${reader.schemasById.size} schemas in the summary`);
  for (const [id, n] of stats.channelMessageCounts) check((perChannel.get(id) ?? 0n) === n, `Statistics channel_message_counts[${id}] = ${n}, read ${perChannel.get(id) ?? 0}`);
  if (messages > 0) {
    check(stats.messageStartTime === start && stats.messageEndTime === end,
          `Statistics times [${stats.messageStartTime}, ${stats.messageEndTime}], messages span [${start}, ${end}]`);
  }

  // --- 9. attachments and metadata, through their indexes too ---
  check(stats.attachmentCount === streamAttachments.length && reader.attachmentIndexes.length === streamAttachments.length,
        `Statistics attachment_count ${stats.attachmentCount}, ${reader.attachmentIndexes.length} Attachment Index records, ${streamAttachments.length} attachments`);
  check(stats.metadataCount === streamMetadata.length && reader.metadataIndexes.length === streamMetadata.length,
        `Statistics metadata_count ${stats.metadataCount}, ${reader.metadataIndexes.length} Metadata Index records, ${streamMetadata.length} metadata records`);
  const fh2 = await open(file, "r");
  const indexed = await McapIndexedReader.Initialize({ readable: new FileHandleReadable(fh2), decompressHandlers });
  const viaIndex = [];
  for await (const a of indexed.readAttachments({ validateCrcs: true })) viaIndex.push(a.name);
  const metadataViaIndex = [];
  for await (const m of indexed.readMetadata()) metadataViaIndex.push(m.name);
  await fh2.close();
  check(JSON.stringify(viaIndex) === JSON.stringify(streamAttachments.map((a) => a.name)),
        `attachments through the index ${JSON.stringify(viaIndex)}, linearly ${JSON.stringify(streamAttachments.map((a) => a.name))}`);
  check(JSON.stringify(metadataViaIndex) === JSON.stringify(streamMetadata.map((m) => m.name)),
        `metadata through the index ${JSON.stringify(metadataViaIndex)}, linearly ${JSON.stringify(streamMetadata.map((m) => m.name))}`);

  const compression = [...new Set(reader.chunkIndexes.map((c) => c.compression || "none"))].sort();
  process.stdout.write(JSON.stringify({
    messages, decoded, chunks: reader.chunkIndexes.length, compression,
    start_ns: String(start ?? 0n), end_ns: String(end ?? 0n), topics,
    statistics: { message_count: Number(stats.messageCount), channel_count: stats.channelCount,
                  schema_count: stats.schemaCount, chunk_count: stats.chunkCount },
    stream_reader_messages: streamMessages,
    attachments: streamAttachments, metadata: streamMetadata,
    crc_checked: { data_section: reader.dataSectionCrc !== undefined, summary: reader.footer.summaryCrc !== 0,
                   chunks: chunksWithCrc },
    library: reader.header.library, profile: reader.header.profile,
  }) + "\n");
}

main().catch((e) => fail(e?.message ?? e));
