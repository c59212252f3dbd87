#pragma once
// The use cases of motionblocks, one library call each: read this header first.
//
// Each use case takes a settings struct that holds its only defaults and returns a typed result; the JSON file the
// command writes is the result's ToJson() (or the report function named), so `motionblocks <command>`
// (tools/commands/<command>_command.cc) and the Python module (python/bind_*.cc) only fill the settings, call, and
// print or convert. Files and reports are written by tools/report/, never here (docs/architecture.md: the layers).
//
//   Simulate   RunSettings → DiagramRun(diagram, settings).Execute(sink) → RunOutcome (run.h); summary.json:
//              RunSummaryJson (tools/report/run_report.h). run_command.cc; motionblocks.simulate (bind_diagram.cc).
//   Compare    CompareSettings → Compare(...) → CompareOutcome (compare.h); compare.json: CompareOutcome::ToJson
//              (tools/report/compare_report.h). compare_command.cc; motionblocks.compare (bind_workflow.cc).
//   Fit        FitSettings → FitToMeasurement(...) → FitOutcome (fit.h); fit.json: FitOutcome::ToJson.
//              fit_command.cc; motionblocks.fit (bind_workflow.cc).
//   Improve    ImproveSettings → ImproveToMeasurement(...) → ImproveOutcome (improve.h; the loop alone: ImproveModel);
//              improve.json: ImproveOutcome::ToJson. improve_command.cc; motionblocks.improve (bind_workflow.cc).
//   Sweep      SweepSpec (ParseSweep, ReadSweepFile: tools/batch/sweep_spec.h) and SweepOptions → RunSweep(...) →
//              SweepOutcome (tools/batch/sweep.h; it writes runs.csv, runs.json, report.html). sweep_command.cc;
//              motionblocks.sweep (bind_sweep.cc).
//   HIL        HilSessionSettings → RunHilSession(settings, stop) → HilSessionResult (tools/hil/hil_session.h, mb_hil);
//              summary.json: HilSessionResult::ToJson. hil_command.cc; motionblocks.run_hil_session (bind_hil.cc).
//   Reproduce  ReproduceOptions → Reproduce(options) → results.json's content (tools/experiments/paper/reproduce.h:
//              the seed paper's experiments). reproduce_command.cc; no Python binding.
//   Linearize  a built Diagram and an OperatingPoint → Linearize(diagram, point) → LinearModel (engine/linearization.h,
//              as Simulink's linmod); its JSON with Bode data: LinearizationJson. linearize_command.cc; no Python
//              binding.
//
// What every measured use case shares: MeasurementSettings (measurement.h: column map, position column, derivative
// cut-off, intersample) and ReadMeasurementFor, or TakeMeasurementFor with MeasurementOfColumns for columns in memory
// (measurement_in_memory.h). A diagram is a DiagramDocument (engine/diagram_document.h: its JSON, folder and source).
//
// This header includes the use cases of this layer and the engine's. Sweep, HIL and Reproduce live in the layers
// above (tools/batch/, tools/hil/, tools/experiments/paper/, which may include this one and not the reverse): include
// their headers named above.

#include "engine/diagram_document.h"
#include "engine/linearization.h"
#include "tools/workflow/compare.h"
#include "tools/workflow/fit.h"
#include "tools/workflow/improve.h"
#include "tools/workflow/measurement.h"
#include "tools/workflow/measurement_in_memory.h"
#include "tools/workflow/run.h"
