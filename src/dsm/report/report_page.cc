// SPDX-License-Identifier: MIT
#include "dsm/report/report.h"

#include <cctype>
#include <fstream>

#include "dsm/util/check.h"

namespace dsm {

namespace {

// Text inside a <script> element must not hold "</script" (it would end the element there).
// JSON: every "</" becomes "<\/", the same string. The bundled script: only "</script", in any
// case, becomes "<\/script" (inside its string and regex literals, where alone it can occur, the
// same text).
std::string JsonInScript(std::string json) {
  for (size_t at = 0; (at = json.find("</", at)) != std::string::npos; at += 3) json.replace(at, 2, "<\\/");
  return json;
}

std::string ScriptInScript(const std::string& script) {
  std::string out;
  out.reserve(script.size());
  for (size_t i = 0; i < script.size(); ++i) {
    out += script[i];
    if (script[i] != '<' || i + 8 > script.size()) continue;
    std::string word = script.substr(i + 1, 7);
    for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (word == "/script") out += '\\';
  }
  return out;
}

std::string EscapeHtml(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::string ReportPage(const nlohmann::json& data, bool live) {
  const std::string title = data.value("title", std::string("dsm"));
  std::string page;
  page += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  page += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  page += "<link rel=\"icon\" href=\"data:,\">\n";  // No icon: the browser asks for none.
  page += "<title>dsm report: " + EscapeHtml(title) + "</title>\n</head>\n";
  page += std::string("<body data-live=\"") + (live ? "1" : "0") + "\">\n";
  page += "<script id=\"dsm-data\" type=\"application/json\">" + JsonInScript(data.dump()) + "</script>\n";
  page += "<script>" + ScriptInScript(dsm_report_script) + "</script>\n</body>\n</html>\n";
  return page;
}

void WriteReport(const std::filesystem::path& run_dir) {
  const std::string page = ReportPage(ReportData(run_dir));
  const std::filesystem::path path = run_dir / "report.html";
  std::ofstream out(path, std::ios::binary);
  out << page;
  if (!out) throw InputError(path.string() + ": cannot write file");
}

}  // namespace dsm
