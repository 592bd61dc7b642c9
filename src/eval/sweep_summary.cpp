#include "hazmap/eval/sweep_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <spdlog/spdlog.h>

#include "hazmap/core/error.hpp"
#include "hazmap/core/number_text.hpp"
#include "hazmap/eval/html_report.hpp"
#include "hazmap/eval/metrics.hpp"
#include "hazmap/eval/plot.hpp"
#include "hazmap/io/atomic_file.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/io/run_layout.hpp"

namespace hazmap::eval {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(line);
  while (std::getline(in, item, sep)) out.push_back(item);
  if (!line.empty() && line.back() == sep) out.emplace_back();
  return out;
}

double number_or_nan(const std::string& text) {
  if (text.empty() || text == "-" || text == "nan") return kNaN;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return *end == '\0' ? v : kNaN;
}

std::string fmt(double v, const char* format) { return printf_finite(v, format, "-"); }

// One layer's pooled sums from a run's summary.csv (areas add across runs).
struct LayerRow {
  std::string layer;
  double resolution_m = 0, h_min_m = 0;
  std::string rule;
  double known_m2 = 0, gt_hazard_m2 = 0, gt_hazard_known_m2 = 0, missed_m2 = 0, false_alarm_m2 = 0;
  double sq_sum = 0;  ///< rms^2 * samples
  double samples = 0;
  double unknown_weighted = 0, extent_m2 = 0;

  void add(const LayerRow& o) {
    known_m2 += o.known_m2;
    gt_hazard_m2 += o.gt_hazard_m2;
    gt_hazard_known_m2 += o.gt_hazard_known_m2;
    missed_m2 += o.missed_m2;
    false_alarm_m2 += o.false_alarm_m2;
    sq_sum += o.sq_sum;
    samples += o.samples;
    unknown_weighted += o.unknown_weighted;
    extent_m2 += o.extent_m2;
  }
  double missed_of_hazard() const {
    return gt_hazard_known_m2 > 0 ? missed_m2 / gt_hazard_known_m2 : kNaN;
  }
  /// Share of the obstacle area (>= h_min, inside the window) the layer knows at all.
  double known_obstacle_share() const {
    return gt_hazard_m2 > 0 ? gt_hazard_known_m2 / gt_hazard_m2 : kNaN;
  }
  double false_alarm_fraction() const { return known_m2 > 0 ? false_alarm_m2 / known_m2 : kNaN; }
  double rms() const { return samples > 0 ? std::sqrt(sq_sum / samples) : kNaN; }
  double unknown_fraction() const { return extent_m2 > 0 ? unknown_weighted / extent_m2 : kNaN; }
};

std::vector<LayerRow> read_run_summary(const fs::path& csv_path) {
  std::ifstream in(csv_path);
  if (!in) throw Error(csv_path.string() + ": cannot read");
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line, ',');
  std::map<std::string, size_t> col;
  for (size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  for (const char* k : {"layer", "resolution_m", "rule", "h_min_m", "known_m2", "extent_m2",
                        "unknown_fraction", "height_rms_m", "height_samples",
                        "gt_hazard_m2", "gt_hazard_known_m2", "missed_m2", "false_alarm_m2"})
    if (!col.count(k)) throw Error(csv_path.string() + ":1: no column '" + k + "'");
  std::vector<LayerRow> rows;
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    const std::vector<std::string> f = split(line, ',');
    if (f.size() != header.size())
      throw Error(csv_path.string() + ":" + std::to_string(line_no) + ": expected " +
                  std::to_string(header.size()) + " fields");
    const auto num = [&](const char* k) { return number_or_nan(f[col.at(k)]); };
    const auto zero_if_nan = [](double v) { return std::isfinite(v) ? v : 0.0; };
    LayerRow r;
    r.layer = f[col.at("layer")];
    r.rule = f[col.at("rule")];
    r.resolution_m = num("resolution_m");
    r.h_min_m = num("h_min_m");
    r.known_m2 = zero_if_nan(num("known_m2"));
    r.extent_m2 = zero_if_nan(num("extent_m2"));
    r.unknown_weighted = zero_if_nan(num("unknown_fraction")) * r.extent_m2;
    r.gt_hazard_m2 = zero_if_nan(num("gt_hazard_m2"));
    r.gt_hazard_known_m2 = zero_if_nan(num("gt_hazard_known_m2"));
    r.missed_m2 = zero_if_nan(num("missed_m2"));
    r.false_alarm_m2 = zero_if_nan(num("false_alarm_m2"));
    r.samples = zero_if_nan(num("height_samples"));
    const double rms = num("height_rms_m");
    r.sq_sum = std::isfinite(rms) ? rms * rms * r.samples : 0.0;
    rows.push_back(r);
  }
  return rows;
}

