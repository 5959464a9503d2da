// The docs tables of the term specs (term_spec.h): what docs/mismatch.md shows of each row.
#include <fmt/core.h>

#include <string>
#include <vector>

#include "graftnav/mismatch/term_spec.h"

namespace graftnav {

namespace {

const char* roleText(TermRole role) {
  switch (role) {
    case TermRole::nuisance:
      return "nuisance";
    case TermRole::candidate:
      return "candidate";
    case TermRole::part:
      return "fixed part";
    case TermRole::reported:
      return "reported";
  }
  return "";
}

// The scopes a row's effects have.
std::vector<SensorScope> scopesOf(TermSensors sensors) {
  switch (sensors) {
    case TermSensors::each_triad:
      return {SensorScope::gyro, SensorScope::accel};
    case TermSensors::gyro:
      return {SensorScope::gyro};
    case TermSensors::accel:
      return {SensorScope::accel};
    case TermSensors::both:
      break;
  }
  return {SensorScope::both};
}

// "gyro, accel", "gyro", "accel" or "both".
std::string sensorsText(TermSensors sensors) {
  std::string text;
  for (const SensorScope s : scopesOf(sensors))
    text += (text.empty() ? "" : ", ") + std::string(scopeName(s));
  return text;
}

// "key [unit]", "key [gyro unit, accel unit]" when the triads differ, "key (text)".
std::string parameterText(const ParameterSpec& p, TermSensors sensors) {
  if (p.layout == ParameterLayout::regressor_name) return fmt::format("{} (text)", p.key);
  std::string units;
  for (const SensorScope s : scopesOf(sensors)) {
    const char* u = unitOf(p, s);
    const std::string unit = u ? u : "?";
    if (units.empty())
      units = unit;
    else if (units != unit)
      units += ", " + unit;
  }
  std::string text = fmt::format("{} [{}]", p.key, units);
  if (p.doc[0] != '\0') text += fmt::format(" {}", p.doc);
  return text;
}

}  // namespace

std::string candidateTermTable(const std::vector<const TermSpec*>& specs) {
  std::string md =
      "| term | role | sensors | regressor | parameters [SI unit] |\n"
      "|---|---|---|---|---|\n";
  for (const TermSpec* spec : specs) {
    std::string params;
    for (const ParameterSpec& p : spec->parameters)
      params += (params.empty() ? "" : "; ") + parameterText(p, spec->sensors);
    md +=
        fmt::format("| {} | {} | {} | {} | {} |\n", spec->name, roleText(spec->role),
                    sensorsText(spec->sensors), spec->regressor_doc, params.empty() ? "-" : params);
  }
  return md;
}

std::string plausibleRangeTable(const std::vector<const TermSpec*>& specs,
                                const std::vector<std::string>& classes) {
  std::vector<PlausibleRanges> ranges;
  std::string md = "| term | parameter | sensor |";
  std::string rule = "|---|---|---|";
  for (const std::string& c : classes) {
    ranges.push_back(plausibleRangesForClass(c));
    md += " " + c + " |";
    rule += "---|";
  }
  md += "\n" + rule + "\n";
  for (const TermSpec* spec : specs)
    for (const ParameterSpec& p : spec->parameters)
      for (const SensorScope s : scopesOf(spec->sensors)) {
        double PlausibleRanges::*const field = boundOf(p, s);
        if (field == nullptr) continue;
        md += fmt::format("| {} | {}{} | {} |", spec->name, p.key,
                          p.diagonal_only ? " (diagonal)" : "", scopeName(s));
        for (const PlausibleRanges& r : ranges) md += fmt::format(" {:.3g} |", r.*field);
        md += "\n";
      }
  return md;
}

}  // namespace graftnav
