#pragma once
// The run viewer's script and style sheet (run_viewer.js, run_viewer.css beside this
// header), compiled in by cmake/embed_text.cmake (see CMakeLists.txt).

namespace hazmap::eval::viewer_assets {

extern const char kScript[];
extern const char kStyle[];

}  // namespace hazmap::eval::viewer_assets
