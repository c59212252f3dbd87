// motionblocks draw DIAGRAM [--format svg|png|dot] [-o FILE] [--set id.param=value …]
// A picture of the diagram (Graphviz): blocks with their type and key parameters, ports by name, subsystems as
// clusters, discrete blocks coloured by sample time; a refused algebraic loop is drawn highlighted and the command
// then exits with the loader's message (exit code 2).

#include <fmt/format.h>

#include <iostream>

#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/diagram_drawing.h"
#include "tools/report/output_files.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

struct DrawOptions {
  std::string diagram;
  std::vector<std::string> overrides;
  std::string format = "svg";
  std::string output;  ///< "" = the diagram's name with the format's extension, in the current folder
};

void RunDraw(const DrawOptions& o) {
  const DrawingFormat format = ParseDrawingFormat(o.format);
  const fs::path output =
      o.output.empty() ? fs::path(fs::path(o.diagram).stem().string() + "." + ToString(format)) : fs::path(o.output);
  RefuseOutputsOverInputs({{"DIAGRAM", o.diagram}}, {{"-o", output}});
  const DrawnDiagram drawn = DrawDiagram(ReadDiagramWithOverrides(o.diagram, o.overrides),
                                         fs::path(o.diagram).parent_path(), o.diagram, format, output);
  std::cout << fmt::format("wrote {}\n", output.string());
  if (drawn.algebraic_loop) {
    std::cerr << "draw: the algebraic loop is highlighted in the drawing\n";
    throw *drawn.algebraic_loop;
  }
}

void SetupDrawCommand(CLI::App& app) {
  auto o = std::make_shared<DrawOptions>();
  auto* cmd = app.add_subcommand("draw", "Draw a diagram with Graphviz: blocks, ports, subsystems, sample times");
  cmd->add_option("diagram", o->diagram, "diagram JSON file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--format", o->format, "svg, png or dot (the Graphviz text)")
      ->check(CLI::IsMember({"svg", "png", "dot"}))
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output, "the picture's file (default: DIAGRAM's name with the format's extension)");
  AddSetOption(cmd, &o->overrides);
  cmd->callback([o] { RunDraw(*o); });
}

}  // namespace

MB_REGISTER_COMMAND(draw, {"draw", CommandGroup::kInspect, &SetupDrawCommand, false})

}  // namespace mb
