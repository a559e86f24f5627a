// robophi sweep's plan, runs and tables (docs/sweep.md).
#include "sweep.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "robotics/tasks.h"
#include "run/interrupt.h"
#include "run/runner.h"

namespace robophi::cli {

namespace {

// Splits at commas outside brackets, braces and quotes.
std::vector<std::string> splitValues(const std::string& text) {
  std::vector<std::string> parts;
  std::string current;
  int depth = 0;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '\\' && i + 1 < text.size()) {
        current += c;
        current += text[++i];
        continue;
      }
      if (c == '"') quoted = false;
    } else if (c == '"') {
      quoted = true;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if (c == ']' || c == '}') {
      --depth;
    } else if (c == ',' && depth == 0) {
      parts.push_back(current);
      current.clear();
      continue;
    }
    current += c;
  }
  parts.push_back(current);
  return parts;
}

// SplitMix64: a counter-based generator (the value depends on the counter only).
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Uniform in [-1, 1) for (seed, particle, axis).
double uniformSigned(int seed, std::int64_t particle, int axis) {
  const std::uint64_t counter = mix(mix(static_cast<std::uint64_t>(seed)) ^
                                    (static_cast<std::uint64_t>(particle) * 4 + axis));
  return static_cast<double>(counter >> 11) * 0x1.0p-52 - 1.0;
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// A cell: strings as they are, numbers at full precision, the rest as JSON.
std::string cellText(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  // The shortest text that reads back as the same double: 0.1 as typed, not
  // 0.10000000000000001.
  if (v.is_number_float()) return fmt::format("{}", v.get<double>());
  return v.dump();
}

// The table's columns: the fixed ones first, then the outcomes (sorted).
std::vector<std::string> columns(const SweepPlan& plan, const std::vector<nlohmann::json>& rows) {
  std::vector<std::string> names = {"run"};
  for (const SweepParameter& p : plan.parameters) names.push_back(p.pointer);
  for (const char* fixed :
       {"seed", "status", "steps", "simulated_time", "energy_drift", "largest_account_error",
        "dissipated", "external_work", "state_hash", "failure"})
    names.emplace_back(fixed);
  std::set<std::string> outcomes, ends;
  for (const nlohmann::json& row : rows) {
    for (const auto& [key, value] : row.items()) {
      if (key.starts_with("outcomes/")) outcomes.insert(key);
      if (key.starts_with("end/")) ends.insert(key);
    }
  }
  names.insert(names.end(), outcomes.begin(), outcomes.end());
  names.insert(names.end(), ends.begin(), ends.end());
  return names;
}

std::string escapeHtml(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// One scatter plot (SVG) of `y` against `x`, with the mean over equal x as a line.
std::string scatterSvg(const std::string& xName, const std::string& yName,
                       const std::vector<std::pair<double, double>>& points) {
  constexpr double kW = 360, kH = 230, kLeft = 64, kRight = 12, kTop = 12, kBottom = 40;
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& [x, y] : points) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  if (!(x1 > x0)) x0 -= 0.5, x1 += 0.5;
  if (!(y1 > y0)) {
    const double pad = std::max(std::abs(y0) * 0.05, 1e-12);
    y0 -= pad, y1 += pad;
  }
  const auto sx = [&](double x) { return kLeft + (x - x0) / (x1 - x0) * (kW - kLeft - kRight); };
  const auto sy = [&](double y) {
    return kH - kBottom - (y - y0) / (y1 - y0) * (kH - kTop - kBottom);
  };
  std::string svg = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{0}' height='{1}' viewBox='0 0 {0} {1}'>"
      "<rect x='{2}' y='{3}' width='{4}' height='{5}' fill='none' stroke='#999'/>",
      kW, kH, kLeft, kTop, kW - kLeft - kRight, kH - kTop - kBottom);
  for (int k = 0; k <= 4; ++k) {
    const double xv = x0 + (x1 - x0) * k / 4.0, yv = y0 + (y1 - y0) * k / 4.0;
    svg +=
        fmt::format("<text x='{:.1f}' y='{:.1f}' font-size='10' text-anchor='middle'>{:.4g}</text>",
                    sx(xv), kH - kBottom + 13, xv);
    svg += fmt::format("<text x='{:.1f}' y='{:.1f}' font-size='10' text-anchor='end'>{:.4g}</text>",
                       kLeft - 4, sy(yv) + 3, yv);
  }
  svg += fmt::format("<text x='{:.1f}' y='{:.1f}' font-size='11' text-anchor='middle'>{}</text>",
                     kLeft + (kW - kLeft - kRight) / 2, kH - 6, escapeHtml(xName));
  std::map<double, std::pair<double, int>> means;
  for (const auto& [x, y] : points) {
    svg += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='3' fill='#1f77b4' fill-opacity='0.7'/>",
                       sx(x), sy(y));
    auto& m = means[x];
    m.first += y;
    ++m.second;
  }
  if (means.size() > 1) {
    std::string path;
    for (const auto& [x, m] : means)
      path +=
          fmt::format("{}{:.1f},{:.1f}", path.empty() ? "M" : " L", sx(x), sy(m.first / m.second));
    svg += fmt::format("<path d='{}' fill='none' stroke='#d62728'/>", path);
  }
  return svg +
         fmt::format("<title>{} against {}</title></svg>", escapeHtml(yName), escapeHtml(xName));
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw std::runtime_error(fmt::format("cannot write {}", path));
}

}  // namespace

