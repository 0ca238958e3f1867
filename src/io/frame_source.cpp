#include "iilfm/io/frame_source.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>

#include "iilfm/error.hpp"
#include "iilfm/io/bag.hpp"
#include "ros_bags.hpp"

namespace iilfm::io {
namespace {

namespace fs = std::filesystem;

// A file name that is a time: "1629371234.5.pcd" (seconds) or "1629371234500000000.pcd" (ns).
bool stamp_from_name(const std::string& path, double& stamp_s) {
  const std::string stem = fs::path(path).stem().string();
  if (stem.empty()) return false;
  const bool integer = std::all_of(stem.begin(), stem.end(), ::isdigit);
  if (integer && stem.size() >= 16) {
    std::uint64_t ns = 0;
    const auto [end, ec] = std::from_chars(stem.data(), stem.data() + stem.size(), ns);
    if (ec != std::errc() || end != stem.data() + stem.size()) return false;
    stamp_s =
        static_cast<double>(ns / 1'000'000'000) + static_cast<double>(ns % 1'000'000'000) * 1e-9;
    return true;
  }
  const auto [end, ec] = std::from_chars(stem.data(), stem.data() + stem.size(), stamp_s);
  return ec == std::errc() && end == stem.data() + stem.size();
}

class FolderFrames final : public FrameSource {
 public:
  explicit FolderFrames(const std::string& folder) : name_(folder), files_(cloud_files_in(folder)) {
    if (files_.empty())
      throw file_error(folder, "folder holds no cloud files (.pcd, .bin, .ply, .txt, .xyz, .xyzi)");
  }
  bool next(Frame& frame) override {
    if (next_ >= files_.size()) return false;
    const std::string& file = files_[next_];
    frame.loaded = read_cloud(file);
    frame.index = next_;
    frame.source = file;
    if (!stamp_from_name(file, frame.stamp_s)) frame.stamp_s = static_cast<double>(next_);
    ++next_;
    return true;
  }
  std::size_t total() const override { return files_.size(); }
  const std::string& name() const override { return name_; }

 private:
  std::string name_;
  std::vector<std::string> files_;
  std::size_t next_ = 0;
};

// One cloud file as a recording of one frame, so that --jsonl and --tum take a single scan too.
class FileFrames final : public FrameSource {
 public:
  explicit FileFrames(const std::string& file) : name_(file) {}
  bool next(Frame& frame) override {
    if (done_) return false;
    frame.loaded = read_cloud(name_);
    frame.index = 0;
    frame.source = name_;
    if (!stamp_from_name(name_, frame.stamp_s)) frame.stamp_s = 0;
    done_ = true;
    return true;
  }
  std::size_t total() const override { return 1; }
  const std::string& name() const override { return name_; }

 private:
  std::string name_;
  bool done_ = false;
};

class BagFrames final : public FrameSource {
 public:
  BagFrames(std::unique_ptr<BagReader> bag, const std::string& path, const std::string& topic)
      : bag_(std::move(bag)), topic_(topic), name_(path + ":" + topic) {
    bag_->select(topic);
    for (const BagTopic& t : bag_->topics()) {
      if (t.name != topic) continue;
      if (!is_cloud_message_type(t.type))
        throw file_error(path, "topic " + topic + " has type " + t.type +
                                   ", not a point cloud (supported: " + cloud_message_types() +
                                   ")");
      total_ = t.messages;
    }
  }
  bool next(Frame& frame) override {
    BagMessage message;
    if (!bag_->next(message)) return false;
    frame.index = index_;
    frame.source = name_ + "#" + std::to_string(index_);
    CloudMessage decoded = decode_cloud_message(message, bag_->path() + ": " + frame.source);
    const std::int64_t stamp_ns =
        decoded.header_stamp_ns != 0 ? decoded.header_stamp_ns : message.stamp_ns;
    frame.stamp_s = static_cast<double>(stamp_ns / 1'000'000'000) +
                    static_cast<double>(stamp_ns % 1'000'000'000) * 1e-9;
    frame.loaded = std::move(decoded.loaded);
    ++index_;
    return true;
  }
  std::size_t total() const override { return total_; }
  const std::string& name() const override { return name_; }

 private:
  std::unique_ptr<BagReader> bag_;
  std::string topic_, name_;
  std::size_t total_ = 0, index_ = 0;
};

}  // namespace

std::vector<std::string> cloud_files_in(const std::string& folder) {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.is_regular_file() && is_cloud_file(entry.path().string()))
      files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::unique_ptr<FrameSource> open_frame_source(const std::string& input, const std::string& topic) {
  if (!fs::exists(input)) throw file_error(input, "no such file or folder");
  if (!topic.empty()) return std::make_unique<BagFrames>(open_bag(input), input, topic);
  if (is_bag_path(input)) {
    // A recording of one LiDAR has one point cloud topic: naming it would only be typing.
    std::unique_ptr<BagReader> bag = open_bag(input);
    std::vector<std::string> clouds;
    for (const BagTopic& t : bag->topics())
      if (is_cloud_message_type(t.type)) clouds.push_back(t.name);
    if (clouds.size() == 1) return std::make_unique<BagFrames>(std::move(bag), input, clouds[0]);
    if (clouds.empty())
      throw file_error(input, "the bag has no point cloud topic (topics: " +
                                  topics_with_types(bag->topics()) + ")");
    std::string names;
    for (const std::string& name : clouds) names += (names.empty() ? "" : ", ") + name;
    throw file_error(
        input, "the bag has several point cloud topics: choose one with --topic (" + names + ")");
  }
  if (fs::is_directory(input)) return std::make_unique<FolderFrames>(input);
  if (is_cloud_file(input)) return std::make_unique<FileFrames>(input);
  throw file_error(input, "not a recording: give a bag, a folder of cloud files or a cloud file");
}

}  // namespace iilfm::io