// "L0 4 cm ccm" style label, with the layer's h_min.
std::string layer_label(const LayerRow& r) {
  return r.layer + " " + fmt(r.resolution_m * 100, "%g") + " cm";
}

struct Grid2 {
  std::vector<std::string> layers;   ///< row keys in first-seen order
  std::vector<double> keys;          ///< swept values, sorted
  std::map<std::string, std::map<double, LayerRow>> cells;
  std::map<std::string, LayerRow> layer_info;
};

void add_run(Grid2& g, double key, const std::vector<LayerRow>& rows) {
  if (std::find(g.keys.begin(), g.keys.end(), key) == g.keys.end()) {
    g.keys.push_back(key);
    std::sort(g.keys.begin(), g.keys.end());
  }
  for (const LayerRow& r : rows) {
    if (!g.layer_info.count(r.layer)) {
      g.layers.push_back(r.layer);
      g.layer_info[r.layer] = r;
    }
    auto& cell = g.cells[r.layer][key];
    if (cell.layer.empty()) cell = r;
    else cell.add(r);
  }
}

double cell_value(const Grid2& g, const std::string& layer, double key,
                  double (LayerRow::*metric)() const) {
  const auto it = g.cells.find(layer);
  if (it == g.cells.end()) return kNaN;
  const auto c = it->second.find(key);
  return c == it->second.end() ? kNaN : (c->second.*metric)();
}

std::string md_table(const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows) {
  std::ostringstream o;
  o << '|';
  for (const auto& h : header) o << ' ' << h << " |";
  o << "\n|";
  for (size_t i = 0; i < header.size(); ++i) o << (i == 0 ? "---|" : "---:|");
  o << '\n';
  for (const auto& row : rows) {
    o << '|';
    for (const auto& c : row) o << ' ' << c << " |";
    o << '\n';
  }
  return o.str();
}

std::string csv_table(const std::vector<std::string>& header,
                      const std::vector<std::vector<std::string>>& rows) {
  std::ostringstream o;
  for (size_t i = 0; i < header.size(); ++i) o << (i ? "," : "") << header[i];
  o << '\n';
  for (const auto& row : rows) {
    for (size_t i = 0; i < row.size(); ++i) o << (i ? "," : "") << (row[i] == "-" ? "nan" : row[i]);
    o << '\n';
  }
  return o.str();
}

