#include "tools/report/diagram_panel.h"

#include <fmt/format.h>

#include <regex>
#include <stdexcept>

#include "engine/registry.h"
#include "tools/report/chart_data.h"
#include "tools/report/report.h"

namespace mb {

namespace {

// At most `max` bytes of `s`, cut at a UTF-8 character boundary, "…" appended when cut.
std::string Cut(const std::string& s, std::size_t max) {
  if (s.size() <= max) return s;
  std::size_t cut = max;
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;  // inside a UTF-8 character
  return s.substr(0, cut) + "…";
}

std::string NumberText(const nlohmann::json& v) {
  if (v.is_number_float()) return fmt::format("{:.6g}", v.get<double>());
  return v.dump();
}

// A parameter's value as the panel shows it.
std::string ValueText(const nlohmann::json& v) {
  if (v.is_number()) return NumberText(v);
  if (v.is_string()) return Cut(v.get<std::string>(), kMaxPanelTextLength);
  if (v.is_array()) {
    std::string text = "[";
    for (std::size_t i = 0; i < v.size() && i < kMaxPanelVectorEntries; ++i) {
      text += (i ? ", " : "") + (v[i].is_number() ? NumberText(v[i]) : Cut(v[i].dump(), kMaxPanelTextLength));
    }
    if (v.size() > kMaxPanelVectorEntries) text += fmt::format(", … ({} entries)", v.size());
    return text + "]";
  }
  return Cut(v.dump(), kMaxPanelTextLength);
}

nlohmann::json ParameterEntry(const std::string& name, const nlohmann::json& value, const ParamSpec* spec) {
  const bool is_default = spec != nullptr && spec->default_value && *spec->default_value == value;
  return {{"name", Cut(name, kMaxPanelTextLength)},
          {"value", ValueText(value)},
          {"unit", spec != nullptr ? spec->unit : std::string()},
          {"default", is_default},
          {"description", spec != nullptr ? spec->description : std::string()}};
}

}  // namespace

nlohmann::json DiagramBlockData(const Diagram& diagram) {
  nlohmann::json blocks = nlohmann::json::array();
  for (std::size_t b = 0; b < diagram.blocks().size(); ++b) {
    const int index = static_cast<int>(b);
    const auto& values = diagram.block_parameters(index).values();
    nlohmann::json parameters = nlohmann::json::array();
    const BlockType* type = BlockRegistry::Global().Find(diagram.block_type(index));
    if (type != nullptr) {
      for (const auto& declared : type->parameters) {  // the declared order, as the block reference lists them
        const ParamSpec spec = OnAxis(declared, diagram.axis());  // N·m·s/rad on a rotary diagram
        const auto it = values.find(spec.name);
        if (it != values.end()) parameters.push_back(ParameterEntry(spec.name, it->second, &spec));
      }
    } else {
      for (const auto& [name, value] : values) parameters.push_back(ParameterEntry(name, value, nullptr));
    }
    blocks.push_back({{"name", Cut(diagram.blocks()[b]->name(), kMaxPanelTextLength)},
                      {"type", Cut(diagram.block_type(index), kMaxPanelTextLength)},
                      {"parameters", std::move(parameters)}});
  }
  return blocks;
}

std::string InlineSvg(const std::string& svg_file_text) {
  const std::size_t start = svg_file_text.find("<svg");
  const std::size_t end = svg_file_text.rfind("</svg>");
  if (start == std::string::npos || end == std::string::npos || end < start) {
    throw std::runtime_error("the diagram's SVG holds no <svg> element");
  }
  std::string svg = svg_file_text.substr(start, end + 6 - start);
  // Graphviz escapes '<' and '>' in text and attribute values, so every "<…>" is a tag: none may run script.
  static const std::regex kUnsafe(R"(^<\s*/?\s*(script|foreignobject)\b|\son[a-z]+\s*=)", std::regex::icase);
  for (std::size_t at = svg.find('<'); at != std::string::npos; at = svg.find('<', at + 1)) {
    const std::size_t close = svg.find('>', at);
    const std::string tag = svg.substr(at, close == std::string::npos ? std::string::npos : close + 1 - at);
    if (std::regex_search(tag, kUnsafe)) {
      throw std::runtime_error(fmt::format("the diagram's SVG holds a tag that could run script: {}", Cut(tag, 80)));
    }
  }
  return svg;
}

namespace {

constexpr const char* kPanelCss =
    ".mb-diagram-svg{overflow:auto;max-height:80vh}.mb-diagram-svg g.mb-block{cursor:pointer;outline:none}"
    ".mb-diagram-svg g.mb-block:hover polygon,.mb-diagram-svg g.mb-block:focus-visible polygon,"
    ".mb-diagram-svg g.mb-selected polygon{stroke:#1f77b4;stroke-width:3}"
    ".mb-block-panel{border:1px solid #1f77b4;border-radius:4px;padding:.4em .8em;margin:.5em 0;background:#f5f9fd}"
    ".mb-block-panel table{margin:.4em 0}.mb-block-panel td,.mb-block-panel th{text-align:left}"
    ".mb-block-panel tr.mb-default td{color:#777}.mb-block-title{font-weight:bold}";

// Fills the figure's panel with the clicked block's data (the JSON beside it), as text only. The figure is the
// script's parent element, so that each diagram of a page has its own data and panel.
constexpr const char* kPanelScript = R"JS((function (figure) {
  'use strict';
  var blocks = JSON.parse(figure.querySelector('script.mb-blocks').textContent);
  var panel = figure.querySelector('.mb-block-panel'), selected = null;
  function add(parent, tag, text, cls) {
    var e = document.createElement(tag);
    e.textContent = text;
    if (cls) e.className = cls;
    parent.appendChild(e);
    return e;
  }
  function show(k, node) {
    var b = blocks[k];
    if (selected) selected.classList.remove('mb-selected');
    selected = node;
    node.classList.add('mb-selected');
    panel.textContent = '';
    add(panel, 'div', b.name + ' \u00b7 ' + b.type, 'mb-block-title');
    if (!b.parameters.length) {
      add(panel, 'div', 'no parameters');
    } else {
      var table = add(panel, 'table', ''), head = add(table, 'tr', '');
      ['parameter', 'value', 'unit (SI)'].forEach(function (h) { add(head, 'th', h); });
      b.parameters.forEach(function (p) {
        var row = add(table, 'tr', '', p['default'] ? 'mb-default' : '');
        row.title = p.description + (p['default'] ? ' (default value)' : '');
        add(row, 'td', p.name, 'mb-name');
        add(row, 'td', p.value, 'mb-value');
        add(row, 'td', p.unit || '1 (no unit)', 'mb-unit');
      });
      add(panel, 'div', 'Grey: the type\'s default value. Hover a row for its description.').style.fontSize = '12px';
    }
    panel.hidden = false;
  }
  Array.prototype.forEach.call(figure.querySelectorAll('g.node'), function (node) {
    var title = node.querySelector('title'), m = title && /^b(\d+)$/.exec(title.textContent);
    if (!m || !blocks[+m[1]]) return;  // a connector or the legend
    var k = +m[1];
    title.textContent = blocks[k].name + ' (' + blocks[k].type + '): click for its parameters';
    node.classList.add('mb-block');
    node.setAttribute('data-block', String(k));  // the block's index in the data (tests/browser reads it)
    node.setAttribute('tabindex', '0');
    node.setAttribute('role', 'button');
    node.addEventListener('click', function () { show(k, node); });
    node.addEventListener('keydown', function (e) { if (e.key === 'Enter') show(k, node); });
  });
})(document.currentScript.parentNode);
)JS";

}  // namespace

std::string ClickableDiagramHtml(const std::string& svg, const nlohmann::json& blocks, const std::string& caption,
                                 const std::string& svg_file) {
  return fmt::format(
      "<figure class=\"mb-diagram\"><style>{}</style>\n<div class=\"mb-diagram-svg\">{}</div>\n"
      "<div class=\"mb-block-panel\" hidden></div>\n"
      "<figcaption>{} Click a block for its parameters. The picture: <a href=\"{}\">{}</a></figcaption>\n"
      "<script type=\"application/json\" class=\"mb-blocks\">{}</script>\n<script>\n{}</script></figure>\n",
      kPanelCss, svg, HtmlEscape(caption), HtmlEscape(svg_file), HtmlEscape(svg_file), ScriptSafeJson(blocks),
      kPanelScript);
}

}  // namespace mb
