#include "tools/report/diagram_drawing.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "engine/diagram_loader.h"
#include "engine/output_file.h"
#include "engine/registry.h"
#include "tools/report/diagram_panel.h"
#include "tools/report/report.h"
#include "tools/report/run_program.h"
#include "tools/report/temporary_folder.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxTextLength = 48;   // a name, type or connector shown [bytes]
constexpr std::size_t kMaxValueLength = 24;  // a parameter value shown [bytes]
constexpr std::size_t kMaxVectorEntries = 3;

// At most `max` bytes of `s`, cut at a UTF-8 character boundary, "…" appended when cut; control characters
// (a newline would end a DOT line) become spaces.
std::string Bounded(const std::string& s, std::size_t max) {
  std::string out;
  std::size_t cut = s.size();
  if (s.size() > max) {
    cut = max;
    while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;  // inside a UTF-8 character
  }
  for (std::size_t i = 0; i < cut; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    out += (c < 0x20 || c == 0x7f) ? ' ' : s[i];
  }
  if (cut < s.size()) out += "…";
  return out;
}

// Text of a plain label inside a quoted DOT string. Two layers: Graphviz's label escapes (\n, \N, \G… — a
// backslash is written "\\") and the DOT string ("\"" for a quote).
std::string LabelText(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\\' || c == '"') out += '\\';
    out += c;
  }
  return out;
}

// Text of one record field inside a quoted DOT string: LabelText plus the record syntax's own characters
// ({ } | < > and the space, which separates tokens) written with a backslash.
std::string RecordText(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\\' || c == '"' || c == '{' || c == '}' || c == '|' || c == '<' || c == '>' || c == ' ') out += '\\';
    out += c;
  }
  return out;
}

std::string FormatNumber(const nlohmann::json& v) {
  return v.is_number_float() ? fmt::format("{:.4g}", v.get<double>()) : v.dump();
}

// A parameter value in a few characters: numbers to 4 digits, the first entries of a vector, a string cut short.
std::string FormatValue(const nlohmann::json& v) {
  if (v.is_number()) return FormatNumber(v);
  if (v.is_string()) return Bounded(v.get<std::string>(), kMaxValueLength);
  if (v.is_array()) {
    std::string text = "[";
    for (std::size_t i = 0; i < v.size() && i < kMaxVectorEntries; ++i) {
      text += (i ? ", " : "") + (v[i].is_number() ? FormatNumber(v[i]) : Bounded(v[i].dump(), kMaxValueLength));
    }
    return text + (v.size() > kMaxVectorEntries ? ", …]" : "]");
  }
  return Bounded(v.dump(), kMaxValueLength);
}

// The parameters block `b` has at other values than their defaults (required ones always), in declared order:
// "name = value unit" lines, at most kMaxKeyParameters, then "+ N more".
std::vector<std::string> KeyParameters(const Diagram& diagram, int b) {
  std::vector<std::string> lines;
  const BlockType* type = BlockRegistry::Global().Find(diagram.block_type(b));
  if (type == nullptr) return lines;
  const auto& values = diagram.block_parameters(b).values();
  std::size_t more = 0;
  for (const auto& declared : type->parameters) {
    const ParamSpec spec = OnAxis(declared, diagram.axis());  // its unit on the diagram's axis (N·m·s/rad)
    const auto it = values.find(spec.name);
    if (it == values.end() || (spec.default_value && *spec.default_value == it->second)) continue;
    if (lines.size() == kMaxKeyParameters) {
      ++more;
      continue;
    }
    lines.push_back(
        fmt::format("{} = {}{}{}", spec.name, FormatValue(it->second), spec.unit.empty() ? "" : " ", spec.unit));
  }
  if (more > 0) lines.push_back(fmt::format("+ {} more", more));
  return lines;
}

// "{<i0> u|<i1> v}": one record field per port, named by the port (and its width when > 1).
std::string PortFields(const std::vector<PortSpec>& ports, char prefix) {
  std::string fields;
  for (std::size_t p = 0; p < ports.size(); ++p) {
    const std::string text = ports[p].width > 1 ? fmt::format("{} [{}]", ports[p].name, ports[p].width) : ports[p].name;
    fields += fmt::format("{}<{}{}> {}", p ? "|" : "", prefix, p, RecordText(Bounded(text, kMaxTextLength)));
  }
  return "{" + fields + "}";
}

