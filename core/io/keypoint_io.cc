#include "core/io/keypoint_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>
#include <utility>

#include "core/model/enum_names.h"
#include "core/model/option_checker.h"

namespace nrsfm {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr EnumName<KeypointPart> kKeypointPartNames[] = {
    {KeypointPart::kPose, "pose"},
    {KeypointPart::kFace, "face"},
    {KeypointPart::kHandLeft, "hand_left"},
    {KeypointPart::kHandRight, "hand_right"},
};

// The most frames a keypoint input may have (10^6 frames of 25 keypoints
// are a W of 400 MB).
constexpr long long kMaxFrames = 1000000;
// The largest W (entries) a keypoint input may imply: 2^28 doubles = 2 GiB,
// as for observation lists (core/io/text_io.h).
constexpr double kMaxEntries = 268435456.0;
// Frames named in a warning; the rest are counted.
constexpr int kMaxListed = 10;

// OpenPose's field of a part.
std::string PartField(KeypointPart part) {
  return std::string(KeypointPartName(part)) + "_keypoints_2d";
}

std::string TypeName(const Json& value) { return value.type_name(); }

Status ReadJsonFile(const std::string& path, Json* json) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) return Status::Error(path + ": no such file");
  if (fs::is_directory(status)) {
    return Status::Error(path + ": is a directory, not a JSON file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path + ": cannot open the file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  try {
    *json = Json::parse(text.str());
  } catch (const Json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 1, column 5: …"
    std::string what = e.what();
    const std::size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    return Status::Error(path + ": not valid JSON (" + what + ")");
  }
  return Status::OK();
}

// The [x, y, score, …] array `values` (named `where` in errors) as numbers;
// empty when the array is.
Status ReadTriples(const Json& values, const std::string& where,
                   std::vector<double>* out) {
  out->clear();
  if (!values.is_array()) {
    return Status::Error(where + " is a " + TypeName(values) +
                         ", not a list [x1, y1, score1, x2, …]");
  }
  if (values.size() % 3 != 0) {
    return Status::Error(
        where + " has " + std::to_string(values.size()) +
        " values, not a multiple of 3 (x, y and score of each keypoint)");
  }
  out->reserve(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!values[i].is_number()) {
      return Status::Error(where + "[" + std::to_string(i) + "] is a " +
                           TypeName(values[i]) + ", not a number");
    }
    const double value = values[i].get<double>();
    if (!std::isfinite(value)) {
      return Status::Error(where + "[" + std::to_string(i) + "] = " +
                           values[i].dump() + " is not a finite number");
    }
    out->push_back(value);
  }
  return Status::OK();
}

// "7, 8, 9 and 4 more" of the frames `names[i]` for i in `frames`.
std::string ListFrames(const std::vector<int>& frames,
                       const std::vector<std::string>& names) {
  std::string text;
  const int count = static_cast<int>(frames.size());
  for (int i = 0; i < count && i < kMaxListed; ++i) {
    text += (i == 0 ? "" : ", ") + names[frames[i]];
  }
  if (count > kMaxListed)
    text += " and " + std::to_string(count - kMaxListed) + " more";
  return text;
}

