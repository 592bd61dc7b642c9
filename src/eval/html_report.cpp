#include "hazmap/eval/html_report.hpp"

#include <algorithm>
#include <sstream>

namespace hazmap::eval {

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

// Inside a <script> block only "</" could end it early; JSON-like string literals
// escape it.
std::string js_string(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '<') {
      out += "\\u003c";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

const char* kStyle = R"(
body { font-family: system-ui, sans-serif; margin: 24px auto; max-width: 1180px; color: #222; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
h2 { font-size: 1.2em; margin-top: 1.6em; border-bottom: 1px solid #ddd; }
.subtitle { color: #555; margin-top: 0; }
table { border-collapse: collapse; margin: 0.6em 0 1em 0; font-size: 0.9em; }
caption { text-align: left; font-weight: 600; padding: 4px 0; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: right; }
th { background: #f0f0f0; }
td:first-child, th:first-child { text-align: left; }
figure { display: inline-block; margin: 0 12px 12px 0; vertical-align: top; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.85em; color: #555; }
#viewer img { max-width: 100%; border: 1px solid #ddd; display: block; margin-top: 6px; }
#viewer input[type=range] { width: 60%; vertical-align: middle; }
)";

const char* kViewerScript = R"(
(function () {
  var img = document.getElementById('viewer-image');
  var label = document.getElementById('viewer-label');
  var slider = document.getElementById('viewer-slider');
  function show(i) {
    i = Math.max(0, Math.min(frames.length - 1, i));
    slider.value = i;
    img.src = frames[i];
    label.textContent = labels[i] + '  (' + (i + 1) + ' / ' + frames.length + ')';
  }
  slider.addEventListener('input', function () { show(parseInt(slider.value, 10)); });
  document.getElementById('viewer-prev').addEventListener('click', function () { show(parseInt(slider.value, 10) - 1); });
  document.getElementById('viewer-next').addEventListener('click', function () { show(parseInt(slider.value, 10) + 1); });
  document.addEventListener('keydown', function (e) {
    if (e.key === 'ArrowLeft') show(parseInt(slider.value, 10) - 1);
    if (e.key === 'ArrowRight') show(parseInt(slider.value, 10) + 1);
  });
  show(frames.length - 1);
})();
)";

}  // namespace

const char* report_style() { return kStyle; }

std::string script_safe(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    out += text[i];
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') out += '\\';
  }
  return out;
}

std::string render_table(const HtmlTable& t) {
  std::ostringstream o;
  o << "<table" << (t.id.empty() ? "" : " id=\"" + html_escape(t.id) + "\"") << ">\n";
  if (!t.caption.empty()) o << "<caption>" << html_escape(t.caption) << "</caption>\n";
  o << "<thead><tr>";
  for (const auto& h : t.header) o << "<th>" << html_escape(h) << "</th>";
  o << "</tr></thead>\n<tbody>\n";
  for (const auto& row : t.rows) {
    o << "<tr>";
    for (size_t c = 0; c < row.size(); ++c) {
      const bool link =
          std::find(t.link_columns.begin(), t.link_columns.end(), c) != t.link_columns.end();
      if (link && row[c].size() > 5 && row[c].substr(row[c].size() - 5) == ".html")
        o << "<td><a href=\"" << html_escape(row[c]) << "\">" << html_escape(row[c]) << "</a></td>";
      else
        o << "<td>" << html_escape(row[c]) << "</td>";
    }
    o << "</tr>\n";
  }
  o << "</tbody>\n</table>\n";
  return o.str();
}

std::string render_html(const HtmlPage& page) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
    << "<title>" << html_escape(page.title) << "</title>\n<style>" << kStyle << "</style>\n"
    << "</head>\n<body>\n<h1>" << html_escape(page.title) << "</h1>\n";
  if (!page.subtitle.empty()) o << "<p class=\"subtitle\">" << html_escape(page.subtitle) << "</p>\n";
  for (const HtmlSection& s : page.sections) {
    o << "<h2>" << html_escape(s.heading) << "</h2>\n";
    if (!s.text.empty()) o << "<p>" << html_escape(s.text) << "</p>\n";
    for (const HtmlTable& t : s.tables) o << render_table(t);
    for (const HtmlFigure& f : s.figures)
      o << "<figure><a href=\"" << html_escape(f.src) << "\"><img src=\"" << html_escape(f.src)
        << "\" alt=\"" << html_escape(f.caption) << "\"></a><figcaption>"
        << html_escape(f.caption) << "</figcaption></figure>\n";
  }
  if (!page.viewer_images.empty()) {
    o << "<h2>" << html_escape(page.viewer_heading) << "</h2>\n<div id=\"viewer\">\n"
      << "<button id=\"viewer-prev\">&larr;</button> <input id=\"viewer-slider\" type=\"range\" "
         "min=\"0\" max=\""
      << page.viewer_images.size() - 1 << "\" value=\"0\"> <button id=\"viewer-next\">&rarr;"
      << "</button> <span id=\"viewer-label\"></span>\n"
      << "<img id=\"viewer-image\" alt=\"frame\" src=\"" << html_escape(page.viewer_images.back())
      << "\">\n</div>\n<script>\nvar frames = [";
    for (size_t i = 0; i < page.viewer_images.size(); ++i)
      o << (i ? ", " : "") << js_string(page.viewer_images[i]);
    o << "];\nvar labels = [";
    for (size_t i = 0; i < page.viewer_images.size(); ++i)
      o << (i ? ", " : "")
        << js_string(i < page.viewer_labels.size() ? page.viewer_labels[i] : page.viewer_images[i]);
    o << "];\n" << kViewerScript << "</script>\n";
  }
  o << "</body>\n</html>\n";
  return o.str();
}

}  // namespace hazmap::eval
