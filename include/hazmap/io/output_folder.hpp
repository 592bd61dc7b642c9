#pragma once
// The output folder of `hazmap run` and `hazmap stereo` (issue 22), `hazmap simulate` and
// `hazmap import-euroc`. Frames of two runs must never mix in one folder (evaluate would
// score one configuration's frames with another's settings), nor files of two sequences
// (a poses_true.txt left by an earlier `simulate --drift` would be read as the true poses
// of a later sequence without drift), so a command writes only into a folder that is
// absent or empty, or, with --overwrite, into one that holds nothing but an earlier output
// of that command, which it then removes first. A folder holding anything else (a home
// folder, a sequence, a user's notes) is refused even with --overwrite, and nothing in it
// is touched: the rule removes only what the command itself would have written.
//
// run and stereo (OutputOwner::run): hazmap's entries at the top of OUT, with the type
// each must have:
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
//
// simulate (OutputOwner::simulate, sim/simulate.cpp): left/, right/, depth/ (files only),
// calibration.yaml, simulation.yaml, poses.txt, poses_true.txt, gt_height.jdem,
// gt_hazard.jdem and the temporaries of those files. import-euroc
// (OutputOwner::import_euroc, io/euroc.cpp): left/, right/ (files only), calibration.yaml,
// poses.txt and their temporaries. A sequence folder looks alike whoever made it (a
// recording, an import, a simulation), so those entries count as the command's own only
// beside its mark: simulation.yaml for simulate, a poses.txt whose first line says
// "imported from EuRoC" for import-euroc. Without it they are foreign, and --overwrite
// never removes someone's recorded sequence.

#include <filesystem>
#include <string>
#include <vector>

namespace hazmap {

/// Which command's outputs a folder may hold (see above).
enum class OutputOwner { run, simulate, import_euroc };

/// What inspect_output_folder found. Nothing is changed by looking.
struct OutputFolder {
  std::filesystem::path dir;
  OutputOwner owner = OutputOwner::run;
  bool exists = false;
  bool is_folder = false;
  std::vector<std::filesystem::path> ours;  ///< hazmap's entries (top level), to clear
  std::vector<std::string> foreign;         ///< entries the owner does not write, relative to dir
  /// Set when entries named like the owner's were foreign for want of its mark: why.
  std::string unmarked;
  bool empty() const { return ours.empty() && foreign.empty(); }
};

/// Lists `dir` (one level, and the content of the owner's folders: frames/, mosaic/,
/// eval/; left/, right/, depth/) as a folder `owner` writes. An absent `dir` is fine
/// (exists = false). Throws Error naming the folder when it cannot be listed
/// (permissions).
OutputFolder inspect_output_folder(const std::filesystem::path& dir,
                                   OutputOwner owner = OutputOwner::run);

/// Why a command must not write into `folder`, as one line naming it ("--out DIR: ...",
/// "DST DIR: ..." for import-euroc); empty when it may: absent, empty, or only the
/// owner's entries and `overwrite`. A folder with foreign entries is refused whatever
/// `overwrite` says; one with an earlier output and no `overwrite` is refused with the
/// advice to pass --overwrite.
std::string output_folder_refusal(const OutputFolder& folder, bool overwrite);

/// Removes `folder.ours` (whole), and nothing else. Call only once every input has been
/// checked, so a bad input leaves the earlier output as it was. Throws Error naming the
/// entry it cannot remove.
void clear_output_folder(const OutputFolder& folder);

}  // namespace hazmap