/// Obstacle sizes: the smallest swept radius each layer detects (detectable_size.csv).
void add_sizes_section(const std::map<std::string, Grid2>& sizes, const fs::path& out_dir,
                       std::ostringstream& md, HtmlPage& page) {
  std::vector<std::vector<std::string>> detect_rows;
  for (const auto& [map_name, g] : sizes) {
    std::vector<std::string> cols;
    for (double r : g.keys) cols.push_back(fmt(r * 100, "%g"));
    struct SizeTable {
      const char* stem;
      const char* title;
      std::string caption;
      double max_value;
      double (LayerRow::*metric)() const;
    };
    const SizeTable tables[] = {
        {"missed_by_size_", "missed obstacle area / known obstacle area",
         "Missed-obstacle fraction by layer and obstacle radius, " + map_name +
             " (share of the known obstacle area at least h_min high that the layer calls "
             "traversable; - = the layer knows no such obstacle area)",
         1.0, &LayerRow::missed_of_hazard},
        {"known_obstacle_by_size_", "known obstacle area / obstacle area in the window",
         "Share of the obstacle area (at least h_min high, inside the window) the layer knows "
         "at all, " + map_name + " (- = no obstacle area at least h_min high)",
         1.0, &LayerRow::known_obstacle_share},
        {"false_alarm_by_size_", "false-alarm area / known area",
         "False-alarm fraction of the known area by layer and obstacle radius, " + map_name, 0.2,
         &LayerRow::false_alarm_fraction},
    };
    for (const SizeTable& st : tables) {
      HeatMap hm;
      hm.title = std::string(st.title) + ", " + map_name;
      hm.row_label = "layer (h_min)";
      hm.col_label = "obstacle radius = height [cm]";
      hm.cols = cols;
      hm.max_value = st.max_value;
      std::vector<std::string> header = {"layer", "h_min [cm]"};
      for (const auto& c : cols) header.push_back(c + " cm");
      std::vector<std::vector<std::string>> rows;
      for (const std::string& layer : g.layers) {
        const LayerRow& info = g.layer_info.at(layer);
        hm.rows.push_back(layer_label(info) + " (" + fmt(info.h_min_m * 100, "%g") + ")");
        std::vector<double> values;
        std::vector<std::string> row = {layer_label(info), fmt(info.h_min_m * 100, "%g")};
        for (double r : g.keys) {
          const double v = cell_value(g, layer, r, st.metric);
          values.push_back(v);
          row.push_back(fmt(v, "%.2f"));
        }
        hm.values.push_back(values);
        rows.push_back(row);
      }
      const std::string stem = st.stem + map_name;
      write_png(out_dir / (stem + ".png"), plot_heatmap(hm));
      write_file_atomically(out_dir / (stem + ".csv"), csv_table(header, rows));
      md << "### " << st.caption << "\n\n" << md_table(header, rows) << "\n![" << stem << "]("
         << stem << ".png)\n\n";
      HtmlSection sec;
      sec.heading = st.caption;
      sec.tables.push_back({stem, "", header, rows, {}});
      sec.figures.push_back({stem + ".png", st.caption});
      page.sections.push_back(sec);
    }
    // Smallest radius from which every larger swept radius is detected.
    for (const std::string& layer : g.layers) {
      const LayerRow& info = g.layer_info.at(layer);
      double smallest = kNaN;
      for (auto it = g.keys.rbegin(); it != g.keys.rend(); ++it) {
        const double v = cell_value(g, layer, *it, &LayerRow::missed_of_hazard);
        if (!(v <= kDetectedMissedFraction)) break;
        smallest = *it;
      }
      detect_rows.push_back({map_name, layer_label(info) + " " + info.rule,
                             fmt(info.h_min_m * 100, "%g"),
                             std::isfinite(smallest) ? fmt(smallest * 100, "%g") : "none swept"});
    }
  }
  if (!detect_rows.empty()) {
    const std::vector<std::string> header = {"map", "layer", "design h_min [cm]",
                                             "detected from radius [cm]"};
    write_file_atomically(out_dir / "detectable_size.csv", csv_table(header, detect_rows));
    const std::string caption =
        "Detectable obstacle size per layer: the smallest swept radius from which every larger "
        "one has at most " + fmt(kDetectedMissedFraction * 100, "%g") + " % of its known area missed";
    md << "### " << caption << "\n\n" << md_table(header, detect_rows) << '\n';
    HtmlSection s;
    s.heading = "Detectable obstacle size per layer";
    s.text = caption;
    s.tables.push_back({"detectable", "", header, detect_rows, {}});
    page.sections.push_back(s);
  }
}

