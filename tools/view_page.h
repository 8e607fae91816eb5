// The HTML page of `nrsfm view`: the page template (tools/viewer/page.html)
// with three.js r111 and its OrbitControls (Debian's libjs-three), the page
// script (tools/viewer/viewer_util.js, viewer.js) and the data inlined, so that
// the file works offline and on its own. The assets are embedded into the
// binary at build time (tools/viewer/embed.cmake), so nothing is read at run
// time but the inputs.
//
// The data sit in <script id="nrsfm-data" type="application/json">: an object
// with "meta" (sizes, paths, metrics, notes; see RenderViewerPage) and flat
// number arrays, frame-major: "estimate" and "truth" (F·P·3, x y z per
// point), "frame_error" (F), "reprojection" and "tracks" (F·M·P·2, u v per
// point, null where a track is missing), "frame_reprojection_rms" (F),
// "edges" (pairs of 0-based point indices). Coordinates have 7 significant
// digits, errors 10.
//
// The page honours a URL fragment: #frame=N (0-based frame shown first),
// play=1 (start playing), fps=N (playback speed, frames per second),
// camera=C (2D view of camera C), vup=1 (draw the image's v axis up, e.g. for
// motion capture with y up), orbit=A,E (first 3D view turned by azimuth A and
// elevation E, degrees), slide_to=N (after loading, moves the frame
// slider to N through its input event, as a user's drag does; for tests).
// It writes the frame shown into document.title ("nrsfm view: frame N of F")
// and the positions of its 3D and 2D panes into <body data-view3d="x y w h"
// data-view2d="x y w h"> (CSS pixels).
#ifndef NRSFM_TOOLS_VIEW_PAGE_H_
#define NRSFM_TOOLS_VIEW_PAGE_H_

#include <string>

#include "core/model/status.h"
#include "tools/view_data.h"

namespace nrsfm {
namespace tools {

// Paths shown on the page (as the user gave them).
struct ViewPageSources {
  std::string result_dir, truth_path, input_path;
};

std::string RenderViewerPage(const ViewData& data,
                             const ViewPageSources& sources);

// Checks, before any work, that `path` can be the output: it ends in .html or
// .htm, is not a directory, does not exist unless `overwrite`, and its
// directory exists.
Status CheckViewerOutput(const std::string& path, bool overwrite);

// Writes `html` to `path` through a hidden temporary file in the same
// directory, renamed when complete, so a failed write leaves no page.
Status WriteViewerPage(const std::string& path, const std::string& html);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_VIEW_PAGE_H_