// Discrete sample times, increasing period then offset, each with its fill colour.
std::map<std::pair<double, double>, std::string> SampleTimeColours(const Diagram& diagram) {
  std::map<std::pair<double, double>, std::string> colours;
  for (const auto& block : diagram.blocks()) {
    if (block->sample_time().is_discrete()) colours[{block->sample_time().period, block->sample_time().offset}] = "";
  }
  std::size_t k = 0;
  for (auto& [ts, colour] : colours) colour = kSampleTimeColours[k++ % std::size(kSampleTimeColours)];
  return colours;
}

// The subsystems as a tree of clusters: "a/b/c" is block c inside cluster b inside cluster a.
struct Cluster {
  std::vector<int> blocks;
  std::map<std::string, Cluster> children;
};

Cluster ClusterTree(const Diagram& diagram) {
  Cluster root;
  for (std::size_t b = 0; b < diagram.blocks().size(); ++b) {
    Cluster* at = &root;
    const std::string& name = diagram.blocks()[b]->name();
    std::size_t start = 0;
    for (std::size_t slash = name.find('/'); slash != std::string::npos; slash = name.find('/', start)) {
      at = &at->children[name.substr(start, slash - start)];
      start = slash + 1;
    }
    at->blocks.push_back(static_cast<int>(b));
  }
  return root;
}

class DotWriter {
 public:
  DotWriter(const Diagram& diagram, const DrawingMarks& marks)
      : d_(diagram),
        loop_(marks.algebraic_loop.begin(), marks.algebraic_loop.end()),
        added_(marks.added.begin(), marks.added.end()),
        added_label_(marks.added_label),
        colours_(SampleTimeColours(diagram)) {}

  std::string Write() {
    out_ << "digraph diagram {\n  rankdir=LR;\n  labelloc=t;\n"
         << "  label=\"" << LabelText(Bounded(d_.name(), kMaxTextLength)) << "\";\n"
         << "  node [fontname=\"Helvetica\", fontsize=10];\n  edge [fontname=\"Helvetica\", fontsize=9];\n";
    Connectors();
    int next_cluster = 0;
    Clusters(ClusterTree(d_), "  ", &next_cluster);
    Edges();
    Legend();
    out_ << "}\n";
    return out_.str();
  }

 private:
  void Connectors() {
    for (std::size_t k = 0; k < d_.inputs().size(); ++k) {
      const auto& in = d_.inputs()[k];
      out_ << fmt::format("  i{} [shape=cds, label=\"{}{}\"];\n", k, LabelText(Bounded(in.name, kMaxTextLength)),
                          in.unit.empty() ? "" : " [" + LabelText(Bounded(in.unit, kMaxTextLength)) + "]");
    }
    for (std::size_t k = 0; k < d_.outputs().size(); ++k) {
      const auto& o = d_.outputs()[k];
      out_ << fmt::format("  o{} [shape=cds, label=\"{}{}\"];\n", k, LabelText(Bounded(o.name, kMaxTextLength)),
                          o.unit.empty() ? "" : " [" + LabelText(Bounded(o.unit, kMaxTextLength)) + "]");
    }
  }

  void Clusters(const Cluster& cluster, const std::string& indent, int* next_cluster) {
    for (int b : cluster.blocks) Node(b, indent);
    for (const auto& [name, child] : cluster.children) {
      out_ << fmt::format("{}subgraph cluster_{} {{\n{}  label=\"{}\";\n{}  style=rounded;\n", indent,
                          (*next_cluster)++, indent, LabelText(Bounded(name, kMaxTextLength)), indent);
      Clusters(child, indent + "  ", next_cluster);
      out_ << indent << "}\n";
    }
  }

