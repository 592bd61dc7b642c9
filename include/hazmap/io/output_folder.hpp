#pragma once
// The OUT folder of `hazmap run` and `hazmap stereo` (issue 22). Frames of two runs must
// never mix in one folder (evaluate would score one configuration's frames with
// another's settings), so a command writes only into a folder that is absent or empty,
// or, with --overwrite, into one that holds nothing but an earlier hazmap output, which
// it then removes first. A folder holding anything else (a home folder, a sequence, a
// user's notes) is refused even with --overwrite, and nothing in it is touched: the rule
// removes only what hazmap itself would have written.
//
// hazmap's own entries at the top of OUT, with the type each must have:
//   frames/               run and stereo: one folder per frame (and hidden staging ones)
//   mosaic/               run --mosaic: <frame>.png
//   eval/                 evaluate's default output folder: files only
//   summary.json          run
//   stereo_summary.json   stereo
//   run.log               run and stereo
//   view.html             view's default output
//   .<file>.tmp<...>      an atomic write of one of those files cut short (kill -9)
// frames/ must hold only folders, mosaic/ and eval/ only files: a "frames" folder of
// someone's images is not ours.

#include <filesystem>
#include <string>
#include <vector>

namespace hazmap {

/// What inspect_output_folder found. Nothing is changed by looking.
struct OutputFolder {
  std::filesystem::path dir;
  bool exists = false;
  bool is_folder = false;
  std::vector<std::filesystem::path> ours;  ///< hazmap's entries (top level), to clear
  std::vector<std::string> foreign;         ///< entries hazmap does not write, relative to dir
  bool empty() const { return ours.empty() && foreign.empty(); }
};

/// Lists `dir` (one level, and the content of frames/, mosaic/ and eval/). An absent
/// `dir` is fine (exists = false). Throws Error naming the folder when it cannot be
/// listed (permissions).
OutputFolder inspect_output_folder(const std::filesystem::path& dir);

/// Why a command must not write into `folder`, as one line naming it; empty when it may:
/// absent, empty, or only hazmap's entries and `overwrite`. A folder with foreign entries
/// is refused whatever `overwrite` says; one with an earlier output and no `overwrite`
/// is refused with the advice to pass --overwrite.
std::string output_folder_refusal(const OutputFolder& folder, bool overwrite);

/// Removes `folder.ours` (whole), and nothing else. Call only once every input has been
/// checked, so a bad input leaves the earlier output as it was. Throws Error naming the
/// entry it cannot remove.
void clear_output_folder(const OutputFolder& folder);

}  // namespace hazmap
