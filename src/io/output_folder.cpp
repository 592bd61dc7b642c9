#include "hazmap/io/output_folder.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <system_error>

#include "hazmap/core/error.hpp"

namespace fs = std::filesystem;

namespace hazmap {
namespace {

enum class Holds { frame_folders, files };

struct OwnFolder {
  const char* name;
  Holds holds;
};

/// What one command writes at the top of its folder, and how its messages name it.
struct Layout {
  const char* who;   ///< "which <who> did not write"
  const char* flag;  ///< how the command line names the folder
  std::vector<OwnFolder> folders;
  std::vector<const char*> files;
  /// Without it the entries above are someone else's (a sequence looks alike whoever
  /// made it): the reason, as the message gives it; empty when `dir` bears the mark.
  /// nullptr: no mark needed.
  std::string (*unmarked)(const fs::path& dir);
};

/// simulate writes simulation.yaml first (sim/simulate.cpp).
std::string simulate_unmarked(const fs::path& dir) {
  std::error_code ec;
  return fs::symlink_status(dir / "simulation.yaml", ec).type() == fs::file_type::regular
             ? ""
             : "no simulation.yaml, so not a sequence it simulated";
}

/// import-euroc writes poses.txt first, its first line saying where from (io/euroc.cpp).
std::string import_unmarked(const fs::path& dir) {
  const fs::path poses = dir / "poses.txt";
  std::error_code ec;
  std::string first;
  if (fs::symlink_status(poses, ec).type() == fs::file_type::regular) {
    std::ifstream in(poses);
    std::getline(in, first);
  }
  return first.rfind("#", 0) == 0 && first.find("imported from EuRoC") != std::string::npos
             ? ""
             : "no poses.txt saying 'imported from EuRoC', so not a sequence it imported";
}

// Kept in step with what the writers write.
// run and stereo: sequence_runner.cpp (summary.json), frame_writer.cpp (frames/, mosaic/),
// cmd_run.cpp and cmd_stereo.cpp (run.log), cmd_stereo.cpp (stereo_summary.json),
// run_evaluation.cpp (eval/, the default --out), run_viewer.cpp (view.html, hazmap view's
// default --out).
const Layout& layout(OutputOwner owner) {
  static const Layout run = {
      "hazmap",
      "--out",
      {{"frames", Holds::frame_folders}, {"mosaic", Holds::files}, {"eval", Holds::files}},
      {"summary.json", "stereo_summary.json", "run.log", "view.html"},
      nullptr};
  // sim/simulate.cpp: simulate_sequence.
  static const Layout simulate = {
      "hazmap simulate",
      "--out",
      {{"left", Holds::files}, {"right", Holds::files}, {"depth", Holds::files}},
      {"calibration.yaml", "simulation.yaml", "poses.txt", "poses_true.txt", "gt_height.jdem",
       "gt_hazard.jdem"},
      simulate_unmarked};
  // io/euroc.cpp: import_euroc.
  static const Layout import_euroc = {"hazmap import-euroc",
                                      "DST",
                                      {{"left", Holds::files}, {"right", Holds::files}},
                                      {"calibration.yaml", "poses.txt"},
                                      import_unmarked};
  switch (owner) {
    case OutputOwner::simulate: return simulate;
    case OutputOwner::import_euroc: return import_euroc;
    case OutputOwner::run: break;
  }
  return run;
}

/// How many foreign entries a refusal names before "and N more": enough to recognise
/// the folder (left, right, poses.txt: a sequence), short enough for one line.
constexpr size_t kNamedEntries = 4;

const OwnFolder* own_folder(const Layout& l, const std::string& name) {
  for (const OwnFolder& f : l.folders)
    if (name == f.name) return &f;
  return nullptr;
}

bool is_own_file(const Layout& l, const std::string& name) {
  return std::any_of(l.files.begin(), l.files.end(), [&](const char* f) { return name == f; });
}

/// ".summary.json.tmp<pid>_<n>": write_file_atomically's temporary, left by a kill -9.
bool is_own_temporary(const Layout& l, const std::string& name) {
  for (const char* file : l.files)
    if (name.rfind("." + std::string(file) + ".tmp", 0) == 0) return true;
  return false;
}

/// Content of an own folder (frames/, mosaic/, eval/; left/, right/, depth/) that does
/// not fit `holds`, relative to OUT.
/// symlink_status throughout: a link is never ours (removing it would be harmless, but
/// a link into someone's data is not a folder hazmap wrote).
void check_content(const fs::path& folder, const std::string& name, Holds holds,
                   std::vector<std::string>& foreign) {
  std::error_code ec;
  std::vector<std::string> misfits;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::file_type type = it->symlink_status(ec).type();
    const bool fits = holds == Holds::frame_folders ? type == fs::file_type::directory
                                                    : type == fs::file_type::regular;
    if (!fits) misfits.push_back(name + "/" + it->path().filename().string());
  }
  if (ec) throw Error(folder.string() + ": cannot list: " + ec.message());
  std::sort(misfits.begin(), misfits.end());
  foreign.insert(foreign.end(), misfits.begin(), misfits.end());
}

std::string named_list(const std::vector<std::string>& names) {
  std::string text;
  for (size_t i = 0; i < names.size() && i < kNamedEntries; ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > kNamedEntries)
    text += " and " + std::to_string(names.size() - kNamedEntries) + " more";
  return text;
}

}  // namespace

