#include "tools/view_command.h"

#include <iomanip>
#include <string>

#include "tools/flag_table.h"
#include "tools/reconstruction_steps.h"
#include "tools/view_data.h"
#include "tools/view_page.h"

namespace nrsfm {
namespace tools {

Status RunView(const CommandFlags& flags, std::ostream& out) {
  if (flags.result.empty()) return Status::Error("--result DIR is required");
  NRSFM_RETURN_IF_ERROR(CheckViewerOutput(flags.output, flags.overwrite));
  ViewDataOptions options;
  options.result_dir = flags.result;
  options.truth_path = flags.truth;
  options.truth_variable = flags.truth_var;
  options.input_path = flags.input;
  options.frames_dir = flags.frames_dir;
  FlagTargets targets;
  NRSFM_RETURN_IF_ERROR(ApplyFlags(flags, &targets));
  options.input = targets.input;
  ViewData data;
  NRSFM_RETURN_IF_ERROR(GatherViewData(options, &data));
  const std::string html =
      RenderViewerPage(data, {flags.result, flags.truth, flags.input});
  NRSFM_RETURN_IF_ERROR(WriteViewerPage(flags.output, html));
  out << "wrote " << flags.output << " (" << html.size() / 1024
      << " KiB): F = " << data.num_frames << ", M = " << data.num_cameras
      << ", P = " << data.num_points << ", " << data.edges.size() << " edges ("
      << data.edge_source << ")";
  if (data.has_truth)
    out << std::setprecision(6) << ", e3D " << data.metrics.e3d;
  if (data.camera_model == CameraModel::kPerspective) {
    out << " (with one scale " << data.metrics.e3d_scaled << ")";
  }
  if (data.has_tracks) {
    out << std::setprecision(6) << ", reprojection RMS "
        << data.reprojection_rms;
  }
  out << "\n";
  for (const std::string& note : data.notes) out << "note: " << note << "\n";
  return Status::OK();
}

}  // namespace tools
}  // namespace nrsfm
