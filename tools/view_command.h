// `nrsfm view`: a reconstruction as one self-contained HTML page.
#ifndef NRSFM_TOOLS_VIEW_COMMAND_H_
#define NRSFM_TOOLS_VIEW_COMMAND_H_

#include <ostream>

#include "core/model/status.h"
#include "tools/commands.h"

namespace nrsfm {
namespace tools {

// nrsfm view --result DIR [--truth PATH [--truth_var NAME]]
//            [--input PATH [--var NAME] [--mask_var NAME] [--format F]]
//            --output FILE.html [--overwrite]
// Writes the page of tools/view_page.h from the data of tools/view_data.h
// and prints one line saying what it holds. Fails (writing nothing) on the
// errors of CheckViewerOutput, GatherViewData and WriteViewerPage.
Status RunView(const CommandFlags& flags, std::ostream& out);

}  // namespace tools
}  // namespace nrsfm

#endif  // NRSFM_TOOLS_VIEW_COMMAND_H_