SweepParameter parseSweepParameter(const std::string& option) {
  const std::size_t eq = option.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument(
        fmt::format("--set '{}': expected POINTER=V1,V2,... (a JSON pointer into the scene, e.g. "
                    "/materials/0/staticFriction=0.3,0.5)",
                    option));
  SweepParameter p;
  p.pointer = option.substr(0, eq);
  if (p.pointer.front() != '/')
    throw std::invalid_argument(
        fmt::format("--set '{}': the pointer '{}' must start with '/' (a JSON pointer, RFC 6901)",
                    option, p.pointer));
  try {
    (void)nlohmann::json::json_pointer(p.pointer);
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(fmt::format("--set '{}': bad JSON pointer: {}", option, e.what()));
  }
  const std::string values = option.substr(eq + 1);
  for (const std::string& text : splitValues(values)) {
    if (text.empty())
      throw std::invalid_argument(fmt::format("--set '{}': an empty value", option));
    nlohmann::json v = nlohmann::json::parse(text, nullptr, false);
    p.values.push_back(v.is_discarded() ? nlohmann::json(text) : v);
  }
  return p;
}

std::vector<SweepCase> sweepCases(const SweepPlan& plan) {
  std::vector<SweepCase> cases;
  std::vector<std::size_t> choice(plan.parameters.size(), 0);
  const int seeds = std::max(plan.seeds, 0);
  while (true) {
    for (int s = seeds == 0 ? 0 : 1; s <= seeds; ++s) cases.push_back({cases.size(), choice, s});
    // The next combination: the last parameter fastest.
    std::size_t k = choice.size();
    while (k > 0) {
      --k;
      if (++choice[k] < plan.parameters[k].values.size()) break;
      choice[k] = 0;
      if (k == 0) return cases;
    }
    if (choice.empty()) return cases;
  }
}

std::string caseSceneText(const SweepPlan& plan, const SweepCase& c) {
  nlohmann::json scene = plan.scene;
  for (std::size_t k = 0; k < plan.parameters.size(); ++k) {
    const SweepParameter& p = plan.parameters[k];
    const nlohmann::json::json_pointer pointer(p.pointer);
    if (!scene.contains(pointer)) {
      const nlohmann::json::json_pointer parent = pointer.parent_pointer();
      if (!scene.contains(parent) || !scene.at(parent).is_object())
        throw std::invalid_argument(fmt::format(
            "--set {}: {} has no {} (the pointer's parent {} is not an object of the scene)",
            p.pointer, plan.scenePath, p.pointer,
            parent.to_string().empty() ? "/" : parent.to_string()));
    }
    scene[pointer] = p.values[c.choice[k]];
  }
  return scene.dump(2);
}

void perturbInitialPositions(Scene& scene, int seed, double jitter) {
  if (seed == 0) return;
  const Model& m = scene.model;
  for (ParticleIndex i = 0; i < m.particleCount(); ++i) {
    if (m.isFixed(i)) continue;
    const double a = jitter * m.radius[static_cast<std::size_t>(i)];
    Vec3& p = scene.initial.position[static_cast<std::size_t>(i)];
    p.x += a * uniformSigned(seed, i, 0);
    p.y += a * uniformSigned(seed, i, 1);
    p.z += a * uniformSigned(seed, i, 2);
  }
}

