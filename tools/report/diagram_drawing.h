#pragma once
// A picture of a diagram: its Graphviz DOT text (as Drake's Diagram::GetGraphvizString) and the picture rendered by
// Graphviz's `dot` program (Debian's graphviz package, run without a shell: run_program.h).
//
// What the DOT text shows: every block as a record node — its input ports (left column) and output ports (right
// column) by name, in the middle its name, its registered type and a bounded list of its key parameters (those the
// diagram sets to other values than their defaults, at most kMaxKeyParameters); the diagram's input and output
// connectors; one edge per connection (port to port); each subsystem ("subsystem/element" after expansion) as a
// cluster; discrete blocks filled with one colour per sample time [Ts, offset] (a legend lists them); and, when
// asked, the blocks of a refused algebraic loop and the elements an analysis added, each in its own colour.
//
// Every string of the diagram (names, types, units, parameter values) reaches the DOT text only through the
// escaping of its context (a quoted DOT string, a record field), so a hostile name can neither break the file
// nor change its meaning. Node identifiers are generated (b0, i0, o0), never taken from a name.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engine/diagram.h"
#include "engine/execution_order.h"

namespace mb {

class HtmlReport;

/// At most this many key parameters are listed in a block's node (then "+ N more").
inline constexpr std::size_t kMaxKeyParameters = 4;

/// What to mark in a drawing besides the diagram itself.
struct DrawingMarks {
  std::vector<int> algebraic_loop;    ///< block indices of a refused algebraic loop (AlgebraicLoopError::cycle())
  std::vector<std::string> added;     ///< element names an analysis added (improve's effects)
  std::string added_label = "added";  ///< the legend's words for `added`
};

/// The colours of a drawing (Graphviz colour names or #rrggbb), exposed for tests and the README's legend.
inline constexpr const char* kAlgebraicLoopColour = "#d62728";
inline constexpr const char* kAddedColour = "#ff7f0e";
/// Fill colours of discrete blocks, one per distinct sample time in increasing period (then cycled).
inline constexpr const char* kSampleTimeColours[] = {"#aec7e8", "#98df8a", "#c5b0d5", "#ffbb78",
                                                     "#f7b6d2", "#dbdb8d", "#9edae5", "#c7c7c7"};

/// The DOT text of `diagram` (a `digraph`, left to right), with `marks`. Never throws for a diagram's strings.
std::string DiagramGraphvizString(const Diagram& diagram, const DrawingMarks& marks = {});

/// The picture formats `dot` is asked for.
enum class DrawingFormat { kDot, kSvg, kPng };
/// "dot", "svg" or "png" → the format. @throws std::invalid_argument naming the choices.
DrawingFormat ParseDrawingFormat(const std::string& text);
/// The file extension (no dot): "dot", "svg", "png".
const char* ToString(DrawingFormat format);

/// Writes `dot_text` to `path` in `format`: the text itself for kDot, else rendered by `dot -T<format>` (no shell;
/// the text is written to a temporary file beside `path`, removed afterwards). The file is written safely
/// (engine/output_file.h). @throws std::runtime_error when Graphviz is missing or fails (its message), or the file
/// cannot be written.
void WriteDrawing(const std::string& dot_text, DrawingFormat format, const std::filesystem::path& path);

/// What DrawDiagram drew: the diagram's name and, when the loader refuses it for an algebraic loop (drawn
/// highlighted), that refusal.
struct DrawnDiagram {
  std::string name;
  std::optional<AlgebraicLoopError> algebraic_loop;
};

/// `motionblocks draw`: builds `diagram` (its JSON, --set applied; subsystem files against `base_directory`,
/// `source` in messages) with InspectDiagram and writes its picture to `path` in `format`, the algebraic loop
/// highlighted if there is one. @throws DiagramError for any other fault of the diagram (nothing is drawn), and as
/// WriteDrawing.
DrawnDiagram DrawDiagram(const nlohmann::json& diagram, const std::filesystem::path& base_directory,
                         const std::string& source, DrawingFormat format, const std::filesystem::path& path);

/// The files AddDiagramDrawing writes, relative to its folder: plot/`file_stem`.dot (the DOT text, what draws the
/// picture: `dot -Tsvg -o ../diagram.svg diagram.dot` in plot/ redraws it) and `file_stem`.svg (the picture).
std::vector<std::string> DiagramDrawingFileNames(const std::string& file_stem = "diagram");

/// Adds a "Diagram" section to `report`: `directory`/`file_stem`.svg (and plot/`file_stem`.dot) drawn from
/// `diagram` with `marks`, shown inline with a click on a block showing its parameters and their units
/// (ClickableDiagramHtml, diagram_panel.h). A drawing that fails (no Graphviz) becomes a note in the report, never
/// an error.
void AddDiagramDrawing(HtmlReport* report, const Diagram& diagram, const DrawingMarks& marks,
                       const std::filesystem::path& directory, const std::string& file_stem = "diagram");
/// The same for a diagram's JSON (as compare and improve hold it; subsystem files resolve against `base_directory`,
/// `source` names it in messages): built with InspectDiagram, so an algebraic loop is drawn highlighted; a diagram
/// that cannot be built becomes a note.
void AddDiagramDrawing(HtmlReport* report, const nlohmann::json& diagram, const std::filesystem::path& base_directory,
                       const std::string& source, DrawingMarks marks, const std::filesystem::path& directory,
                       const std::string& file_stem = "diagram");

}  // namespace mb
