// SPDX-License-Identifier: MIT
/// @brief recoverMcap (see mcap_recover.h).
#include "robot/record/mcap_recover.h"

#include <map>

#include "robot/record/mcap_reader.h"

namespace telesphere::record {

bool recoverMcap(const std::string& in, const std::string& out, const McapWriterOptions& options,
                 McapRecoverReport* report, std::string* error) {
  *report = {};
  auto reader = McapReader::open(in, error);
  if (!reader) return false;
  report->file_bytes = reader->fileSize();
  // The writer never opens an existing file, least of all the input mapped here.
  auto writer = McapWriter::create(out, options, error);
  if (!writer) return false;
  // Ids in the new file are the writer's own; schemas and channels are added on first use.
  std::map<std::uint16_t, std::uint16_t> schema_ids, channel_ids;
  std::string read_error;
  McapDamage damage;
  bool write_failed = false;
  // Metadata and attachments (which robot, the calibration in use) are kept too, in their place.
  McapReader::Extras extras;
  extras.on_attachment = [&](const McapAttachmentView& a) {
    write_failed = write_failed || !writer->writeAttachment(a.log_time_ns, a.create_time_ns, a.name, a.media_type, a.data, a.size);
    return !write_failed;
  };
  extras.on_metadata = [&](const McapMetadata& m) {
    write_failed = write_failed || !writer->writeMetadata(m.name, m.metadata);
    return !write_failed;
  };
  const bool read = reader->forEachRecord(
      [&](const McapMessageView& m) {
        auto channel = channel_ids.find(m.channel->id);
        if (channel == channel_ids.end()) {
          std::uint16_t schema_id = 0;
          if (m.channel->schema_id != 0) {
            auto schema = schema_ids.find(m.channel->schema_id);
            if (schema == schema_ids.end()) {
              const McapSchema& s = reader->schemasSeen().at(m.channel->schema_id);
              schema = schema_ids.emplace(s.id, writer->addSchema(s.name, s.encoding, s.data)).first;
            }
            schema_id = schema->second;
          }
          channel = channel_ids
                        .emplace(m.channel->id, writer->addChannel(m.channel->topic, schema_id,
                                                                    m.channel->message_encoding, m.channel->metadata))
                        .first;
        }
        if (!writer->write(channel->second, m.sequence, m.log_time_ns, m.publish_time_ns, m.data, m.size)) {
          write_failed = true;
          return false;
        }
        ++report->messages;
        return true;
      },
      extras, &read_error, true, &damage);
  if (write_failed || !writer->close()) {
    *error = out + ": " + writer->error();
    return false;
  }
  if (!read) {  // cannot happen with stop_at_damage; kept for a reader that changes
    *error = read_error;
    return false;
  }
  report->damage = damage.reason;
  report->intact_bytes = damage.reason.empty() ? report->file_bytes : damage.offset;
  return true;
}

}  // namespace telesphere::record
