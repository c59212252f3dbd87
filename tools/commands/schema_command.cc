// motionblocks schema [--sweep]: the JSON Schema of a diagram (from the block registry) or of a sweep file,
// for editors' completion and checks (diagrams/schema.json and diagrams/sweep.schema.json are copies).

#include <iostream>

#include "engine/diagram_schema.h"
#include "tools/commands/command_registry.h"
#include "tools/batch/sweep_schema.h"

namespace mb {

namespace {
struct SchemaOptions {
  bool sweep = false;
};

void RunSchema(const SchemaOptions& o) {
  std::cout << (o.sweep ? SweepSchema() : DiagramSchema(BlockRegistry::Global())).dump(2) << "\n";
}

void SetupSchemaCommand(CLI::App& app) {
  auto o = std::make_shared<SchemaOptions>();
  auto* cmd = app.add_subcommand("schema", "Print the JSON Schema of a diagram (every block type and parameter)");
  cmd->add_flag("--sweep", o->sweep, "print the schema of a sweep file instead");
  cmd->callback([o] { RunSchema(*o); });
}

}  // namespace

MB_REGISTER_COMMAND(schema, {"schema", CommandGroup::kInspect, &SetupSchemaCommand, false})

}  // namespace mb
