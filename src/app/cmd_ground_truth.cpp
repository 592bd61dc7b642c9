// hazmap ground-truth: a scanned point cloud in W -> gt_height.jdem, gt_hazard.jdem.

#include <cstdio>
#include <sstream>

#include <spdlog/spdlog.h>

#include "cli.hpp"
#include "hazmap/core/error.hpp"
#include "hazmap/eval/cloud_ground_truth.hpp"
#include "hazmap/io/point_cloud_file.hpp"

namespace hazmap::cli {

namespace {
const char* kGroundTruthUsage =
    R"(usage: hazmap ground-truth --cloud FILE --out DIR [--resolution R] [--fill-radius M]
                           [--ground-radius M] [--ground-tolerance M] [--crop X0,Y0,X1,Y1]
                           [--quiet]

Turns a point cloud in the world frame W (a laser scan of the terrain; x y z in metres)
into the ground truth 'hazmap evaluate' reads: DIR/gt_height.jdem (surface height per
cell), DIR/gt_hazard.jdem (obstacle height above the local ground, 0 on ground, as
'hazmap simulate' writes it) and DIR/ground_truth.yaml (how). Give the sequence folder as
DIR to score runs of that sequence. Method: docs/ground_truth.md.
  --cloud FILE          .ply (ascii or binary_little_endian, vertex x y z) or text
                        (.xyz .txt .csv: x y z per line, more columns ignored)
  --resolution R        cell size [m] (0.01)
  --fill-radius M       an empty cell is filled only when points within M of its centre
                        lie on all four sides of it, else NaN (3 cells)
  --ground-radius M     obstacles narrower than 2M are found; the ground is the lower
                        envelope at this scale (0.15)
  --ground-tolerance M  relief up to M above that envelope is ground (0.003)
  --crop X0,Y0,X1,Y1    only this box of W (default: the cloud's bounding box)
  --quiet               no summary line (errors and warnings still print)
)";
}  // namespace

int cmd_ground_truth(int argc, char** argv) {
  if (wants_help(argc, argv)) {
    std::fputs(kGroundTruthUsage, stdout);
    return kExitOk;
  }
  const Args args = parse_args(argc, argv,
                               {"cloud", "out", "resolution", "fill-radius", "ground-radius",
                                "ground-tolerance", "crop"},
                               {"quiet"});
  const std::string cloud = args.required("cloud");
  const std::string out = args.required("out");
  CloudGroundTruthOptions options;
  if (args.has("resolution")) options.resolution_m = args.number("resolution");
  if (args.has("fill-radius")) options.fill_radius_m = args.number("fill-radius");
  if (args.has("ground-radius")) options.ground_radius_m = args.number("ground-radius");
  if (args.has("ground-tolerance")) options.ground_tolerance_m = args.number("ground-tolerance");
  if (args.has("crop")) {
    std::istringstream in(args.get("crop"));
    double v[4];
    char comma = 0;
    if (!(in >> v[0] >> comma >> v[1] >> comma >> v[2] >> comma >> v[3]) || !in.eof())
      throw UsageError("--crop: expected X0,Y0,X1,Y1");
    options.x0_m = v[0], options.y0_m = v[1], options.x1_m = v[2], options.y1_m = v[3];
  }
  try {
    validate(options);
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
  setup_logging("", args.on("quiet"));
  const auto points = read_point_cloud(cloud);
  CloudGroundTruth gt;
  try {
    gt = cloud_ground_truth(points, options);
  } catch (const Error& e) {
    throw Error(cloud + ": " + e.what());  // name the cloud whose extent is at fault
  }
  write_cloud_ground_truth(out, gt, options, cloud);
  spdlog::info(
      "ground truth {} x {} cells of {} m from {} points: {} measured, {} filled, {} unknown, "
      "{} obstacle -> {}",
      gt.height.rows, gt.height.cols, options.resolution_m, gt.points, gt.cells_measured,
      gt.cells_filled, gt.cells_unknown, gt.cells_obstacle, out.c_str());
  return kExitOk;
}

}  // namespace hazmap::cli