std::vector<std::size_t> endStateObjects(const Model& model,
                                         const std::vector<std::string>& names) {
  std::vector<std::size_t> out;
  if (names.size() == 1 && names.front() == "none") return out;
  if (names.empty()) {  // those that touch something (not "virtual"), if few
    for (std::size_t o = 0; o < model.objects.size(); ++o)
      if (model.objects[o].kind != "virtual" && model.objects[o].particleCount > 0)
        out.push_back(o);
    if (out.size() > kEndStateObjects) out.clear();
    return out;
  }
  for (const std::string& name : names) {
    const auto it = std::find_if(model.objects.begin(), model.objects.end(),
                                 [&](const ObjectInfo& o) { return o.name == name; });
    if (it == model.objects.end()) {
      std::string listed;  // the objects that touch something, the first 20
      std::size_t count = 0;
      for (const ObjectInfo& o : model.objects) {
        if (o.kind == "virtual") continue;
        if (count < 20) listed += (count ? ", '" : "'") + o.name + "'";
        ++count;
      }
      if (count > 20) listed += ", ...";
      throw std::invalid_argument(
          fmt::format("--end: the scene has no object '{}' (its objects: {})", name, listed));
    }
    out.push_back(static_cast<std::size_t>(it - model.objects.begin()));
  }
  return out;
}

namespace {

// Where each object ended: its centre of mass (m) and the speed of that centre
// (m/s), as "end/<object>/x", "/y", "/z", "/speed"; null where not finite (a
// run that diverged).
void addEndState(const Model& model, const State& state, const std::vector<std::string>& names,
                 nlohmann::json& row) {
  if (state.position.size() != static_cast<std::size_t>(model.particleCount())) return;
  const auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  for (const std::size_t o : endStateObjects(model, names)) {
    if (model.objects[o].particleCount == 0) continue;
    const robotics::ObjectMotion motion =
        robotics::objectMotion(model, state, static_cast<std::int32_t>(o));
    const std::string prefix = "end/" + model.objects[o].name + "/";
    row[prefix + "x"] = number(motion.center.x);
    row[prefix + "y"] = number(motion.center.y);
    row[prefix + "z"] = number(motion.center.z);
    row[prefix + "speed"] = number(norm(motion.velocity));
  }
}

}  // namespace

nlohmann::json runCase(const SweepPlan& plan, const SweepCase& c, double& wallSeconds) {
  const auto start = std::chrono::steady_clock::now();
  nlohmann::json row = nlohmann::json::object();
  row["run"] = c.index;
  for (std::size_t k = 0; k < plan.parameters.size(); ++k)
    row[plan.parameters[k].pointer] = plan.parameters[k].values[c.choice[k]];
  row["seed"] = c.seed;
  try {
    SceneLoadResult loaded = loadSceneText(caseSceneText(plan, c), plan.scenePath);
    if (!loaded.ok())
      throw std::invalid_argument(loaded.errors.empty() ? std::string("the scene does not load")
                                                        : loaded.errors.front().format("error"));
    Scene& scene = *loaded.scene;
    perturbInitialPositions(scene, c.seed, plan.jitter);
    RunOptions options;
    options.settings = scene.run;
    if (plan.duration > 0.0) options.settings.duration = plan.duration;
    options.writeReplay = false;
    // The runs themselves share the cores (--threads): one thread a run.
    options.threads = 1;
    options.tasks = {robotics::makeSceneTasks(scene)};
    // A signal stops the run at once (robophi sweep then writes nothing).
    options.stop = &InterruptGuard::flag();
    State finalState;
    const RunReport report = runScene(scene, options, &finalState);
    row["status"] = report.status;
    row["steps"] = report.steps;
    row["simulated_time"] = report.simulatedTime;
    row["energy_drift"] = report.energyDrift;
    row["largest_account_error"] = report.largestAccountError;
    row["dissipated"] = report.dissipated;
    row["external_work"] = report.externalWork;
    row["state_hash"] = fmt::format("{:016x}", report.stateHash);
    row["failure"] = report.failure;
    // (The flattened copy is kept: a range-for over a temporary's items() dangles.)
    const nlohmann::json flat =
        report.outcomes.empty() ? nlohmann::json::object() : report.outcomes.flatten();
    for (const auto& [key, value] : flat.items()) row["outcomes" + key] = value;
    addEndState(scene.model, finalState, plan.endObjects, row);
  } catch (const std::exception& e) {
    row["status"] = "error";
    row["failure"] = e.what();
  }
  wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return row;
}