OutputFolder inspect_output_folder(const fs::path& dir, OutputOwner owner) {
  const Layout& l = layout(owner);
  OutputFolder out;
  out.dir = dir;
  out.owner = owner;
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  out.exists = fs::exists(status);
  out.is_folder = fs::is_directory(status);
  if (!out.exists || !out.is_folder) return out;
  std::vector<fs::path> entries;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    entries.push_back(it->path());
  if (ec) throw Error(dir.string() + ": cannot list: " + ec.message());
  std::sort(entries.begin(), entries.end());  // the same message whatever the file system's order
  for (const fs::path& entry : entries) {
    const std::string name = entry.filename().string();
    const fs::file_type type = fs::symlink_status(entry, ec).type();
    if (const OwnFolder* own = own_folder(l, name); own && type == fs::file_type::directory) {
      // Ours only when its content is too; otherwise that content is what is listed.
      const size_t foreign_before = out.foreign.size();
      check_content(entry, name, own->holds, out.foreign);
      if (out.foreign.size() == foreign_before) out.ours.push_back(entry);
      continue;
    }
    if (type == fs::file_type::regular && (is_own_file(l, name) || is_own_temporary(l, name)))
      out.ours.push_back(entry);
    else
      out.foreign.push_back(name);
  }
  // Entries named like a sequence's are the command's own only beside its mark; a
  // temporary (a write cut short before the mark was written) is its own by its name.
  if (l.unmarked && !out.ours.empty()) {
    out.unmarked = l.unmarked(dir);
    if (!out.unmarked.empty()) {
      std::vector<fs::path> temporaries;
      for (const fs::path& entry : out.ours) {
        const std::string name = entry.filename().string();
        if (is_own_temporary(l, name))
          temporaries.push_back(entry);
        else
          out.foreign.push_back(name);
      }
      out.ours = temporaries;
      std::sort(out.foreign.begin(), out.foreign.end());
      if (out.foreign.empty()) out.unmarked.clear();
    }
  }
  return out;
}

std::string output_folder_refusal(const OutputFolder& folder, bool overwrite) {
  const Layout& l = layout(folder.owner);
  const std::string dir = std::string(l.flag) + " " + folder.dir.string();
  if (folder.exists && !folder.is_folder) return dir + ": exists and is not a folder";
  if (!folder.foreign.empty())
    return dir + ": holds " + named_list(folder.foreign) + ", which " + l.who +
           " did not write" + (folder.unmarked.empty() ? "" : " (" + folder.unmarked + ")") +
           "; refusing to write there, --overwrite included (it removes only " + l.who +
           "'s own outputs): choose an empty or new folder";
  if (!folder.ours.empty() && !overwrite) {
    std::vector<std::string> names;
    for (const fs::path& p : folder.ours) names.push_back(p.filename().string());
    return dir + ": not empty (an earlier output: " + named_list(names) +
           "); pass --overwrite to replace it, or choose an empty or new folder";
  }
  return {};
}

void clear_output_folder(const OutputFolder& folder) {
  for (const fs::path& entry : folder.ours) {
    std::error_code ec;
    fs::remove_all(entry, ec);
    if (ec) throw Error(entry.string() + ": cannot remove it (--overwrite): " + ec.message());
  }
}

}  // namespace hazmap