// The frames' keypoints (3P values each; empty = no person) as measurements
// and confidences; `names` (one per frame) and `what` (how a frame is
// named, e.g. "image_id") for the warning about frames with no person.
// Errors, naming `path`, when no keypoint is visible.
Status BuildKeypoints(const std::string& path,
                      const std::vector<std::vector<double>>& frames,
                      int num_points, const KeypointOptions& options,
                      const std::vector<std::string>& names,
                      const std::string& what, Keypoints* keypoints) {
  const int num_frames = static_cast<int>(frames.size());
  if (2.0 * num_frames * num_points > kMaxEntries) {
    return Status::Error(path + ": F = " + std::to_string(num_frames) +
                         " frames of P = " + std::to_string(num_points) +
                         " keypoints imply a W larger than 2^28 entries");
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Measurements& m = keypoints->measurements;
  m = Measurements();
  m.num_frames = num_frames;
  m.num_cameras = 1;
  m.num_points = num_points;
  m.W = Eigen::MatrixXd::Constant(2 * num_frames, num_points, nan);
  m.visible = VisibilityMask::Constant(num_frames, num_points, false);
  keypoints->confidence =
      Eigen::ArrayXXd::Constant(num_frames, num_points, nan);
  std::vector<int> empty;
  for (int t = 0; t < num_frames; ++t) {
    const std::vector<double>& values = frames[t];
    if (values.empty()) {
      empty.push_back(t);
      continue;
    }
    for (int p = 0; p < num_points; ++p) {
      const double score = values[3 * p + 2];
      keypoints->confidence(t, p) = score;
      if (!(score > 0.0 && score >= options.min_confidence)) continue;
      m.W(2 * t, p) = values[3 * p];
      m.W(2 * t + 1, p) = values[3 * p + 1];
      m.visible(t, p) = true;
    }
  }
  if (!m.visible.any()) {
    std::ostringstream msg;
    msg << path << ": no keypoint has a score of at least min_confidence = "
        << options.min_confidence << " (the highest is "
        << keypoints->confidence.isNaN()
               .select(-1.0, keypoints->confidence)
               .maxCoeff()
        << ")";
    return Status::Error(msg.str());
  }
  if (!empty.empty()) {
    keypoints->warnings.push_back(
        std::to_string(empty.size()) + " of " + std::to_string(num_frames) +
        " frames have no person, their points are missing (" + what + " " +
        ListFrames(empty, names) + ")");
  }
  return Status::OK();
}

// The warning about frames with several people or entries, or "".
// "3 of 120 frames have <what> (<label> 4, 9, 17): <used> is used".
std::string SeveralWarning(const std::vector<int>& frames, int num_frames,
                           const std::vector<std::string>& names,
                           const std::string& what, const std::string& label,
                           const std::string& used) {
  if (frames.empty()) return "";
  return std::to_string(frames.size()) + " of " + std::to_string(num_frames) +
         " frames have " + what + " (" + label + " " +
         ListFrames(frames, names) + "): " + used + " is used";
}

// The frame key of a COCO entry: an integer, another number or a string.
enum class KeyKind { kInteger, kNumber, kString };

KeyKind KindOf(const Json& key) {
  if (key.is_string()) return KeyKind::kString;
  const double value = key.get<double>();
  return (std::floor(value) == value && std::abs(value) <= 9.0e15)
             ? KeyKind::kInteger
             : KeyKind::kNumber;
}

std::string KeyText(const Json& key) { return key.dump(); }

struct CocoEntry {
  Json key;
  double score = 0.0;
  std::vector<double> values;
};

// The entries of a COCO results file, checked (header).
Status ReadCocoEntries(const std::string& path, const Json& root,
                       const std::string& frame_key,
                       std::vector<CocoEntry>* entries, int* num_points) {
  if (!root.is_array()) {
    std::string hint;
    if (root.is_object() && root.contains("annotations")) {
      hint =
          "; this looks like a COCO annotation file (it has 'annotations'): "
          "nrsfm reads "
          "keypoint results, the list a detector writes";
    } else if (root.is_object() && root.contains("people")) {
      hint =
          "; this looks like one OpenPose frame: give the folder of its "
          "per-frame files";
    }
    return Status::Error(
        path +
        ": expected a list of COCO keypoint results [{\"image_id\", "
        "\"keypoints\": [x, y, score, ...], \"score\"}, ...], got a " +
        TypeName(root) + hint);
  }
  if (root.empty())
    return Status::Error(path + ": the list of keypoint results is empty");
  if (static_cast<long long>(root.size()) > kMaxFrames * 10) {
    return Status::Error(path + ": " + std::to_string(root.size()) +
                         " entries, more than nrsfm reads (10^7)");
  }
  entries->clear();
  entries->reserve(root.size());
  *num_points = 0;
  for (std::size_t i = 0; i < root.size(); ++i) {
    const Json& e = root[i];
    std::string where = path + ": entry " + std::to_string(i);
    if (!e.is_object()) {
      return Status::Error(
          where + " is a " + TypeName(e) +
          ", not an object {\"image_id\", \"keypoints\", ...}");
    }
    if (!e.contains(frame_key)) {
      return Status::Error(
          where + " has no '" + frame_key + "' (the frame key" +
          (frame_key == "image_id" ? "; --frame_key names another field" : "") +
          ")");
    }
    CocoEntry entry;
    entry.key = e[frame_key];
    if (!entry.key.is_number() && !entry.key.is_string()) {
      return Status::Error(where + ": '" + frame_key + "' is a " +
                           TypeName(entry.key) + ", not a number or a string");
    }
    where += " (" + frame_key + " " + KeyText(entry.key) + ")";
    if (!e.contains("keypoints"))
      return Status::Error(where + " has no 'keypoints'");
    NRSFM_RETURN_IF_ERROR(
        ReadTriples(e["keypoints"], where + ": 'keypoints'", &entry.values));
    if (entry.values.empty())
      return Status::Error(where + ": 'keypoints' is empty");
    const int points = static_cast<int>(entry.values.size() / 3);
    if (i == 0) {
      *num_points = points;
    } else if (points != *num_points) {
      return Status::Error(where + " has " + std::to_string(points) +
                           " keypoints but entry 0 has " +
                           std::to_string(*num_points));
    }
    if (e.contains("score")) {
      if (!e["score"].is_number()) {
        return Status::Error(where + ": 'score' is a " + TypeName(e["score"]) +
                             ", not a number");
      }
      entry.score = e["score"].get<double>();
    }
    if (i > 0 && entry.key.is_string() != (*entries)[0].key.is_string()) {
      return Status::Error(where + ": '" + frame_key + "' is a " +
                           TypeName(entry.key) + " but entry 0's is a " +
                           TypeName((*entries)[0].key));
    }
    entries->push_back(std::move(entry));
  }
  return Status::OK();
}

}  // namespace

