// The files `nrsfm view` inlines into its pages, embedded at build time by
// tools/viewer/embed.cmake (the definitions are generated into the build
// tree). Each is the file's bytes, NUL-terminated.
#ifndef NRSFM_TOOLS_VIEWER_ASSETS_H_
#define NRSFM_TOOLS_VIEWER_ASSETS_H_

#include <cstddef>

namespace nrsfm {
namespace tools {

// tools/viewer/page.html: the page template.
extern const char kViewerPageHtml[];
extern const std::size_t kViewerPageHtmlSize;
// tools/viewer/viewer_util.js then tools/viewer/viewer.js: the page's script.
extern const char kViewerJs[];
extern const std::size_t kViewerJsSize;
// three.min.js of libjs-three (three.js r111, MIT licence).
extern const char kThreeJs[];
extern const std::size_t kThreeJsSize;
// examples/js/controls/OrbitControls.js of libjs-three.
extern const char kOrbitControlsJs[];
extern const std::size_t kOrbitControlsJsSize;

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_VIEWER_ASSETS_H_