/// Height precision on the craters scenario: RMS by cell size, CCM at 2r against PWC at r.
void add_craters_section(const std::map<std::string, Grid2>& craters, const fs::path& out_dir,
                         std::ostringstream& md, HtmlPage& page) {
  if (!craters.empty()) {
    LineChart chart;
    chart.title = "height RMS by cell size (craters scenario)";
    chart.x_label = "cell size [cm]";
    chart.y_label = "RMS [cm]";
    chart.log2_x = true;
    std::vector<std::vector<std::string>> rows;
    std::map<std::string, std::map<double, double>> rms_by_res;  // map -> res -> rms
    for (const auto& [map_name, g] : craters) {
      Series s;
      s.name = map_name;
      for (const std::string& layer : g.layers) {
        const LayerRow& info = g.layer_info.at(layer);
        if (info.rule == "fused" || info.rule == "footprint") continue;  // no heights
        const double rms = cell_value(g, layer, 0.0, &LayerRow::rms);
        const double unknown = cell_value(g, layer, 0.0, &LayerRow::unknown_fraction);
        rows.push_back({map_name, layer_label(info) + " " + info.rule, fmt(rms * 100, "%.3f"),
                        fmt(unknown * 100, "%.1f")});
        s.x.push_back(info.resolution_m * 100);
        s.y.push_back(rms * 100);
        rms_by_res[map_name][info.resolution_m] = rms;
      }
      chart.series.push_back(s);
    }
    const std::vector<std::string> header = {"map", "layer", "height RMS [cm]", "unknown [%]"};
    write_file_atomically(out_dir / "craters_rms.csv", csv_table(header, rows));
    write_png(out_dir / "craters_rms.png", plot_lines(chart));
    md << "### Height RMS by layer, craters scenario\n\n" << md_table(header, rows)
       << "\n![craters_rms](craters_rms.png)\n\n";
    HtmlSection s;
    s.heading = "Height precision by layer (craters scenario)";
    s.tables.push_back({"craters_rms", "", header, rows, {}});
    s.figures.push_back({"craters_rms.png", "height RMS against cell size"});
    // The thesis' claim: CCM at 2r at least as precise as piecewise constant at r.
    std::vector<std::vector<std::string>> claim;
    for (const auto& [pwc_name, pwc] : rms_by_res)
      for (const auto& [ccm_name, ccm] : rms_by_res) {
        if (pwc_name == ccm_name || ccm_name.find("ccm") == std::string::npos ||
            pwc_name.find("ccm") != std::string::npos)
          continue;
        for (const auto& [r, rms_pwc] : pwc) {
          const auto it = std::find_if(ccm.begin(), ccm.end(), [&](const auto& kv) {
            return std::abs(kv.first - 2 * r) < 1e-9;
          });
          if (it == ccm.end()) continue;
          claim.push_back({fmt(r * 100, "%g") + " cm " + pwc_name, fmt(rms_pwc * 100, "%.3f"),
                           fmt(2 * r * 100, "%g") + " cm " + ccm_name,
                           fmt(it->second * 100, "%.3f"),
                           it->second <= rms_pwc ? "yes" : "NO (worse)"});
        }
      }
    if (!claim.empty()) {
      const std::vector<std::string> h = {"piecewise constant at r", "RMS [cm]", "CCM at 2r",
                                          "RMS [cm]", "CCM(2r) <= PWC(r)"};
      md << "### CCM at 2r against piecewise constant at r\n\n" << md_table(h, claim) << '\n';
      s.tables.push_back({"ccm_vs_pwc", "CCM at 2r against piecewise constant at r", h, claim, {}});
    }
    page.sections.push_back(s);
  }
}

/// Pose drift on the sine scenario: missed obstacles and false alarms (drift.csv, plots).
void add_drift_section(const std::map<std::string, Grid2>& drift, const fs::path& out_dir,
                       std::ostringstream& md, HtmlPage& page) {
  if (!drift.empty()) {
    std::vector<std::vector<std::string>> rows;
    for (const auto& [map_name, g] : drift) {
      LineChart missed_chart, fa_chart;
      missed_chart.title = "missed obstacle fraction vs pose drift, " + map_name;
      fa_chart.title = "false-alarm fraction vs pose drift, " + map_name;
      for (LineChart* c : {&missed_chart, &fa_chart}) {
        c->x_label = "drift [% of distance travelled]";
        c->y_label = "%";
        for (double d : g.keys) c->x_ticks.push_back(d * 100);
      }
      for (const std::string& layer : g.layers) {
        const LayerRow& info = g.layer_info.at(layer);
        Series sm, sf;
        sm.name = sf.name = layer_label(info);
        std::vector<std::string> row_m = {map_name, layer_label(info) + " missed [%]"};
        std::vector<std::string> row_f = {map_name, layer_label(info) + " false alarm [%]"};
        for (double d : g.keys) {
          const double m = cell_value(g, layer, d, &LayerRow::missed_of_hazard);
          const double f = cell_value(g, layer, d, &LayerRow::false_alarm_fraction);
          sm.x.push_back(d * 100);
          sm.y.push_back(m * 100);
          sf.x.push_back(d * 100);
          sf.y.push_back(f * 100);
          row_m.push_back(fmt(m * 100, "%.1f"));
          row_f.push_back(fmt(f * 100, "%.2f"));
        }
        missed_chart.series.push_back(sm);
        fa_chart.series.push_back(sf);
        rows.push_back(row_m);
        rows.push_back(row_f);
      }
      write_png(out_dir / ("drift_missed_" + map_name + ".png"), plot_lines(missed_chart));
      write_png(out_dir / ("drift_false_alarm_" + map_name + ".png"), plot_lines(fa_chart));
    }
    // Column headers name the drift values of the first map (all drift maps share them).
    std::vector<std::string> h = {"map", "layer: metric"};
    for (double d : drift.begin()->second.keys) h.push_back(fmt(d * 100, "%g") + " % drift");
    write_file_atomically(out_dir / "drift.csv", csv_table(h, rows));
    md << "### Missed obstacles and false alarms against pose drift (sine scenario)\n\n"
       << md_table(h, rows) << '\n';
    HtmlSection s;
    s.heading = "Pose drift (sine scenario)";
    s.text = "Map built on poses that drift by the given fraction of the distance travelled; "
             "scored against the ground truth placed with the true poses.";
    s.tables.push_back({"drift", "", h, rows, {}});
    for (const auto& [map_name, g] : drift) {
      s.figures.push_back({"drift_missed_" + map_name + ".png", "missed obstacles, " + map_name});
      s.figures.push_back({"drift_false_alarm_" + map_name + ".png", "false alarms, " + map_name});
    }
    page.sections.push_back(s);
  }
}

}  // namespace

