#include "tools/synth_steps.h"

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "core/io/ground_truth.h"
#include "core/model/enum_names.h"
#include "tools/reconstruction_steps.h"

namespace nrsfm {
namespace tools {
namespace {

Status CheckFinite(const char* flag, double value) {
  if (!std::isfinite(value)) {
    return Status::Error(std::string("--") + flag + " must be a finite number");
  }
  return Status::OK();
}

}  // namespace

Status CheckSynthDataset(const std::string& dataset) {
  const char* const kDatasets[] = {"random", "superquadric", "shoe",
                                   "reproject"};
  std::string valid;
  for (const char* name : kDatasets) {
    if (dataset == name) return Status::OK();
    valid += (valid.empty() ? "" : ", ") + std::string(name);
  }
  return UnknownName("--dataset", dataset, valid);
}

Status CheckSynthOutput(const std::string& output) {
  if (output.empty()) return Status::Error("--output PATH.mat is required");
  if (std::filesystem::path(output).extension() != ".mat") {
    return Status::Error("--output must name a .mat file, got '" + output +
                         "'");
  }
  return Status::OK();
}

namespace {

// Parses "x,y,z" into a vector; false on anything else.
bool ParseVector3(const std::string& text, Eigen::Vector3d* v) {
  std::stringstream in(text);
  std::string item;
  int i = 0;
  while (std::getline(in, item, ',')) {
    if (i == 3) return false;
    try {
      std::size_t used = 0;
      (*v)(i) = std::stod(item, &used);
      if (used != item.size()) return false;
    } catch (...) {
      return false;
    }
    ++i;
  }
  return i == 3;
}

}  // namespace

Status SynthesizeReprojection(const CommandFlags& flags,
                              ReprojectedSequence* sequence,
                              std::vector<MatVariable>* variables) {
  if (flags.input.empty()) {
    return Status::Error(
        "--input is required for --dataset reproject (a .mat "
        "with S + Rs, P3_gt or X)");
  }
  if (!flags.K.empty() || flags.frames != -1 || flags.points != -1) {
    return Status::Error(
        "--K, --frames and --points do not apply to --dataset "
        "reproject (the source fixes them)");
  }
  if (flags.noise != 0.0) {
    return Status::Error(
        "--noise does not apply to --dataset reproject; give "
        "--noise_fraction (of the image size)");
  }
  ReprojectOptions options;
  options.total_rotation_deg = flags.rotation;
  if (!ParseVector3(flags.axis, &options.axis)) {
    return Status::Error("--axis must be three numbers x,y,z, got '" +
                         flags.axis + "'");
  }
  NRSFM_RETURN_IF_ERROR(ParseSpeedProfile(flags.profile, &options.profile)
                            .WithContext("--profile"));
  options.noise_fraction = flags.noise_fraction;
  options.missing_fraction = flags.missing;
  options.occlusion_radius = flags.occlusion;
  options.seed = flags.seed;
  options.distance_ratio = flags.distance_ratio;
  GroundTruth source;
  NRSFM_RETURN_IF_ERROR(ReadTruth(flags.input, flags.truth_var, &source));
  NRSFM_RETURN_IF_ERROR(GenerateReprojection(source, options, sequence)
                            .WithContext("--input " + flags.input));
  const Measurements& m = sequence->measurements;
  const int f = m.num_frames, p = m.num_points;
  Eigen::MatrixXd w = m.W, s(3 * f, p), rs(2 * f, 3);
  for (int t = 0; t < f; ++t) {
    s.middleRows(3 * t, 3) = sequence->truth.points_in_object[t];
    rs.middleRows(2 * t, 2) = sequence->truth.rotations[t].topRows<2>();
  }
  *variables = {
      {"W", w, {}},
      {"S", s, {}},
      {"Rs", rs, {}},
      {"cameras", Eigen::MatrixXd::Constant(1, 1, 1.0), {}},
      {"image_size", Eigen::MatrixXd::Constant(1, 1, sequence->image_size), {}},
      {"noise_stddev",
       Eigen::MatrixXd::Constant(1, 1, sequence->noise_stddev),
       {}}};
  if (m.intrinsics.cols() == 1) {
    const Eigen::Vector4d k = m.intrinsics.col(0);
    Eigen::Matrix3d kcam;
    kcam << k(0), 0.0, k(2), 0.0, k(1), k(3), 0.0, 0.0, 1.0;
    Eigen::MatrixXd x(3, static_cast<Eigen::Index>(p) * f);
    for (int t = 0; t < f; ++t) {
      x.middleCols(static_cast<Eigen::Index>(p) * t, p) =
          sequence->truth.points_in_camera[t];
    }
    variables->push_back({"Kcam", kcam, {}});
    variables->push_back({"X", x, {3, p, f}});
  }
  // The skeleton edges of the source, for nrsfm view.
  Eigen::MatrixXd list;
  if (std::filesystem::path(flags.input).extension() == ".mat" &&
      ReadMatVariable(flags.input, "list", &list).ok()) {
    variables->push_back({"list", list, {}});
  }
  return Status::OK();
}

Status Synthesize(const CommandFlags& flags, SyntheticSequence* sequence) {
  NumBasesFlag num_bases;
  if (!ParseNumBasesFlag(flags.K, &num_bases).ok() || num_bases.automatic) {
    return Status::Error("--K must be an integer >= 1 for synth, got '" +
                         flags.K + "'");
  }
  const int k = num_bases.given ? num_bases.value : -1;
  NRSFM_RETURN_IF_ERROR(CheckFinite("noise", flags.noise));
  NRSFM_RETURN_IF_ERROR(CheckFinite("missing", flags.missing));
  // --frames, --noise, --missing and --seed of the random and superquadric
  // data.
  const auto set_sequence = [&flags](SmoothSequenceOptions* o) {
    if (flags.frames != -1) o->num_frames = flags.frames;
    o->noise_stddev = flags.noise;
    o->missing_fraction = flags.missing;
    o->seed = flags.seed;
  };
  if (flags.dataset == "random") {
    RandomBasisOptions o;
    set_sequence(&o);
    if (flags.points != -1) o.num_points = flags.points;
    if (k != -1) o.num_bases = k;
    return GenerateRandomBasis(o, sequence);
  }
  if (flags.dataset == "superquadric") {
    if (k != -1)
      return Status::Error("--K is fixed (4) for the superquadric dataset");
    SuperquadricOptions o;
    set_sequence(&o);
    if (flags.points != -1) o.num_points = flags.points;
    return GenerateSuperquadric(o, sequence);
  }
  if (flags.dataset == "shoe") {
    if (k != -1) return Status::Error("--K is fixed (4) for the shoe dataset");
    if (flags.missing != 0.0) {
      return Status::Error(
          "--missing does not apply to the shoe dataset (its "
          "missing entries come from self-occlusion)");
    }
    ShoeOptions o;
    if (flags.frames != -1) o.num_frames = flags.frames;
    if (flags.points != -1) o.num_points = flags.points;
    o.num_cameras = flags.cameras == 0 ? 1 : flags.cameras;
    o.noise_stddev = flags.noise;
    o.seed = flags.seed;
    return GenerateShoe(o, sequence);
  }
  NRSFM_RETURN_IF_ERROR(CheckSynthDataset(flags.dataset));
  return Status::Error(
      "--dataset reproject is made by SynthesizeReprojection, not here");
}

std::vector<MatVariable> SyntheticVariables(const SyntheticSequence& sequence) {
  const Measurements& m = sequence.measurements;
  const Model& truth = sequence.truth;
  // W with NaN at missing entries; P3_gt = camera 0's 3D truth in the block
  // layout [x rows of all frames; y rows; z rows], as in the face data.
  Eigen::MatrixXd w = m.W;
  for (int view = 0; view < m.NumViews(); ++view) {
    for (int p = 0; p < m.num_points; ++p) {
      if (!m.visible(view, p)) w.block<2, 1>(2 * view, p).setConstant(NAN);
    }
  }
  const int f = m.num_frames;
  Eigen::MatrixXd p3_gt(3 * f, m.num_points);
  for (int t = 0; t < f; ++t) {
    Eigen::Matrix3Xd x = truth.ShapeInCamera(t, 0);
    x.topRows<2>().colwise() += truth.translations.col(truth.View(t, 0));
    for (int axis = 0; axis < 3; ++axis) p3_gt.row(axis * f + t) = x.row(axis);
  }
  Eigen::MatrixXd rotations(3, truth.NumViews());
  rotations = truth.rotations;
  return {{"W", w, {}},
          {"P3_gt", p3_gt, {}},
          {"rotations_gt", rotations, {}},
          {"weights_gt", truth.weights.transpose(), {}},
          {"basis_gt", truth.basis, {}},
          {"cameras", Eigen::MatrixXd::Constant(1, 1, m.num_cameras), {}}};
}

}  // namespace tools
}  // namespace nrsfm