std::vector<std::string> writeSweepTables(const std::string& dir, const SweepPlan& plan,
                                          const std::vector<nlohmann::json>& rows,
                                          const std::vector<double>& wallSeconds,
                                          const std::string& sharing) {
  const std::vector<std::string> names = columns(plan, rows);
  std::string csv;
  for (std::size_t k = 0; k < names.size(); ++k) csv += (k ? "," : "") + csvField(names[k]);
  csv += '\n';
  for (const nlohmann::json& row : rows) {
    for (std::size_t k = 0; k < names.size(); ++k) {
      const auto it = row.find(names[k]);
      csv += (k ? "," : "") + csvField(it == row.end() ? std::string() : cellText(*it));
    }
    csv += '\n';
  }
  writeFile(dir + "/sweep.csv", csv);

  nlohmann::json table;
  table["scene"] = plan.scenePath;
  table["parameters"] = nlohmann::json::array();
  for (const SweepParameter& p : plan.parameters)
    table["parameters"].push_back({{"pointer", p.pointer}, {"values", p.values}});
  table["seeds"] = plan.seeds;
  table["jitter"] = plan.jitter;
  if (plan.duration > 0.0) table["duration"] = plan.duration;
  if (plan.endObjects.empty())
    table["end_state_objects_at_most"] = kEndStateObjects;
  else
    table["end_objects"] = plan.endObjects;
  table["columns"] = names;
  table["runs"] = rows;
  writeFile(dir + "/sweep.json", table.dump(2) + "\n");

  std::string timing = "run,wall_seconds\n";
  for (std::size_t i = 0; i < wallSeconds.size(); ++i)
    timing += fmt::format("{},{:.6f}\n", i, wallSeconds[i]);
  writeFile(dir + "/timing.csv", timing);

  // The report: every numeric figure against every numeric parameter.
  writeFile(dir + "/report.html", sweepReportHtml(plan, rows, names, sharing));
  return {"sweep.csv", "sweep.json", "timing.csv", "report.html"};
}