const char* KeypointPartName(KeypointPart part) {
  return NameOf(kKeypointPartNames, part);
}

Status ParseKeypointPart(const std::string& name, KeypointPart* part) {
  return ParseName(kKeypointPartNames, name, "keypoint part", part);
}

Status KeypointOptions::Check() const {
  OptionChecker check("keypoint options");
  check.Require(!frame_key.empty(),
                "frame_key must name a field of the entries, got ''");
  check.Require(NameOf(kKeypointPartNames, part) != std::string("unknown"),
                "invalid part " + std::to_string(static_cast<int>(part)));
  check.Require(std::isfinite(min_confidence) && min_confidence >= 0.0,
                "min_confidence must be finite and >= 0");
  return check.status();
}

bool NaturalLess(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const bool digit_a = std::isdigit(static_cast<unsigned char>(a[i])) != 0;
    const bool digit_b = std::isdigit(static_cast<unsigned char>(b[j])) != 0;
    if (!digit_a || !digit_b) {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
      continue;
    }
    // Two runs of digits: compare without their leading zeros, by length
    // and then digit by digit.
    std::size_t end_a = i, end_b = j;
    while (end_a < a.size() &&
           std::isdigit(static_cast<unsigned char>(a[end_a])))
      ++end_a;
    while (end_b < b.size() &&
           std::isdigit(static_cast<unsigned char>(b[end_b])))
      ++end_b;
    std::size_t start_a = i, start_b = j;
    while (start_a + 1 < end_a && a[start_a] == '0') ++start_a;
    while (start_b + 1 < end_b && b[start_b] == '0') ++start_b;
    const std::string_view run_a(a.data() + start_a, end_a - start_a);
    const std::string_view run_b(b.data() + start_b, end_b - start_b);
    if (run_a.size() != run_b.size()) return run_a.size() < run_b.size();
    if (run_a != run_b) return run_a < run_b;
    // The same number: more leading zeros first.
    if (end_a - i != end_b - j) return end_a - i > end_b - j;
    i = end_a, j = end_b;
  }
  return a.size() - i < b.size() - j;
}

Status ReadCocoKeypoints(const std::string& path,
                         const KeypointOptions& options, Keypoints* keypoints) {
  NRSFM_RETURN_IF_ERROR(options.Check());
  Json root;
  NRSFM_RETURN_IF_ERROR(ReadJsonFile(path, &root));
  std::vector<CocoEntry> entries;
  int num_points = 0;
  NRSFM_RETURN_IF_ERROR(
      ReadCocoEntries(path, root, options.frame_key, &entries, &num_points));
  root = Json();

  // The frame of every entry (header): integers span their range; other
  // numbers and strings are their distinct values in order.
  KeyKind kind = KindOf(entries[0].key);
  for (const CocoEntry& entry : entries) {
    if (kind == KeyKind::kInteger && KindOf(entry.key) == KeyKind::kNumber)
      kind = KeyKind::kNumber;
  }
  std::vector<int> frame_of(entries.size());
  std::vector<std::string> names;
  if (kind == KeyKind::kInteger) {
    long long lowest = std::numeric_limits<long long>::max();
    long long highest = std::numeric_limits<long long>::min();
    for (const CocoEntry& entry : entries) {
      const long long value = static_cast<long long>(entry.key.get<double>());
      lowest = std::min(lowest, value);
      highest = std::max(highest, value);
    }
    if (highest - lowest + 1 > kMaxFrames) {
      return Status::Error(
          path + ": '" + options.frame_key + "' runs from " +
          std::to_string(lowest) + " to " + std::to_string(highest) +
          ", more than 10^6 frames (every integer between them is a frame); "
          "number the frames of the video or name another --frame_key");
    }
    for (std::size_t i = 0; i < entries.size(); ++i) {
      frame_of[i] = static_cast<int>(
          static_cast<long long>(entries[i].key.get<double>()) - lowest);
    }
    for (long long value = lowest; value <= highest; ++value) {
      names.push_back(std::to_string(value));
    }
  } else {
    const auto less = [kind](const Json& a, const Json& b) {
      return kind == KeyKind::kString
                 ? NaturalLess(a.get<std::string>(), b.get<std::string>())
                 : a.get<double>() < b.get<double>();
    };
    std::map<Json, int, decltype(less)> index(less);
    for (const CocoEntry& entry : entries) index.emplace(entry.key, 0);
    for (auto& [key, frame] : index) {
      frame = static_cast<int>(names.size());
      names.push_back(KeyText(key));
    }
    for (std::size_t i = 0; i < entries.size(); ++i)
      frame_of[i] = index.at(entries[i].key);
  }

  // The entry used in each frame: the highest score, the first of equal ones.
  const int num_frames = static_cast<int>(names.size());
  std::vector<int> chosen(num_frames, -1), count(num_frames, 0);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const int t = frame_of[i];
    ++count[t];
    if (chosen[t] < 0 || entries[i].score > entries[chosen[t]].score) {
      chosen[t] = static_cast<int>(i);
    }
  }
  std::vector<std::vector<double>> frames(num_frames);
  std::vector<int> several;
  for (int t = 0; t < num_frames; ++t) {
    if (chosen[t] >= 0) frames[t] = std::move(entries[chosen[t]].values);
    if (count[t] > 1) several.push_back(t);
  }
  *keypoints = Keypoints();
  NRSFM_RETURN_IF_ERROR(BuildKeypoints(path, frames, num_points, options, names,
                                       options.frame_key, keypoints));
  const std::string warning =
      SeveralWarning(several, num_frames, names, "several entries",
                     options.frame_key, "the one with the highest 'score'");
  if (!warning.empty()) keypoints->warnings.push_back(warning);
  return Status::OK();
}

