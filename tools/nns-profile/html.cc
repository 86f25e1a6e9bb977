// SPDX-License-Identifier: LGPL-2.1-only
// nns-profile's HTML report: one self-contained page (inline CSS, SVG and a small script, no
// network): the pipeline graph with elements coloured by busy share and links labelled with
// rates and latencies, the table, and a latency histogram per element.
#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

#include "profile/hist.h"
#include "report.h"

namespace nns::profile::report {

namespace {

std::string esc(const std::string &s) {
  std::string o;
  for (char c : s) switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      case '\'':
        o += "&#39;";
        break;
      default:
        o += c;
    }
  return o;
}

std::string num(double v, const char *f = "%.1f") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// Green (idle) to red (saturated).
std::string busy_colour(double busy) {
  const double b = std::clamp(busy, 0.0, 1.0);
  return "hsl(" + num(120 * (1 - b), "%.0f") + ",70%,62%)";
}

std::string hist_svg(const std::vector<std::pair<int64_t, uint64_t>> &h, const std::string &label) {
  if (h.empty()) return "";
  const int k0 = hist_bucket(h.front().first), k1 = hist_bucket(h.back().first);
  const int n = k1 - k0 + 1;
  std::map<int, uint64_t> counts;
  uint64_t top = 1;
  for (const auto &[lo, c] : h) {
    counts[hist_bucket(lo)] = c;
    top = std::max(top, c);
  }
  const int W = 360, H = 90, bw = std::max(2, (W - 20) / std::max(n, 1));
  std::ostringstream o;
  o << "<figure class=\"hist\"><figcaption>" << esc(label) << "</figcaption><svg width=\"" << W
    << "\" height=\"" << H + 20 << "\" role=\"img\">";
  for (int k = k0; k <= k1; ++k) {
    const uint64_t c = counts.count(k) ? counts[k] : 0;
    const double bh = static_cast<double>(c) * (H - 5) / static_cast<double>(top);
    o << "<rect x=\"" << 10 + (k - k0) * bw << "\" y=\"" << num(H - bh) << "\" width=\"" << bw - 1
      << "\" height=\"" << num(bh) << "\"><title>" << fmt_ns(hist_lower(k)) << " - "
      << fmt_ns(hist_lower(k + 1)) << ": " << c << "</title></rect>";
  }
  o << "<text x=\"10\" y=\"" << H + 15 << "\">" << fmt_ns(hist_lower(k0)) << "</text>";
  o << "<text x=\"" << 10 + n * bw << "\" y=\"" << H + 15 << "\" text-anchor=\"end\">"
    << fmt_ns(hist_lower(k1 + 1)) << "</text></svg></figure>";
  return o.str();
}

}  // namespace

