// ROS 2 bags in the sqlite3 storage (rosbag2_storage_default_plugins): a folder with metadata.yaml
// naming one or more .db3 files, each with the tables
//   topics(id, name, type, serialization_format, offered_qos_profiles)
//   messages(id, topic_id, timestamp, data)   -- timestamp in ns, data CDR-serialized
// A .db3 file alone is read the same way.
#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "iilfm/error.hpp"
#include "ros_bags.hpp"

namespace iilfm::io {
namespace {

namespace fs = std::filesystem;

struct DbDeleter {
  void operator()(sqlite3* db) const { sqlite3_close(db); }
};
struct StatementDeleter {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Db = std::unique_ptr<sqlite3, DbDeleter>;
using Statement = std::unique_ptr<sqlite3_stmt, StatementDeleter>;

std::string text_column(sqlite3_stmt* s, int column) {
  const unsigned char* text = sqlite3_column_text(s, column);
  return text ? printable(reinterpret_cast<const char*>(text)) : "";
}

struct TopicRow {
  std::int64_t id;
  std::string serialization;
};

class Ros2Bag final : public BagReader {
 public:
  Ros2Bag(std::string path, const std::vector<std::string>& files) : path_(std::move(path)) {
    if (files.empty()) throw file_error(path_, "no .db3 files in this ROS 2 bag");
    for (const std::string& file : files) open_file(file);
    std::sort(topics_.begin(), topics_.end(),
              [](const BagTopic& a, const BagTopic& b) { return a.name < b.name; });
  }

  const std::string& path() const override { return path_; }
  std::string format() const override {
    return "ROS 2 bag, sqlite3 storage, " + std::to_string(files_.size()) + " file(s)";
  }
  const std::vector<BagTopic>& topics() const override { return topics_; }
  const std::string& damage() const override { return damage_; }

  void select(const std::string& topic) override {
    const auto found = std::find_if(topics_.begin(), topics_.end(),
                                    [&](const BagTopic& t) { return t.name == topic; });
    if (found == topics_.end()) throw file_error(path_, missing_topic_problem(topic, topics_));
    topic_ = topic;
    type_ = found->type;
    file_index_ = 0;
    statement_.reset();
  }

  bool next(BagMessage& message) override {
    while (file_index_ < files_.size()) {
      File& file = files_[file_index_];
      if (!statement_) {
        const auto row = file.topic_rows.find(topic_);
        if (row == file.topic_rows.end()) {
          ++file_index_;
          continue;
        }
        if (row->second.serialization != "cdr")
          throw file_error(file.path, "topic " + topic_ + " uses serialization '" +
                                          row->second.serialization + "', not cdr");
        statement_ = prepare(file,
                             "SELECT timestamp, data FROM messages WHERE topic_id = ? "
                             "ORDER BY timestamp, id");
        sqlite3_bind_int64(statement_.get(), 1, row->second.id);
      }
      const int status = sqlite3_step(statement_.get());
      if (status == SQLITE_ROW) {
        message.stamp_ns = sqlite3_column_int64(statement_.get(), 0);
        message.data = static_cast<const std::uint8_t*>(sqlite3_column_blob(statement_.get(), 1));
        message.size = static_cast<std::size_t>(sqlite3_column_bytes(statement_.get(), 1));
        message.type = type_;
        message.encoding = MessageEncoding::kCdr;
        return true;
      }
      if (status != SQLITE_DONE)
        throw file_error(file.path, std::string("sqlite: ") + sqlite3_errmsg(file.db.get()));
      statement_.reset();
      ++file_index_;
    }
    return false;
  }

 private:
  struct File {
    std::string path;
    Db db;
    std::map<std::string, TopicRow> topic_rows;
  };

  Statement prepare(const File& file, const char* sql) const {
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(file.db.get(), sql, -1, &raw, nullptr) != SQLITE_OK) {
      const std::string problem = sqlite3_errmsg(file.db.get());
      sqlite3_finalize(raw);
      throw file_error(file.path, "not a ROS 2 sqlite3 bag (" + problem + ")");
    }
    return Statement(raw);
  }

  void open_file(const std::string& path) {
    if (!fs::is_regular_file(path)) throw file_error(path, "file not found");
    sqlite3* raw = nullptr;
    const int status = sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
    File file{path, Db(raw), {}};
    if (status != SQLITE_OK)
      throw file_error(path, std::string("cannot open sqlite3 file: ") + sqlite3_errmsg(raw));
    const Statement rows = prepare(
        file,
        "SELECT t.id, t.name, t.type, t.serialization_format, COUNT(m.id), MIN(m.timestamp), "
        "MAX(m.timestamp) FROM topics t LEFT JOIN messages m ON m.topic_id = t.id GROUP BY t.id");
    int step;
    while ((step = sqlite3_step(rows.get())) == SQLITE_ROW) {
      const std::string name = text_column(rows.get(), 1);
      file.topic_rows[name] = {sqlite3_column_int64(rows.get(), 0), text_column(rows.get(), 3)};
      auto topic = std::find_if(topics_.begin(), topics_.end(),
                                [&](const BagTopic& t) { return t.name == name; });
      if (topic == topics_.end()) {
        topics_.push_back({name, text_column(rows.get(), 2), 0, 0, 0, ""});
        topic = topics_.end() - 1;
      }
      const auto count = static_cast<std::size_t>(sqlite3_column_int64(rows.get(), 4));
      if (count == 0) continue;
      const std::int64_t first = sqlite3_column_int64(rows.get(), 5);
      const std::int64_t last = sqlite3_column_int64(rows.get(), 6);
      topic->first_ns = topic->messages == 0 ? first : std::min(topic->first_ns, first);
      topic->last_ns = topic->messages == 0 ? last : std::max(topic->last_ns, last);
      topic->messages += count;
    }
    if (step != SQLITE_DONE)
      throw file_error(path, std::string("sqlite: ") + sqlite3_errmsg(file.db.get()));
    files_.push_back(std::move(file));
  }

  std::string path_;
  std::vector<File> files_;
  std::vector<BagTopic> topics_;
  std::string damage_;
  std::string topic_, type_;
  std::size_t file_index_ = 0;
  Statement statement_;
};

}  // namespace

std::unique_ptr<BagReader> open_ros2_bag(const std::string& path,
                                         const std::vector<std::string>& files) {
  return std::make_unique<Ros2Bag>(path, files);
}

}  // namespace iilfm::io
