#pragma once
// A report's diagram that answers a click (issue 27, item 5): the picture Graphviz drew (diagram_drawing.h) inline in
// the page as SVG, and beside it a panel that shows the clicked block's name, type and every parameter with its
// value and unit.
//
// Where the units come from: the loader converts a value written with a unit ({"value": 200, "unit": "N·s/m"}, or
// {"value": 2000, "unit": "g"}) to the SI unit its block type declares (ParamSpec::unit, engine/parameters.h), and a
// parameter whose type declares no unit is dimensionless (the loader refuses a unit for it). So a block's values
// (Diagram::block_parameters) are SI, and their unit is the registry's on the diagram's axis (Diagram::axis, OnAxis:
// N·s/m on a linear diagram, N·m·s/rad on a rotary one in rad and N·m): that pair is what the panel shows.
//
// Every string of the diagram reaches the page as data: the block data as JSON inside a <script
// type="application/json"> (ScriptSafeJson: no "</script>" can occur in it), written into the panel by the page's
// script as text (textContent), never as markup; the SVG as Graphviz wrote it (every text XML-escaped, every id
// generated: DiagramGraphvizString names no node after a block).

#include <string>

#include <nlohmann/json.hpp>

#include "engine/diagram.h"

namespace mb {

/// The panel's data, one entry per block in block order (entry b is the drawing's node "b<b>"): {"name", "type",
/// "parameters": [{"name", "value" (text: a number to 6 significant digits, an integer as it is, a vector's first
/// kMaxPanelVectorEntries entries, a string cut at kMaxPanelTextLength bytes), "unit" (SI, on the diagram's axis; "" dimensionless),
/// "default" (whether the value is the type's default), "description"}]}, parameters in the type's declared order.
/// Throws nothing for a diagram's strings.
nlohmann::json DiagramBlockData(const Diagram& diagram);

/// At most this many entries of a vector parameter are shown (then "… (N entries)").
inline constexpr std::size_t kMaxPanelVectorEntries = 20;
/// At most this many bytes of a string parameter (or a name) are shown (cut at a character boundary, then "…").
inline constexpr std::size_t kMaxPanelTextLength = 200;

/// The <svg> element of an SVG file Graphviz wrote (its XML prolog, DOCTYPE and leading comments dropped), to stand
/// inline in an HTML page. @throws std::runtime_error if there is no <svg> element, or the text holds a <script> or
/// <foreignObject> element or an "on…" event attribute (Graphviz writes none).
std::string InlineSvg(const std::string& svg_file_text);

/// The HTML of a clickable diagram: `svg` (InlineSvg of Graphviz's drawing of DiagramGraphvizString) in a scrolling
/// box, an empty panel, `caption` (escaped here) with a link to `svg_file` (the picture as a file), `blocks`
/// (DiagramBlockData) as JSON and the small script that fills the panel when a block's node is clicked (or focused
/// and Enter pressed). Without script the picture is still shown. Throws nothing.
std::string ClickableDiagramHtml(const std::string& svg, const nlohmann::json& blocks, const std::string& caption,
                                 const std::string& svg_file);

}  // namespace mb
