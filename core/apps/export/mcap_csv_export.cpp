#include "export/mcap_csv_export.hpp"

#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "ros/cdr_columns.hpp"
#include "csv/csv_rows.hpp"
#include "files/log_file.hpp"
#include "mcap/mcap_reader.hpp"

namespace tern::core {

namespace {

/// The columns of a tern_msgs schema: one "<type> <name>" line per column, packed in order.
std::vector<reflect::Column> schema_columns(const McapSchema& s, const fs::path& file) {
  std::vector<reflect::Column> cols;
  std::istringstream lines(s.data);
  std::string line;
  std::size_t offset = 0;
  while (std::getline(lines, line)) {
    std::istringstream words(line.substr(0, line.find('#')));
    std::string type, name;
    if (!(words >> type >> name)) continue;  // blank or comment
    const auto kind = scalar_of_ros2msg(type);
    if (!kind)
      throw McapError(fmt::format("{}: schema {}: field '{}' has type '{}', not a tern log column", file.string(), s.name, name, type));
    cols.push_back({name, "", *kind, offset});
    offset += reflect::scalar_size(*kind);
  }
  if (cols.size() == 1 && cols[0].name == "structure_needs_at_least_one_member") cols.clear();
  return cols;
}

struct Table {
  std::string topic;
  std::vector<reflect::Column> columns;
  std::size_t msg_size = 0;
  std::unique_ptr<LogFile> file;
  std::string pending;  // records: int64 t, then msg_size bytes
  std::uint64_t rows = 0;
};

class Exporter {
 public:
  Exporter(const fs::path& file, const fs::path& out_dir, const std::set<std::string>& only)
      : reader_(file), out_dir_(out_dir), only_(only) {}
  CsvExportReport run();

 private:
  void add_channel(const McapChannel& c);
  void add_message(const McapMessage& m);
  void write(Table& t);

  McapReader reader_;
  fs::path out_dir_;
  std::set<std::string> only_;  // empty: every topic
  LogHealth health_;
  std::map<std::uint16_t, McapSchema> schemas_;
  std::map<std::uint16_t, Table> tables_;
  std::unique_ptr<char[]> text_;
  std::size_t capacity_ = 0;
  CsvExportReport report_;
};

void Exporter::add_channel(const McapChannel& c) {
  // a topic's copy in its ROS type (ros_channels.hpp): its table is the topic's own; the 3-D scene (scene_channels.hpp)
  if (c.metadata.count("tern.topic") || c.metadata.count("tern.scene")) return;
  const auto header = c.metadata.find("tern.csv_header");
  const auto schema = schemas_.find(c.schema);
  if (header == c.metadata.end() || schema == schemas_.end() || c.message_encoding != "cdr") {
    report_.skipped.push_back(c.topic);
    return;
  }
  Table t;
  t.topic = c.topic.substr(c.topic.rfind('/') + 1);
  if (!only_.empty() && !only_.count(t.topic)) return;
  t.columns = schema_columns(schema->second, reader_.path());
  for (const auto& col : t.columns) t.msg_size = col.offset + reflect::scalar_size(col.kind);
  const fs::path csv = out_dir_ / (t.topic + ".csv");
  if (fs::exists(csv))
    throw McapError(fmt::format("{}: exists; nothing was overwritten (export into another directory: --out)", csv.string()));
  t.file = std::make_unique<LogFile>(csv, health_);
  t.file->append(header->second + "\n");
  if (health_.failed()) throw McapError(health_.error());
  tables_[c.id] = std::move(t);
}

void Exporter::add_message(const McapMessage& m) {
  const auto it = tables_.find(m.channel);
  if (it == tables_.end()) return;
  Table& t = it->second;
  const std::size_t n = t.pending.size();
  t.pending.resize(n + sizeof(Nanos) + t.msg_size);
  const auto when = static_cast<Nanos>(m.log_time);
  std::memcpy(t.pending.data() + n, &when, sizeof when);
  if (!decode_cdr(t.columns, m.data, t.pending.data() + n + sizeof when))
    throw McapError(
        fmt::format("{}: /{} message {}: not {} bytes of little-endian CDR", reader_.path().string(), t.topic, m.sequence, t.msg_size));
  ++t.rows;
  if (t.pending.size() >= 256 * 1024) write(t);
}

void Exporter::write(Table& t) {
  const std::size_t n = format_csv_rows(t.columns, t.msg_size, t.pending, text_, capacity_);
  t.file->append(std::string_view(text_.get(), n));
  t.pending.clear();
  if (health_.failed()) throw McapError(health_.error());
}

CsvExportReport Exporter::run() {
  std::error_code ec;
  fs::create_directories(out_dir_, ec);
  if (ec) throw McapError(fmt::format("{}: cannot create: {}", out_dir_.string(), ec.message()));
  McapRecord r;
  std::string buffer;
  while (reader_.next(r)) {
    if (r.op == mcap::Op::schema) {
      McapSchema s = reader_.schema(r);
      schemas_[s.id] = std::move(s);
    } else if (r.op == mcap::Op::channel) {
      add_channel(reader_.channel(r));
    } else if (r.op == mcap::Op::message) {
      add_message(reader_.message(r.content, r.offset));
    } else if (r.op == mcap::Op::chunk) {
      reader_.chunk_messages(r, buffer, [this](const McapMessage& m) { add_message(m); });
    }
  }
  report_.stopped = reader_.truncated();
  for (auto& [id, t] : tables_) {
    write(t);
    report_.rows[t.topic] = t.rows;
  }
  return report_;
}

}  // namespace

CsvExportReport export_csv(const fs::path& mcap_file, const fs::path& out_dir, const std::set<std::string>& only) {
  return Exporter(mcap_file, out_dir, only).run();
}

}  // namespace tern::core