std::vector<SweepEntry> read_sweep_manifest(const fs::path& sweep_dir) {
  const fs::path path = sweep_dir / "sweep.tsv";
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": missing (write it with tools/sweep.sh)");
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line, '\t');
  const std::vector<std::string> expected = {"experiment", "map", "scenario", "radius_m", "drift",
                                             "run_dir"};
  if (header != expected)
    throw Error(path.string() + ":1: header must be 'experiment map scenario radius_m drift "
                                "run_dir' (tab-separated)");
  std::vector<SweepEntry> entries;
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> f = split(line, '\t');
    if (f.size() != expected.size())
      throw Error(path.string() + ":" + std::to_string(line_no) + ": expected 6 tab-separated fields");
    SweepEntry e;
    e.experiment = f[0];
    e.map = f[1];
    e.scenario = f[2];
    e.radius_m = number_or_nan(f[3]);
    e.drift = number_or_nan(f[4]);
    e.run_dir = fs::path(f[5]).is_absolute() ? fs::path(f[5]) : sweep_dir / f[5];
    entries.push_back(e);
  }
  return entries;
}

int summarize_sweep(const fs::path& sweep_dir, const fs::path& out_dir) {
  const std::vector<SweepEntry> entries = read_sweep_manifest(sweep_dir);
  fs::create_directories(out_dir);
  std::map<std::string, Grid2> sizes;    // per map, key radius
  std::map<std::string, Grid2> craters;  // per map, key 0
  std::map<std::string, Grid2> drift;    // per map, key drift
  std::vector<std::vector<std::string>> run_rows;
  int evaluated = 0;
  for (const SweepEntry& e : entries) {
    const fs::path csv = e.run_dir / run_layout::kEvalDir / "summary.csv";
    const std::string rel_report =
        fs::relative(e.run_dir / run_layout::kEvalDir / "report.html", out_dir).generic_string();
    if (!fs::exists(csv)) {
      spdlog::warn("sweep: {} has no evaluation; left out", e.run_dir.string());
      run_rows.push_back({e.experiment, e.map, e.scenario, fmt(e.radius_m * 100, "%g"),
                          fmt(e.drift * 100, "%g"), "missing"});
      continue;
    }
    const std::vector<LayerRow> rows = read_run_summary(csv);
    ++evaluated;
    run_rows.push_back({e.experiment, e.map, e.scenario, fmt(e.radius_m * 100, "%g"),
                        fmt(e.drift * 100, "%g"), rel_report});
    if (e.experiment == "sizes") add_run(sizes[e.map], e.radius_m, rows);
    else if (e.experiment == "craters") add_run(craters[e.map], 0.0, rows);
    else if (e.experiment == "drift") add_run(drift[e.map], e.drift, rows);
    else spdlog::warn("sweep: unknown experiment '{}' in sweep.tsv", e.experiment);
  }
  if (evaluated == 0) throw Error((sweep_dir / "sweep.tsv").string() + ": no run has an evaluation");

  std::ostringstream md;
  HtmlPage page;
  page.title = "hazmap sweep: " + sweep_dir.lexically_normal().parent_path().filename().string();
  if (sweep_dir.lexically_normal().filename() != "")
    page.title = "hazmap sweep: " + sweep_dir.lexically_normal().filename().string();
  page.subtitle = std::to_string(evaluated) + " evaluated runs from " + sweep_dir.string() +
                  ". Fractions pooled over every written frame of a run.";

  add_sizes_section(sizes, out_dir, md, page);
  add_craters_section(craters, out_dir, md, page);
  add_drift_section(drift, out_dir, md, page);

  HtmlSection runs;
  runs.heading = "Runs";
  runs.tables.push_back({"runs", "", {"experiment", "map", "scenario", "radius [cm]", "drift [%]",
                                      "report"}, run_rows, {5}});
  page.sections.push_back(runs);
  write_file_atomically(out_dir / "tables.md", md.str());
  write_file_atomically(out_dir / "report.html", render_html(page));
  return evaluated;
}

}  // namespace hazmap::eval
