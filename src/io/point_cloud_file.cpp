#include "hazmap/io/point_cloud_file.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace fs = std::filesystem;
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

Error at_line(const fs::path& path, std::size_t line, const std::string& what) {
  return Error(path.string() + ":" + std::to_string(line) + ": " + what);
}

/// Parses one number token completely ("1.5" yes, "1.5x" or "" no).
bool parse_number(const std::string& token, double& value) {
  if (token.empty()) return false;
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return *end == '\0';
}

void check_point(const fs::path& path, std::size_t line, const Eigen::Vector3d& p,
                 const char* where = "line") {
  if (!p.allFinite())
    throw Error(path.string() + (std::strcmp(where, "line") == 0 ? ":" : ": vertex ") +
                std::to_string(line) + ": coordinates must be finite numbers");
}

std::vector<Eigen::Vector3d> read_text_cloud(const fs::path& path, std::istream& in) {
  std::vector<Eigen::Vector3d> points;
  std::string line;
  for (std::size_t line_no = 1; std::getline(in, line); ++line_no) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    for (char& c : line)
      if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
    std::istringstream fields(line);
    std::string tokens[3];
    int n = 0;
    for (std::string tok; n < 3 && fields >> tok;) tokens[n++] = tok;
    if (n == 0) continue;
    if (n < 3)
      throw at_line(path, line_no, "expected x y z, found " + std::to_string(n) + " field(s)");
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i)
      if (!parse_number(tokens[i], p[i]))
        throw at_line(path, line_no, "field " + std::to_string(i + 1) + " is not a number: '" +
                                         tokens[i] + "'");
    check_point(path, line_no, p);
    points.push_back(p);
  }
  return points;
}

struct PlyProperty {
  std::string name;
  int bytes = 0;
  char kind = 'f';  ///< 'i' signed, 'u' unsigned, 'f' floating
};

bool ply_type(const std::string& t, PlyProperty& p) {
  static const struct { const char* name; int bytes; char kind; } kTypes[] = {
      {"char", 1, 'i'},  {"int8", 1, 'i'},    {"uchar", 1, 'u'},  {"uint8", 1, 'u'},
      {"short", 2, 'i'}, {"int16", 2, 'i'},   {"ushort", 2, 'u'}, {"uint16", 2, 'u'},
      {"int", 4, 'i'},   {"int32", 4, 'i'},   {"uint", 4, 'u'},   {"uint32", 4, 'u'},
      {"float", 4, 'f'}, {"float32", 4, 'f'}, {"double", 8, 'f'}, {"float64", 8, 'f'}};
  for (const auto& k : kTypes)
    if (t == k.name) {
      p.bytes = k.bytes;
      p.kind = k.kind;
      return true;
    }
  return false;
}

/// A little-endian binary value of `p`'s type (this code runs on little-endian hosts:
/// x86-64 and ARM Linux).
double binary_value(const unsigned char* b, const PlyProperty& p) {
  switch (p.bytes) {
    case 1: return p.kind == 'i' ? static_cast<double>(static_cast<std::int8_t>(b[0])) : b[0];
    case 2: {
      std::uint16_t u;
      std::memcpy(&u, b, 2);
      return p.kind == 'i' ? static_cast<double>(static_cast<std::int16_t>(u)) : u;
    }
    case 4: {
      if (p.kind == 'f') {
        float f;
        std::memcpy(&f, b, 4);
        return f;
      }
      std::uint32_t u;
      std::memcpy(&u, b, 4);
      return p.kind == 'i' ? static_cast<double>(static_cast<std::int32_t>(u)) : u;
    }
    default: {
      double d;
      std::memcpy(&d, b, 8);
      return d;
    }
  }
}

