#pragma once
// Static HTML pages for people to look at a run's or a sweep's evaluation: no server,
// no network, no external script or style sheet; images by relative path, so a report
// folder can be copied or zipped together with the run. Opens from file:// in any
// browser.

#include <string>
#include <vector>

namespace hazmap::eval {

/// A table: header cells and rows of already formatted cells (escaped when written).
struct HtmlTable {
  std::string id;       ///< element id, e.g. "summary"
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  /// Columns whose cells are relative links (shown as their text).
  std::vector<size_t> link_columns;
};

/// A figure: image path relative to the page, and a caption.
struct HtmlFigure {
  std::string src;
  std::string caption;
};

/// A page section: heading, a paragraph, then tables and figures.
struct HtmlSection {
  std::string heading;
  std::string text;
  std::vector<HtmlTable> tables;
  std::vector<HtmlFigure> figures;
};

struct HtmlPage {
  std::string title;
  std::string subtitle;  ///< one line under the title (run, sequence, ...)
  std::vector<HtmlSection> sections;
  /// Frame viewer: image paths relative to the page and their labels; empty: none.
  /// A slider, previous/next buttons and the arrow keys flip through them.
  std::vector<std::string> viewer_images;
  std::vector<std::string> viewer_labels;
  std::string viewer_heading = "Frame by frame";
};

/// Escapes &, <, >, " and '.
std::string html_escape(const std::string& text);

/// The whole page as one self-contained HTML document.
std::string render_html(const HtmlPage& page);

/// One table as render_html writes it (<table id=...>, caption, header, rows).
std::string render_table(const HtmlTable& table);

/// The pages' style sheet (the CSS inside <style>), shared by every hazmap page so that
/// they look alike.
const char* report_style();

/// `text` made safe inside a <script> element: every "</" becomes "<\/", which JSON and
/// JavaScript string literals read back as "</" (only "</script" could end the element).
std::string script_safe(const std::string& text);

}  // namespace hazmap::eval