std::string html_page(const Report &r) {
  // Graph layout: column = longest path from a source, row = order within the column.
  std::map<int, int> col, row;
  for (const auto &e : r.elements) col[e.id] = 0;
  for (std::size_t pass = 0; pass < r.elements.size(); ++pass)
    for (const auto &k : r.links)
      if (col.count(k.from) && col.count(k.to) && col[k.to] < col[k.from] + 1 &&
          col[k.from] + 1 < static_cast<int>(r.elements.size()))
        col[k.to] = col[k.from] + 1;
  std::map<int, int> used;
  std::vector<const Element *> order;
  for (const auto &e : r.elements) order.push_back(&e);
  std::stable_sort(order.begin(), order.end(),
                   [](const Element *a, const Element *b) { return a->id < b->id; });
  int max_col = 0, max_row = 0;
  for (const Element *e : order) {
    row[e->id] = used[col[e->id]]++;
    max_col = std::max(max_col, col[e->id]);
    max_row = std::max(max_row, row[e->id]);
  }
  const int BW = 170, BH = 58, GX = 90, GY = 40;
  auto X = [&](int id) { return 20 + col[id] * (BW + GX); };
  auto Y = [&](int id) { return 20 + row[id] * (BH + GY); };
  const int W = 40 + (max_col + 1) * (BW + GX), H = 40 + (max_row + 1) * (BH + GY);

  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
    << "<title>nns-profile report</title><style>"
    << "body{font-family:sans-serif;margin:20px;color:#222}"
    << "table{border-collapse:collapse;margin:10px 0}td,th{border:1px solid #bbb;padding:3px 8px;"
    << "text-align:right}td:first-child,th:first-child{text-align:left}th{background:#eee;"
    << "cursor:pointer}.element rect{stroke:#333}.element text{font-size:12px}"
    << ".edge line{stroke:#555;stroke-width:1.5}.edge text{font-size:11px;fill:#124}"
    << ".hist rect{fill:#4a7bd0}.hist text{font-size:10px}figure.hist{display:inline-block;"
    << "margin:8px}.bottleneck{font-weight:bold;color:#a00}</style></head><body>\n";
  o << "<h1>nns-profile report</h1><p><code>" << esc(r.title) << "</code></p>\n";
  o << "<p>Run: " << fmt_ns(static_cast<double>(r.duration_ns)) << ", " << r.elements.size()
    << " elements.</p><p class=\"bottleneck\" id=\"bottleneck\">" << esc(r.bottleneck_text)
    << "</p>\n";

  o << "<h2>Pipeline</h2><svg id=\"graph\" width=\"" << W << "\" height=\"" << H
    << "\" xmlns=\"http://www.w3.org/2000/svg\"><defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" "
       "refX=\"10\" refY=\"5\" markerWidth=\"7\" markerHeight=\"7\" orient=\"auto\"><path d=\"M0,0"
       "L10,5L0,10z\" fill=\"#555\"/></marker></defs>\n";
  for (const auto &k : r.links) {
    if (!col.count(k.from) || !col.count(k.to)) continue;
    const int x1 = X(k.from) + BW, y1 = Y(k.from) + BH / 2, x2 = X(k.to), y2 = Y(k.to) + BH / 2;
    std::string label = num(k.rate, k.rate >= 100 ? "%.0f" : "%.1f") + "/s";
    if (k.latency_count) label += ", " + fmt_ns(k.latency_mean_ns);
    o << "<g class=\"edge\"><line x1=\"" << x1 << "\" y1=\"" << y1 << "\" x2=\"" << x2 << "\" y2=\""
      << y2 << "\" marker-end=\"url(#arrow)\"/><text x=\"" << (x1 + x2) / 2 << "\" y=\""
      << (y1 + y2) / 2 - 6 << "\" text-anchor=\"middle\">" << esc(label) << "</text><title>"
      << esc(k.from_pad + " -> " + k.to_pad) << ": " << k.buffers << " buffers</title></g>\n";
  }
  for (const auto &e : r.elements) {
    o << "<g class=\"element\" data-name=\"" << esc(e.name) << "\"><rect x=\"" << X(e.id)
      << "\" y=\"" << Y(e.id) << "\" width=\"" << BW << "\" height=\"" << BH
      << "\" rx=\"6\" fill=\"" << (e.kind == "queue" ? std::string("#ddd") : busy_colour(e.busy))
      << "\"/>"
      << "<text x=\"" << X(e.id) + 8 << "\" y=\"" << Y(e.id) + 18 << "\" font-weight=\"bold\">"
      << esc(e.name) << "</text><text x=\"" << X(e.id) + 8 << "\" y=\"" << Y(e.id) + 34 << "\">"
      << esc(e.factory) << "</text><text x=\"" << X(e.id) + 8 << "\" y=\"" << Y(e.id) + 50 << "\">"
      << (e.kind == "queue" ? std::string("queue (waits)")
                            : "busy " + num(e.busy * 100) + "%, " + fmt_ns(e.per_buffer_ns))
      << "</text></g>\n";
  }
  o << "</svg>\n";

  o << "<h2>Elements</h2><table id=\"elements\"><thead><tr><th>element</th><th>factory</th>"
       "<th>kind</th><th>buffers</th><th>busy %</th><th>share %</th><th>per buffer</th>"
       "<th>p50</th><th>p99</th><th>max</th><th>invoke</th><th>in/s</th><th>out/s</th></tr>"
       "</thead><tbody>\n";
  for (const auto &e : r.elements)
    o << "<tr class=\"element-row\"><td>" << esc(e.name) << "</td><td>" << esc(e.factory)
      << "</td><td>" << esc(e.kind) << "</td><td>" << e.buffers << "</td><td>"
      << (e.kind == "queue" ? std::string("wait") : num(e.busy * 100)) << "</td><td>"
      << num(e.share * 100) << "</td><td data-v=\"" << num(e.per_buffer_ns, "%.0f") << "\">"
      << fmt_ns(e.per_buffer_ns) << "</td><td>" << fmt_ns(static_cast<double>(e.q.p50))
      << "</td><td>" << fmt_ns(static_cast<double>(e.q.p99)) << "</td><td>"
      << fmt_ns(static_cast<double>(e.max_ns)) << "</td><td>"
      << (e.invokes ? fmt_ns(e.invoke_mean_ns) : std::string("-")) << "</td><td>" << num(e.in_rate)
      << "</td><td>" << num(e.out_rate) << "</td></tr>\n";
  o << "</tbody></table>\n";

  std::map<int, std::string> names;
  for (const auto &e : r.elements) names[e.id] = e.name;
  o << "<h2>Links</h2><table id=\"links\"><thead><tr><th>from</th><th>to</th><th>buffers</th>"
       "<th>rate</th><th>bytes/s</th><th>latency mean</th><th>p99</th><th>max</th></tr></thead>"
       "<tbody>\n";
  for (const auto &k : r.links)
    o << "<tr><td>" << esc(k.from_pad) << "</td><td>" << esc(k.to_pad) << "</td><td>" << k.buffers
      << "</td><td>" << num(k.rate) << "</td><td>" << num(k.bytes_rate, "%.0f") << "</td><td>"
      << fmt_ns(k.latency_mean_ns) << "</td><td>" << fmt_ns(static_cast<double>(k.latency_q.p99))
      << "</td><td>" << fmt_ns(static_cast<double>(k.latency_max_ns)) << "</td></tr>\n";
  o << "</tbody></table>\n";

  if (!r.threads.empty()) {
    o << "<h2>Streaming threads</h2><table id=\"threads\"><thead><tr><th>thread</th><th>tid</th>"
         "<th>starts at</th><th>CPU</th><th>wall</th><th>CPU %</th></tr></thead><tbody>\n";
    for (const auto &t : r.threads)
      o << "<tr><td>" << esc(t.name) << "</td><td>" << t.tid << "</td><td>" << esc(t.root)
        << "</td><td>" << fmt_ns(static_cast<double>(t.cpu_ns)) << "</td><td>"
        << fmt_ns(static_cast<double>(t.wall_ns)) << "</td><td>" << num(t.cpu_share * 100)
        << "</td></tr>\n";
    o << "</tbody></table>\n";
  }

  o << "<h2>Time per buffer</h2>\n";
  for (const auto &e : r.elements) {
    o << hist_svg(e.hist, e.name + ": own time per buffer");
    o << hist_svg(e.invoke_hist, e.name + ": invoke time");
  }
  for (const auto &k : r.links)
    if (k.to_sink && k.latency_count)
      o << "<p>End-to-end latency to " << esc(names[k.to]) << ": mean " << fmt_ns(k.latency_mean_ns)
        << ", p99 " << fmt_ns(static_cast<double>(k.latency_q.p99)) << ", max "
        << fmt_ns(static_cast<double>(k.latency_max_ns)) << "</p>\n";

  // Click a column header to sort its table.
  o << "<script>\n"
       "document.querySelectorAll('th').forEach(function (th, i) {\n"
       "  th.addEventListener('click', function () {\n"
       "    var tb = th.closest('table').tBodies[0];\n"
       "    var col = th.cellIndex;\n"
       "    var rows = Array.prototype.slice.call(tb.rows);\n"
       "    var key = function (r) { var c = r.cells[col]; var v = c.dataset.v || c.textContent;"
       " var n = parseFloat(v); return isNaN(n) ? v : n; };\n"
       "    rows.sort(function (a, b) { var x = key(a), y = key(b);"
       " return x < y ? 1 : x > y ? -1 : 0; });\n"
       "    rows.forEach(function (r) { tb.appendChild(r); });\n"
       "  });\n"
       "});\n"
       "console.log('nns-profile report: ' + document.querySelectorAll('g.element').length +"
       " ' elements');\n"
       "</script>\n</body></html>\n";
  return o.str();
}

}  // namespace nns::profile::report
