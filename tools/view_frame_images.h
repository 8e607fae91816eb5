// The frames of ViewDataOptions::frames_dir for the page of `nrsfm view`
// (tools/view_data.h): each image file's bytes as a data: URL, which the
// browser decodes under the 2D view.
#ifndef NRSFM_TOOLS_VIEW_FRAME_IMAGES_H_
#define NRSFM_TOOLS_VIEW_FRAME_IMAGES_H_

#include "core/model/status.h"
#include "tools/view_data.h"

namespace nrsfm {
namespace tools {

// Sets data->frame_images, one per frame of the result (one camera), in
// the order `nrsfm track` numbers a folder (track/tracks.h ListFrameFiles).
// Fails, naming the folder or file, on several cameras, a folder that does
// not hold F frames, a file that is not PNG, JPEG, BMP or WebP, or cannot be
// read.
Status AddFrameImages(const ViewDataOptions& options, ViewData* data);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_VIEW_FRAME_IMAGES_H_
