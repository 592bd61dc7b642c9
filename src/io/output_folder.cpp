#include "hazmap/io/output_folder.hpp"

#include <algorithm>
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

// Kept in step with what the writers write: sequence_runner.cpp (summary.json),
// frame_writer.cpp (frames/, mosaic/), cmd_run.cpp and cmd_stereo.cpp (run.log),
// cmd_stereo.cpp (stereo_summary.json), run_evaluation.cpp (eval/, the default --out),
// run_viewer.cpp (view.html, hazmap view's default --out).
constexpr OwnFolder kOwnFolders[] = {
    {"frames", Holds::frame_folders}, {"mosaic", Holds::files}, {"eval", Holds::files}};
constexpr const char* kOwnFiles[] = {"summary.json", "stereo_summary.json", "run.log", "view.html"};

/// How many foreign entries a refusal names before "and N more": enough to recognise
/// the folder (left, right, poses.txt: a sequence), short enough for one line.
constexpr size_t kNamedEntries = 4;

const OwnFolder* own_folder(const std::string& name) {
  for (const OwnFolder& f : kOwnFolders)
    if (name == f.name) return &f;
  return nullptr;
}

bool is_own_file(const std::string& name) {
  return std::any_of(std::begin(kOwnFiles), std::end(kOwnFiles),
                     [&](const char* f) { return name == f; });
}

/// ".summary.json.tmp<pid>_<n>": write_file_atomically's temporary, left by a kill -9.
bool is_own_temporary(const std::string& name) {
  for (const char* file : kOwnFiles)
    if (name.rfind("." + std::string(file) + ".tmp", 0) == 0) return true;
  return false;
}

/// Content of frames/, mosaic/ or eval/ that does not fit `holds`, relative to OUT.
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

OutputFolder inspect_output_folder(const fs::path& dir) {
  OutputFolder out;
  out.dir = dir;
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
    if (const OwnFolder* own = own_folder(name); own && type == fs::file_type::directory) {
      // Ours only when its content is too; otherwise that content is what is listed.
      const size_t foreign_before = out.foreign.size();
      check_content(entry, name, own->holds, out.foreign);
      if (out.foreign.size() == foreign_before) out.ours.push_back(entry);
      continue;
    }
    if (type == fs::file_type::regular && (is_own_file(name) || is_own_temporary(name)))
      out.ours.push_back(entry);
    else
      out.foreign.push_back(name);
  }
  return out;
}

std::string output_folder_refusal(const OutputFolder& folder, bool overwrite) {
  const std::string dir = folder.dir.string();
  if (folder.exists && !folder.is_folder) return "--out " + dir + ": exists and is not a folder";
  if (!folder.foreign.empty())
    return "--out " + dir + ": holds " + named_list(folder.foreign) +
           ", which hazmap did not write; refusing to write there, --overwrite included (it "
           "removes only hazmap's own outputs): choose an empty or new folder";
  if (!folder.ours.empty() && !overwrite) {
    std::vector<std::string> names;
    for (const fs::path& p : folder.ours) names.push_back(p.filename().string());
    return "--out " + dir + ": not empty (an earlier output: " + named_list(names) +
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