Status ReadOpenPoseFolder(const std::string& path,
                          const KeypointOptions& options,
                          Keypoints* keypoints) {
  NRSFM_RETURN_IF_ERROR(options.Check());
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) return Status::Error(path + ": no such folder");
  if (!fs::is_directory(status)) {
    return Status::Error(
        path +
        ": is not a folder (OpenPose input is the folder of its "
        "per-frame .json files)");
  }
  std::vector<std::string> files;
  for (fs::directory_iterator it(path, ec), end; !ec && it != end;
       it.increment(ec)) {
    std::string extension = it->path().extension().string();
    std::transform(
        extension.begin(), extension.end(), extension.begin(),
        [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".json" && it->is_regular_file(ec)) {
      files.push_back(it->path().filename().string());
    }
    if (static_cast<long long>(files.size()) > kMaxFrames) {
      return Status::Error(path + ": more than 10^6 .json files");
    }
  }
  if (ec)
    return Status::Error(path + ": cannot list the folder (" + ec.message() +
                         ")");
  if (files.empty()) {
    return Status::Error(path +
                         ": no .json files in the folder (OpenPose writes one "
                         "<name>_keypoints.json per frame with --write_json)");
  }
  std::sort(files.begin(), files.end(), NaturalLess);

  const std::string field = PartField(options.part);
  const int num_frames = static_cast<int>(files.size());
  std::vector<std::vector<double>> frames(num_frames);
  std::vector<int> several;
  int num_points = 0, first = -1;
  for (int t = 0; t < num_frames; ++t) {
    const std::string file = (fs::path(path) / files[t]).string();
    Json frame;
    NRSFM_RETURN_IF_ERROR(ReadJsonFile(file, &frame));
    if (!frame.is_object() || !frame.contains("people") ||
        !frame["people"].is_array()) {
      return Status::Error(
          file + ": no 'people' list (not an OpenPose keypoint file)");
    }
    const Json& people = frame["people"];
    if (people.empty()) continue;
    if (people.size() > 1) several.push_back(t);
    if (!people[0].is_object() || !people[0].contains(field)) {
      return Status::Error(file + ": people[0] has no '" + field + "'");
    }
    NRSFM_RETURN_IF_ERROR(ReadTriples(
        people[0][field], file + ": people[0]." + field, &frames[t]));
    if (frames[t].empty()) continue;
    const int points = static_cast<int>(frames[t].size() / 3);
    if (first < 0) {
      first = t;
      num_points = points;
    } else if (points != num_points) {
      return Status::Error(file + ": people[0]." + field + " has " +
                           std::to_string(points) + " keypoints but " +
                           files[first] + " has " + std::to_string(num_points));
    }
  }
  if (first < 0) {
    return Status::Error(
        path + ": none of the " + std::to_string(num_frames) +
        " frames has a person with " + field +
        (options.part == KeypointPart::kPose
             ? ""
             : " (OpenPose computes faces and hands with --face, --hand)"));
  }
  *keypoints = Keypoints();
  NRSFM_RETURN_IF_ERROR(BuildKeypoints(path, frames, num_points, options, files,
                                       "files", keypoints));
  const std::string warning = SeveralWarning(
      several, num_frames, files, "more than one person", "files", "people[0]");
  if (!warning.empty()) keypoints->warnings.push_back(warning);
  return Status::OK();
}

}  // namespace nrsfm