std::string sweepReportHtml(const SweepPlan& plan, const std::vector<nlohmann::json>& rows,
                            const std::vector<std::string>& names, const std::string& sharing) {
  // One page width: plots wrap, the table scrolls inside its own box, long cells wrap.
  std::string html = fmt::format(
      "<!doctype html><html><head><meta charset='utf-8'><title>robophi sweep: {0}</title>"
      "<style>body{{font-family:sans-serif;margin:1.5em;max-width:100%;overflow-x:hidden}}"
      "table{{border-collapse:collapse;font-size:12px}}td,th{{border:1px solid #ccc;"
      "padding:2px 6px;vertical-align:top}}td{{max-width:24em;overflow-wrap:anywhere}}"
      ".table{{overflow-x:auto;max-width:100%}}.plots{{display:flex;flex-wrap:wrap;gap:12px}}"
      "figure{{margin:0;max-width:100%}}figure svg{{max-width:100%;height:auto}}"
      "figcaption{{font-size:12px;font-weight:bold;margin-bottom:2px}}"
      "details{{margin:6px 0}}summary{{cursor:pointer}}</style></head>"
      "<body><h1>robophi sweep</h1><p>Scene <code>{0}</code>: {1} runs ({2}). Seeds: {3}; "
      "jitter {4} of a particle's radius.</p>",
      escapeHtml(plan.scenePath), rows.size(), escapeHtml(sharing), plan.seeds,
      cellText(nlohmann::json(plan.jitter)));
  std::map<std::string, int> statusCount;
  for (const nlohmann::json& row : rows) ++statusCount[row.value("status", std::string("?"))];
  html += "<p>Status:";
  for (const auto& [status, count] : statusCount) html += fmt::format(" {} {};", status, count);
  html += "</p>";
  const auto isParameter = [&](const std::string& name) {
    return std::any_of(plan.parameters.begin(), plan.parameters.end(),
                       [&](const SweepParameter& p) { return p.pointer == name; });
  };
  const auto isEnd = [](const std::string& name) { return name.starts_with("end/"); };
  // The report's order: the run and its parameters, then what came out (status,
  // the outcomes, the failure), then the run's own figures; the objects' end
  // states last, collapsed.
  std::vector<std::string> order = {"run"};
  for (const SweepParameter& p : plan.parameters) order.push_back(p.pointer);
  order.emplace_back("status");
  for (const std::string& name : names)
    if (name.starts_with("outcomes/")) order.push_back(name);
  order.emplace_back("failure");
  for (const std::string& name : names)
    if (std::find(order.begin(), order.end(), name) == order.end() && !isEnd(name))
      order.push_back(name);
  std::vector<std::string> ends;
  for (const std::string& name : names)
    if (isEnd(name)) ends.push_back(name);

  std::vector<std::string> figures;
  for (const std::string& name : order) {
    if (name == "run" || name == "seed" || isParameter(name)) continue;
    const bool numeric = std::any_of(rows.begin(), rows.end(), [&](const nlohmann::json& r) {
      const auto it = r.find(name);
      return it != r.end() && (it->is_number() || it->is_boolean());
    });
    if (numeric) figures.push_back(name);
  }
  // A figure against a parameter: its caption above its plot.
  const auto figure = [&](const SweepParameter& p, const std::string& name) -> std::string {
    std::vector<std::pair<double, double>> points;
    for (const nlohmann::json& row : rows) {
      const auto x = row.find(p.pointer);
      const auto y = row.find(name);
      if (x == row.end() || y == row.end()) continue;
      if (!(y->is_number() || y->is_boolean())) continue;
      const double yv = y->is_boolean() ? (y->get<bool>() ? 1.0 : 0.0) : y->get<double>();
      if (std::isfinite(yv)) points.emplace_back(x->get<double>(), yv);
    }
    if (points.empty()) return {};
    return fmt::format("<figure><figcaption>{}</figcaption>{}</figure>", escapeHtml(name),
                       scatterSvg(p.pointer, name, points));
  };
  html += "<h2>Figures against parameters</h2>";
  for (const SweepParameter& p : plan.parameters) {
    const bool numeric = std::all_of(p.values.begin(), p.values.end(),
                                     [](const nlohmann::json& v) { return v.is_number(); });
    if (!numeric || p.values.size() < 2) continue;
    html += fmt::format("<h3><code>{}</code></h3><div class='plots'>", escapeHtml(p.pointer));
    for (const std::string& name : figures) html += figure(p, name);
    html += "</div>";
    std::string endPlots;
    std::size_t endCount = 0;
    for (const std::string& name : ends) {
      const std::string one = figure(p, name);
      endCount += one.empty() ? 0 : 1;
      endPlots += one;
    }
    if (endCount > 0) {
      html += fmt::format(
          "<details><summary>Where the objects ended ({} plots)</summary><div class='plots'>{}"
          "</div></details>",
          endCount, endPlots);
    }
  }
  html += "<h2>Table</h2><div class='table'><table><tr>";
  for (const std::string& name : order) html += "<th>" + escapeHtml(name) + "</th>";
  if (!ends.empty()) html += "<th>end states</th>";
  html += "</tr>";
  for (const nlohmann::json& row : rows) {
    html += "<tr>";
    for (const std::string& name : order) {
      const auto it = row.find(name);
      html += "<td>" + escapeHtml(it == row.end() ? std::string() : cellText(*it)) + "</td>";
    }
    if (!ends.empty()) {
      // Per object: "name: x, y, z (m), speed (m/s)", collapsed.
      std::string list;
      std::size_t objects = 0;
      for (std::size_t k = 0; k < ends.size(); ++k) {
        const std::string& name = ends[k];
        const std::size_t slash = name.rfind('/');
        const std::string object = name.substr(4, slash - 4);
        const bool first = k == 0 || ends[k - 1].substr(0, ends[k - 1].rfind('/')) !=
                                         name.substr(0, slash);
        if (first) {
          list += (objects > 0 ? "<br>" : "") + escapeHtml(object) + ":";
          ++objects;
        }
        const auto it = row.find(name);
        list += " " + escapeHtml(name.substr(slash + 1)) + " " +
                escapeHtml(it == row.end() ? std::string() : cellText(*it));
      }
      html += fmt::format("<td><details><summary>{} object{}</summary>{}</details></td>", objects,
                          objects == 1 ? "" : "s", list);
    }
    html += "</tr>";
  }
  html += "</table></div></body></html>\n";
  return html;
}

}  // namespace robophi::cli