std::vector<Eigen::Vector3d> read_ply_cloud(const fs::path& path, std::istream& in) {
  std::string line;
  std::size_t line_no = 0;
  auto next = [&]() -> bool {
    if (!std::getline(in, line)) return false;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  if (!next() || line != "ply") throw at_line(path, 1, "not a PLY file (first line must be 'ply')");
  std::string format;
  long long vertices = -1;
  bool in_vertex = false, vertex_done = false;
  std::vector<PlyProperty> props;
  for (;;) {
    if (!next()) throw Error(path.string() + ": PLY header has no 'end_header'");
    std::istringstream f(line);
    std::string key;
    f >> key;
    if (key == "end_header") break;
    if (key == "comment" || key == "obj_info" || key.empty()) continue;
    if (key == "format") {
      std::string version;
      f >> format >> version;
      if (format != "ascii" && format != "binary_little_endian")
        throw at_line(path, line_no, "PLY format '" + format +
                                         "' not supported (ascii or binary_little_endian)");
    } else if (key == "element") {
      std::string name;
      long long count = -1;
      f >> name >> count;
      if (in_vertex) vertex_done = true;
      in_vertex = false;
      if (name == "vertex") {
        if (vertices >= 0 || vertex_done)
          throw at_line(path, line_no, "second 'element vertex'");
        if (!(count >= 0)) throw at_line(path, line_no, "malformed 'element vertex' count");
        vertices = count;
        in_vertex = true;
      } else if (vertices < 0) {
        throw at_line(path, line_no, "the first element must be 'vertex', found '" + name + "'");
      } else {
        vertex_done = true;
      }
    } else if (key == "property") {
      if (!in_vertex) continue;  // a later element's property: never read
      std::string type, name;
      f >> type;
      if (type == "list") throw at_line(path, line_no, "list properties of vertices not supported");
      f >> name;
      PlyProperty p;
      p.name = name;
      if (name.empty() || !ply_type(type, p))
        throw at_line(path, line_no, "malformed property line (type '" + type + "')");
      props.push_back(p);
    } else {
      throw at_line(path, line_no, "unknown PLY header keyword '" + key + "'");
    }
  }
  if (format.empty()) throw Error(path.string() + ": PLY header has no 'format' line");
  if (vertices < 0) throw Error(path.string() + ": PLY header has no 'element vertex'");
  int ix = -1, iy = -1, iz = -1;
  for (int i = 0; i < static_cast<int>(props.size()); ++i) {
    if (props[i].name == "x") ix = i;
    if (props[i].name == "y") iy = i;
    if (props[i].name == "z") iz = i;
  }
  if (ix < 0 || iy < 0 || iz < 0)
    throw Error(path.string() + ": PLY vertices need properties x, y and z");
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<std::size_t>(std::min<long long>(vertices, 1 << 24)));
  if (format == "ascii") {
    for (long long v = 0; v < vertices; ++v) {
      if (!next())
        throw Error(path.string() + ": ends after " + std::to_string(v) + " of " +
                    std::to_string(vertices) + " vertices");
      std::istringstream f(line);
      std::vector<double> values;
      for (std::string tok; values.size() < props.size() && f >> tok;) {
        double value = 0;
        if (!parse_number(tok, value))
          throw at_line(path, line_no, "not a number: '" + tok + "'");
        values.push_back(value);
      }
      if (values.size() < props.size())
        throw at_line(path, line_no, "expected " + std::to_string(props.size()) +
                                         " vertex values, found " + std::to_string(values.size()));
      const Eigen::Vector3d p(values[ix], values[iy], values[iz]);
      check_point(path, line_no, p);
      points.push_back(p);
    }
    return points;
  }
  std::vector<int> offset(props.size());
  int stride = 0;
  for (std::size_t i = 0; i < props.size(); ++i) {
    offset[i] = stride;
    stride += props[i].bytes;
  }
  std::vector<unsigned char> record(static_cast<std::size_t>(stride));
  for (long long v = 0; v < vertices; ++v) {
    if (!in.read(reinterpret_cast<char*>(record.data()), stride))
      throw Error(path.string() + ": ends after " + std::to_string(v) + " of " +
                  std::to_string(vertices) + " vertices");
    const Eigen::Vector3d p(binary_value(&record[offset[ix]], props[ix]),
                            binary_value(&record[offset[iy]], props[iy]),
                            binary_value(&record[offset[iz]], props[iz]));
    check_point(path, static_cast<std::size_t>(v), p, "vertex");
    points.push_back(p);
  }
  return points;
}

}  // namespace

std::vector<Eigen::Vector3d> read_point_cloud(const fs::path& path) {
  if (fs::is_directory(path)) throw Error(path.string() + ": is a folder, not a point cloud");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open point cloud");
  const bool ply = lower(path.extension().string()) == ".ply";
  std::vector<Eigen::Vector3d> points = ply ? read_ply_cloud(path, in) : read_text_cloud(path, in);
  if (points.empty()) throw Error(path.string() + ": no points");
  return points;
}

}  // namespace hazmap