  void Node(int b, const std::string& indent) {
    const Block& block = *d_.blocks()[static_cast<std::size_t>(b)];
    const std::string& name = block.name();
    const std::string last = name.substr(name.rfind('/') + 1);  // the cluster names the rest
    std::string centre = RecordText(Bounded(last.empty() ? name : last, kMaxTextLength)) + "\\n" +
                         RecordText(Bounded(d_.block_type(b), kMaxTextLength));
    for (const auto& line : KeyParameters(d_, b)) centre += "\\n" + RecordText(line);
    std::string label = "{";
    if (!block.input_ports().empty()) label += PortFields(block.input_ports(), 'i') + "|";
    label += centre;
    if (!block.output_ports().empty()) label += "|" + PortFields(block.output_ports(), 'o');
    label += "}";
    std::string style = "filled";
    std::string fill = "white";
    if (block.sample_time().is_discrete()) fill = colours_.at({block.sample_time().period, block.sample_time().offset});
    std::string border = "black";
    double pen = 1.0;
    const bool in_loop = loop_.count(b) != 0;  // the loop's colour wins over "added"
    if (in_loop || added_.count(name) != 0) {
      border = in_loop ? kAlgebraicLoopColour : kAddedColour;
      pen = 3.0;
      style += ",bold";
    }
    out_ << fmt::format(
        "{}b{} [shape=record, style=\"{}\", fillcolor=\"{}\", color=\"{}\", penwidth={}, label=\"{}\"];\n", indent, b,
        style, fill, border, pen, label);
  }

  void Edges() {
    for (std::size_t b = 0; b < d_.blocks().size(); ++b) {
      const auto& ports = d_.blocks()[b]->input_ports();
      for (std::size_t p = 0; p < ports.size(); ++p) {
        const SignalRef src = d_.sources()[b][p];
        const bool in_loop = !src.is_external() && ports[p].direct_feedthrough && loop_.count(src.block) &&
                             loop_.count(static_cast<int>(b));
        out_ << fmt::format("  {} -> b{}:i{}{};\n", From(src), b, p,
                            in_loop ? fmt::format(" [color=\"{}\", penwidth=3]", kAlgebraicLoopColour) : "");
      }
    }
    for (std::size_t k = 0; k < d_.outputs().size(); ++k)
      out_ << fmt::format("  {} -> o{};\n", From(d_.outputs()[k].source), k);
  }

  static std::string From(const SignalRef& src) {
    return src.is_external() ? fmt::format("i{}", src.port) : fmt::format("b{}:o{}", src.block, src.port);
  }

  void Legend() {
    std::vector<std::string> entries;
    for (const auto& [ts, colour] : colours_) {
      entries.push_back(fmt::format("label=\"discrete, Ts = {:g} s{}\", fillcolor=\"{}\"", ts.first,
                                    ts.second != 0.0 ? fmt::format(", offset {:g} s", ts.second) : "", colour));
    }
    if (!loop_.empty()) {
      entries.push_back(
          fmt::format("label=\"algebraic loop\", fillcolor=white, color=\"{}\", penwidth=3", kAlgebraicLoopColour));
    }
    if (!added_.empty()) {
      entries.push_back(fmt::format("label=\"{}\", fillcolor=white, color=\"{}\", penwidth=3",
                                    LabelText(Bounded(added_label_, kMaxTextLength)), kAddedColour));
    }
    if (entries.empty()) return;
    out_ << "  subgraph cluster_legend {\n    label=\"legend\";\n    style=dashed;\n"
         << "    node [shape=box, style=filled, fontsize=9];\n";
    for (std::size_t k = 0; k < entries.size(); ++k) {
      out_ << fmt::format("    legend{} [{}];\n", k, entries[k]);
    }
    for (std::size_t k = 1; k < entries.size(); ++k) {
      out_ << fmt::format("    legend{} -> legend{} [style=invis];\n", k - 1, k);
    }
    out_ << "  }\n";
  }

  const Diagram& d_;
  std::set<int> loop_;
  std::set<std::string> added_;
  std::string added_label_;
  std::map<std::pair<double, double>, std::string> colours_;
  std::ostringstream out_;
};

std::string ReadWholeFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

std::string DiagramGraphvizString(const Diagram& diagram, const DrawingMarks& marks) {
  return DotWriter(diagram, marks).Write();
}

DrawingFormat ParseDrawingFormat(const std::string& text) {
  if (text == "dot") return DrawingFormat::kDot;
  if (text == "svg") return DrawingFormat::kSvg;
  if (text == "png") return DrawingFormat::kPng;
  throw std::invalid_argument(fmt::format("--format {}: unknown; choose svg, png or dot", Bounded(text, 40)));
}

const char* ToString(DrawingFormat format) {
  switch (format) {
    case DrawingFormat::kDot: return "dot";
    case DrawingFormat::kSvg: return "svg";
    case DrawingFormat::kPng: return "png";
  }
  return "dot";
}

