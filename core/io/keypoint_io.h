// Detector keypoints as measurements (docs/guide.md, "Input formats",
// docs/inputs.md): the 2D keypoints of one tracked person (or animal, face,
// hand) over the frames of a video, with the detector's score of each.
//
//   COCO keypoint results  one JSON file: a list of entries
//                          {"image_id": …, "category_id": …, "keypoints":
//                          [x1, y1, s1, x2, y2, s2, …], "score": …}, one
//                          tracked instance per image (as MMPose, Detectron2
//                          and the COCO evaluation write them).
//   OpenPose               a folder of per-frame JSON files (OpenPose's
//                          --write_json: one <name>_keypoints.json per frame),
//                          {"people": [{"pose_keypoints_2d": [x1, y1, c1, …],
//                          "face_keypoints_2d": …, "hand_left_keypoints_2d":
//                          …, "hand_right_keypoints_2d": …}, …]}.
//
// Frames: COCO's KeypointOptions::frame_key orders the entries (integer
// values are frame numbers, gaps are frames with no person; others give one
// frame per distinct value in natural order), the highest "score" wins
// within a frame; OpenPose: one frame per file in natural order, people[0].
// A frame with no person has all its points missing; warnings count the
// frames with several people and with none (docs/inputs.md has the rules).
// Points: P = (values per entry) / 3, the same in every frame; a keypoint is
// visible when its score is > 0 and ≥ KeypointOptions::min_confidence.
//
// Coordinates: W holds the files' pixel coordinates as they are, u = x to
// the right and v = y down (the image convention), M = 1. The reconstruction
// of such W is in pixels, in the camera frame x right, y down, z = x × y
// pointing away from the camera into the scene (right-handed, as OpenCV's
// camera frame; the sign of depth is the orthographic camera's usual
// ambiguity), and `nrsfm view` draws it with v down, so upright.
//
// Errors name the file, the entry or file of the folder, the field and the
// value: a file that is not valid JSON, another schema (a COCO annotation
// file, one OpenPose frame given instead of its folder, an entry without
// "keypoints" or without the frame key), keypoints that are not numbers or
// not in triples, another number of keypoints than the first entry's, no
// entry at all, or no frame with a person.
#ifndef NRSFM_CORE_IO_KEYPOINT_IO_H_
#define NRSFM_CORE_IO_KEYPOINT_IO_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/status.h"

namespace nrsfm {

// The keypoints of an OpenPose person that are the points.
enum class KeypointPart {
  kPose,       // pose_keypoints_2d (BODY_25: 25 points, COCO model: 18)
  kFace,       // face_keypoints_2d (70)
  kHandLeft,   // hand_left_keypoints_2d (21)
  kHandRight,  // hand_right_keypoints_2d (21)
};
// "pose", "face", "hand_left", "hand_right"; the error lists them.
const char* KeypointPartName(KeypointPart part);
Status ParseKeypointPart(const std::string& name, KeypointPart* part);

struct KeypointOptions {
  // COCO results: the field of each entry whose value orders the frames (a
  // number or a string; see the header for integers with gaps).
  std::string frame_key = "image_id";
  // OpenPose: which keypoints of the person are the points.
  KeypointPart part = KeypointPart::kPose;
  // A keypoint whose score is below this is missing (score units, usually
  // 0 … 1); 0.05 is OpenPose's own render threshold. A score of 0 or less is
  // always missing.
  double min_confidence = 0.05;

  // Errors on an empty frame_key, a part not in the enum, and a
  // min_confidence that is negative or not finite.
  Status Check() const;
};

// What a keypoint input holds.
struct Keypoints {
  Measurements measurements;  // F frames, M = 1, P keypoints; pixels (above)
  // F × P: the detector's score of every keypoint, also of those below
  // min_confidence; NaN in a frame with no person.
  Eigen::ArrayXXd confidence;
  // For the user, one line each: frames with no person, frames with more
  // than one. Empty when there is nothing to say.
  std::vector<std::string> warnings;
};

// A COCO keypoint results file (header).
Status ReadCocoKeypoints(const std::string& path,
                         const KeypointOptions& options, Keypoints* keypoints);

// A folder of OpenPose per-frame JSON files (header).
Status ReadOpenPoseFolder(const std::string& path,
                          const KeypointOptions& options, Keypoints* keypoints);

// a < b in natural order: runs of digits compare as numbers ("f2" < "f10"),
// the rest character by character; equal numbers with more leading zeros
// come first, so the order is total.
bool NaturalLess(const std::string& a, const std::string& b);

}  // namespace nrsfm

#endif  // NRSFM_CORE_IO_KEYPOINT_IO_H_