void WriteDrawing(const std::string& dot_text, DrawingFormat format, const fs::path& path) {
  if (format == DrawingFormat::kDot) {
    WriteFileSafely(path, dot_text);
    return;
  }
  const TemporaryFolder folder("motionblocks-draw");
  const fs::path input = folder.path() / "diagram.dot";
  const fs::path output = folder.path() / fmt::format("diagram.{}", ToString(format));
  const fs::path log = folder.path() / "dot.log";
  WriteFileSafely(input, dot_text);
  // No shell: the program and its arguments as a vector; both paths are ours (absolute, no user text).
  const int status =
      RunProgram({"dot", fmt::format("-T{}", ToString(format)), "-o", output.string(), input.string()}, log);
  if (status != 0 || !fs::is_regular_file(output)) {
    throw std::runtime_error(
        fmt::format("draw: Graphviz's dot could not render the diagram (exit {}): {} — is graphviz installed? "
                    "(scripts/install-deps.sh; or write --format dot and render it elsewhere)",
                    status, Bounded(ReadWholeFile(log), 400)));
  }
  WriteFileSafely(path, ReadWholeFile(output));
}

namespace {

// Graphviz's layout grows faster than linearly with the blocks: 100,000 blocks did not finish in 3 minutes (found by
// tests/hostile). A picture of more blocks than this is unreadable anyway; its DOT text is still written.
constexpr std::size_t kMaxDrawnBlocks = 2000;

void RequireDrawableSize(const Diagram& diagram) {
  if (diagram.blocks().size() <= kMaxDrawnBlocks) return;
  throw std::invalid_argument(fmt::format(
      "draw: {} has {} blocks, more than the {} a picture lays out in reasonable time: write its source with "
      "--format dot (and lay it out with your own Graphviz options), or draw a subsystem of it",
      Bounded(diagram.name(), 80), diagram.blocks().size(), kMaxDrawnBlocks));
}

}  // namespace

DrawnDiagram DrawDiagram(const nlohmann::json& diagram, const fs::path& base_directory, const std::string& source,
                         DrawingFormat format, const fs::path& path) {
  InspectedDiagram inspected = InspectDiagram(diagram, base_directory, source);
  if (format != DrawingFormat::kDot) RequireDrawableSize(inspected.diagram);
  DrawingMarks marks;
  if (inspected.algebraic_loop) marks.algebraic_loop = inspected.algebraic_loop->cycle();
  WriteDrawing(DiagramGraphvizString(inspected.diagram, marks), format, path);
  return DrawnDiagram{inspected.diagram.name(), std::move(inspected.algebraic_loop)};
}

std::vector<std::string> DiagramDrawingFileNames(const std::string& file_stem) {
  return {std::string(kPlotFolder) + "/" + file_stem + ".dot", file_stem + ".svg"};
}

void AddDiagramDrawing(HtmlReport* report, const Diagram& diagram, const DrawingMarks& marks, const fs::path& directory,
                       const std::string& file_stem) {
  report->Heading("Diagram");
  const std::string dot_text = DiagramGraphvizString(diagram, marks);
  const std::vector<std::string> names = DiagramDrawingFileNames(file_stem);
  try {
    fs::create_directories((directory / names[0]).parent_path());
    WriteDrawing(dot_text, DrawingFormat::kDot, directory / names[0]);
    RequireDrawableSize(diagram);
    WriteDrawing(dot_text, DrawingFormat::kSvg, directory / names[1]);
    report->Fragment(ClickableDiagramHtml(
        InlineSvg(ReadWholeFile(directory / names[1])), DiagramBlockData(diagram),
        fmt::format("The diagram {} (Graphviz; its DOT text: {}).", diagram.name(), names[0]), names[1]));
  } catch (const std::exception& e) {
    report->Warning(fmt::format("Diagram drawing missing: {}", e.what()));
  }
}

void AddDiagramDrawing(HtmlReport* report, const nlohmann::json& diagram, const fs::path& base_directory,
                       const std::string& source, DrawingMarks marks, const fs::path& directory,
                       const std::string& file_stem) {
  try {
    InspectedDiagram inspected = InspectDiagram(diagram, base_directory, source);
    if (inspected.algebraic_loop) marks.algebraic_loop = inspected.algebraic_loop->cycle();
    AddDiagramDrawing(report, inspected.diagram, marks, directory, file_stem);
  } catch (const std::exception& e) {
    report->Heading("Diagram");
    report->Warning(fmt::format("Diagram drawing missing: {}", e.what()));
  }
}

}  // namespace mb
