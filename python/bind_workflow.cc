// motionblocks.compare / fit / improve: the `compare`, `fit` and `improve` commands' library calls (tools/workflow)
// with the measurement given as a CSV path, a dict of columns or a NumPy structured array; each returns an outcome
// object whose to_dict() is the JSON the command writes (tools/report), less the entries that name written files.

#include <cmath>
#include <iostream>
#include <optional>

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "tools/report/compare_report.h"
#include "tools/report/improve_report.h"
#include "tools/workflow/compare.h"
#include "tools/workflow/fallback.h"
#include "tools/workflow/improve.h"
#include "tools/workflow/measurement_in_memory.h"

namespace mb::python {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// ---- The measurement ------------------------------------------------------------------------------------------

// What a log file's reader refuses (engine/table.h), for columns in memory: a value that is not finite, a time that
// decreases. Rows are counted from 0, as NumPy indexes them.
void CheckColumns(const std::vector<std::string>& names, const std::vector<Eigen::VectorXd>& columns) {
  for (std::size_t c = 0; c < columns.size(); ++c) {
    for (Eigen::Index i = 0; i < columns[c].size(); ++i) {
      if (!std::isfinite(columns[c](i))) {
        throw std::invalid_argument(fmt::format("measurement: column '{}' row {} is {}: give finite values (drop or "
                                                "interpolate that sample)",
                                                names[c], i, columns[c](i)));
      }
    }
  }
  const Eigen::VectorXd& t = columns.front();
  for (Eigen::Index i = 1; i < t.size(); ++i) {
    if (t(i) < t(i - 1)) {
      throw std::invalid_argument(fmt::format("measurement: time '{}' decreases at row {} ({} s after {} s): sort the "
                                              "samples by time",
                                              names.front(), i, t(i), t(i - 1)));
    }
  }
}

// A measurement log in memory from named columns: the one named time_s first (else the first given).
MeasurementLog TableOfColumns(const std::vector<std::pair<std::string, py::object>>& given) {
  if (given.empty()) throw std::invalid_argument("measurement: no columns given; give time_s and the measured columns");
  const py::module_ numpy = py::module_::import("numpy");
  std::vector<std::string> names;
  std::vector<Eigen::VectorXd> columns;
  for (const auto& [name, values] : given) {
    const auto column = numpy.attr("ravel")(numpy.attr("asarray")(values, "float64")).cast<Eigen::VectorXd>();
    if (!columns.empty() && column.size() != columns.front().size()) {
      throw std::invalid_argument(fmt::format("measurement: column '{}' has {} values, '{}' has {}: give every column "
                                              "one value per sample",
                                              name, column.size(), names.front(), columns.front().size()));
    }
    const bool time = name == "time_s";
    names.insert(time ? names.begin() : names.end(), name);
    columns.insert(time ? columns.begin() : columns.end(), column);
  }
  CheckColumns(names, columns);
  return MeasurementLog(names, columns, "<measurement arrays>");
}

// The columns of a dict (or any mapping) or of a NumPy structured array.
std::vector<std::pair<std::string, py::object>> ColumnsOf(const py::handle& measurement) {
  std::vector<std::pair<std::string, py::object>> columns;
  const py::object dtype = py::getattr(measurement, "dtype", py::none());
  if (!dtype.is_none() && !dtype.attr("names").is_none()) {
    for (const auto& name : dtype.attr("names")) columns.emplace_back(name.cast<std::string>(), measurement[name]);
  } else if (py::hasattr(measurement, "keys")) {
    for (const auto& name : measurement.attr("keys")()) {
      columns.emplace_back(py::str(name).cast<std::string>(), measurement[name]);
    }
  } else {
    throw py::type_error("measurement: give a CSV path, a dict of columns {name: 1-D array} (time_s first or named "
                         "time_s) or a NumPy structured array");
  }
  return columns;
}

bool IsPath(const py::handle& object) {
  return py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__");
}

// The measurement read for `diagram` as compare, fit and improve read it; `name` gets how it is named in reports.
MeasurementLog MeasurementFor(const json& diagram, const py::handle& measurement, const MeasurementSettings& settings,
                              std::string* name) {
  if (IsPath(measurement)) {
    *name = PathText(measurement);
    return ReadMeasurementFor(diagram, *name, settings);
  }
  *name = "<measurement arrays>";
  return TakeMeasurementFor(diagram, TableOfColumns(ColumnsOf(measurement)), settings);
}

MeasurementSettings SettingsOf(const std::map<std::string, std::string>& column_map, const std::string& position_column,
                               double derivative_cutoff_hz, const std::string& intersample) {
  MeasurementSettings s;
  s.column_map = column_map;
  s.position_column = position_column;
  s.derivative_cutoff_hz = derivative_cutoff_hz;
  s.intersample = ParseIntersample(intersample);
  return s;
}

// Progress lines on stderr when asked (no Python object is touched: the computation runs without the GIL).
std::function<void(const std::string&)> ProgressTo(bool progress) {
  if (!progress) return {};
  return [](const std::string& line) { std::cerr << line << std::endl; };
}

// What a diagram is called in messages and in the JSON: its file, else the document's source.
std::string SourceOf(const PyDiagram& d) { return d.path.empty() ? d.document.source() : d.path; }

PyDiagram DiagramOf(const json& diagram, const PyDiagram& from) {
  return PyDiagram{DiagramDocument(diagram, from.document.base_directory(), SourceOf(from)), "", {}};
}

// ---- Outcomes -------------------------------------------------------------------------------------------------

/// One refit parameter: estimate with its standard error and 95 % interval (estimate ± 1.96·SE).
struct FittedParameter {
  std::string name;
  double initial = 0.0, estimate = 0.0, standard_error = 0.0;
};

std::vector<FittedParameter> FittedParameters(const std::optional<FitResult>& fit) {
  std::vector<FittedParameter> out;
  if (!fit) return out;
  for (std::size_t i = 0; i < fit->parameters.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    out.push_back({fit->parameters[i].name, fit->initial(k), fit->estimate(k), fit->standard_error(k)});
  }
  return out;
}

struct PyCompare {
  CompareOutcome outcome;
  MeasurementLog log;
  PyDiagram diagram;
  std::string measurement;
};

struct PyFit {
  DiagramFit fit;
  json summary;
  PyDiagram diagram;
};

struct PyImprove {
  ImproveResult result;
  FallbackOutcome fallback;
  json context;
  PyDiagram diagram;
};

PyCompare Compare(const PyDiagram& d, const py::object& measurement, const std::vector<std::string>& fit, bool no_fit,
                  bool gpr_fallback, bool suggest, const std::string& suggest_effect,
                  const std::map<std::string, std::string>& column_map, const std::string& position_column,
                  double derivative_cutoff_hz, const std::string& intersample, bool progress) {
  CompareSettings settings;
  settings.measurement = SettingsOf(column_map, position_column, derivative_cutoff_hz, intersample);
  settings.fit = fit;
  settings.no_fit = no_fit;
  settings.gpr_fallback = gpr_fallback;
  settings.suggest = suggest;
  settings.suggest_effect = suggest_effect;
  std::string name;
  MeasurementLog log = MeasurementFor(d.document.json(), measurement, settings.measurement, &name);
  py::gil_scoped_release release;
  CompareOutcome outcome = mb::Compare(d.document.json(), d.document.base_directory(), SourceOf(d), log, settings,
                                       ProgressTo(progress));
  return PyCompare{std::move(outcome), std::move(log), d, name};
}

PyFit Fit(const PyDiagram& d, const py::object& measurement, std::vector<std::string> names,
          const std::map<std::string, std::string>& column_map, const std::string& position_column,
          double derivative_cutoff_hz, const std::string& intersample) {
  const json& diagram = d.document.json();
  if (names.empty()) names = d.document.FreeParameters();
  if (names.empty()) {
    throw std::invalid_argument(fmt::format(
        "nothing to fit: name parameters with fit=['block.param', …] ({} has no \"free\" list)", SourceOf(d)));
  }
  const MeasurementSettings settings = SettingsOf(column_map, position_column, derivative_cutoff_hz, intersample);
  const ExperimentMode mode = d.document.Mode();
  std::string name;
  const MeasurementLog log = MeasurementFor(diagram, measurement, settings, &name);
  std::optional<DiagramFit> fit;
  {
    py::gil_scoped_release release;
    fit = FitDiagram(diagram, d.document.base_directory(), SourceOf(d), log, settings.column_map, names,
                     mode == ExperimentMode::kEquationError ? settings.derivative_cutoff_hz : 0.0);
  }
  // fit.json as `motionblocks fit` writes it, less the fitted diagram's file.
  json summary = fit->ToJson();
  summary["diagram"] = SourceOf(d);
  summary["measurement"] = name;
  summary["mode"] = mode;
  summary["samples"] = log.rows();
  return PyFit{std::move(*fit), std::move(summary), d};
}

PyImprove Improve(const PyDiagram& d, const py::object& measurement, const py::object& validation,
                  const ImproveSettings& settings, bool fallback, bool progress) {
  const json& diagram = d.document.json();
  std::string name, validation_name;
  const MeasurementLog training = MeasurementFor(diagram, measurement, settings.measurement, &name);
  std::optional<MeasurementLog> held_out;
  if (!validation.is_none()) held_out = MeasurementFor(diagram, validation, settings.measurement, &validation_name);
  // improve.json's head, as `motionblocks improve` writes it.
  const json context = {{"diagram", SourceOf(d)},
                        {"measurement", name},
                        {"validation", held_out ? json(validation_name) : json(nullptr)},
                        {"mode", ModeOf(diagram)},
                        {"max_effects", settings.max_effects},
                        {"min_relative_gain", settings.min_relative_gain}};
  py::gil_scoped_release release;
  ImproveResult result = ImproveModel(diagram, d.document.base_directory(), SourceOf(d), training,
                                      held_out ? &*held_out : nullptr, settings, ProgressTo(progress));
  FallbackOutcome fitted = fallback ? FitImproveFallback(result, ProgressTo(progress)) : FallbackOutcome{};
  return PyImprove{std::move(result), std::move(fitted), context, d};
}

json ImproveJson(const PyImprove& i) {
  json j = i.context;
  j.update(i.result.ToJson());
  if (i.fallback.attempted) j["nonparametric_fallback"] = ImproveFallbackRecord(i.fallback);
  j["complete"] = true;  // the call returned: the whole result, as the command's last improve.json says
  return j;
}

// ---- Bindings -------------------------------------------------------------------------------------------------

void BindOutcomeParts(py::module_& m) {
  py::class_<FittedParameter>(m, "FittedParameter", "A refit parameter (Levenberg–Marquardt), in its SI unit.")
      .def_readonly("name", &FittedParameter::name, "'element.parameter' (or 'element.parameter[i]').")
      .def_readonly("initial", &FittedParameter::initial, "Value before the fit.")
      .def_readonly("estimate", &FittedParameter::estimate, "Fitted value.")
      .def_readonly("standard_error", &FittedParameter::standard_error, "sqrt(diag(σ² (JᵀJ)⁻¹)).")
      .def_property_readonly(
          "interval",
          [](const FittedParameter& p) {
            return std::make_pair(p.estimate - 1.96 * p.standard_error, p.estimate + 1.96 * p.standard_error);
          },
          "95 % confidence interval (estimate ± 1.96·SE).")
      .def("__repr__", [](const FittedParameter& p) {
        return fmt::format("<FittedParameter {} = {:.6g} ± {:.3g} (95 %)>", p.name, p.estimate,
                           1.96 * p.standard_error);
      });
  py::class_<DiagnosedEffect>(m, "DiagnosedEffect", "A candidate missing physical effect, ranked by the diagnosis.")
      .def_readonly("effect", &DiagnosedEffect::effect, "Catalogue name, e.g. 'velocity_dependent_ripple'.")
      .def_readonly("score", &DiagnosedEffect::score, "Share of the remaining held-out residual energy explained, 0..1.")
      .def_readonly("cumulative_share", &DiagnosedEffect::cumulative_share,
                    "Share of the base's held-out residual energy explained so far, 0..1.")
      .def_readonly("parameters", &DiagnosedEffect::parameters, "dict of the effect's parameters, SI (period [m], …).")
      .def_readonly("description", &DiagnosedEffect::description, "In words, with the figures.")
      .def("__repr__", [](const DiagnosedEffect& e) {
        return fmt::format("<DiagnosedEffect {} {:.1f} %>", e.effect, 100.0 * e.score);
      });
}

void BindCompare(py::module_& m) {
  py::class_<PyCompare>(m, "CompareOutcome",
                        "What compare found: the fit, the ranked missing effects, the fallback. Arrays are the primary "
                        "output, shape (N,), in its unit.")
      .def_property_readonly("mode", [](const PyCompare& c) { return std::string(Name(c.outcome.mode)); })
      .def_property_readonly("output", [](const PyCompare& c) { return c.outcome.primary_after().connector; })
      .def_property_readonly("unit", [](const PyCompare& c) { return c.outcome.primary_after().unit; })
      .def_property_readonly("rmse_before", [](const PyCompare& c) { return c.outcome.primary_before().rmse; })
      .def_property_readonly("rmse_after", [](const PyCompare& c) { return c.outcome.primary_after().rmse; })
      .def_property_readonly("fit_percent_before",
                             [](const PyCompare& c) { return c.outcome.primary_before().fit_percent; })
      .def_property_readonly("fit_percent_after",
                             [](const PyCompare& c) { return c.outcome.primary_after().fit_percent; })
      .def_property_readonly("parameters", [](const PyCompare& c) { return FittedParameters(c.outcome.compared.fit); },
                             "list of FittedParameter (empty: nothing refit).")
      .def_property_readonly(
          "diagnosis",
          [](const PyCompare& c) {
            return c.outcome.compared.diagnosis ? c.outcome.compared.diagnosis->effects : std::vector<DiagnosedEffect>{};
          },
          "list of DiagnosedEffect, highest share first.")
      .def_property_readonly("summary",
                             [](const PyCompare& c) {
                               const auto& d = c.outcome.compared.diagnosis;
                               return d ? d->summary : c.outcome.compared.diagnosis_skipped;
                             })
      .def_property_readonly("notes", [](const PyCompare& c) { return c.outcome.compared.notes; })
      .def_property_readonly("time", [](const PyCompare& c) { return Eigen::VectorXd(c.log.time()); },
                             "Sample times of the compared log [s], shape (N,).")
      .def_property_readonly("measured", [](const PyCompare& c) { return c.outcome.primary_after().measured; },
                             "The measured primary output, shape (N,).")
      .def_property_readonly("model_before", [](const PyCompare& c) { return c.outcome.primary_before().model; },
                             "The model's primary output as given, shape (N,).")
      .def_property_readonly("model", [](const PyCompare& c) { return c.outcome.primary_after().model; },
                             "The model's primary output after the refit, shape (N,).")
      .def_property_readonly("fitted_diagram",
                             [](const PyCompare& c) { return DiagramOf(c.outcome.compared.fitted_diagram, c.diagram); })
      .def_property_readonly(
          "suggested_diagram",
          [](const PyCompare& c) -> std::optional<PyDiagram> {
            if (!c.outcome.suggestion || !c.outcome.suggestion->diagram) return std::nullopt;
            return DiagramOf(*c.outcome.suggestion->diagram, c.diagram);
          },
          "With suggest=True: the diagram amended with the top-ranked effect's block (None: see to_dict()).")
      .def("to_dict",
           [](const PyCompare& c) {
             return FromJson(CompareResultsJson(c.outcome, c.log, SourceOf(c.diagram), c.measurement));
           },
           "compare.json as `motionblocks compare` writes it, less the written files' entries.");
}

void BindFit(py::module_& m) {
  py::class_<PyFit>(m, "FitOutcome", "A refit of chosen parameters against a measurement (`motionblocks fit`).")
      .def_property_readonly("parameters", [](const PyFit& f) { return FittedParameters(f.fit.fit); })
      .def_property_readonly("rmse_before", [](const PyFit& f) { return f.fit.before.front().rmse; })
      .def_property_readonly("rmse_after", [](const PyFit& f) { return f.fit.after.front().rmse; })
      .def_property_readonly("status", [](const PyFit& f) { return f.fit.fit.status; })
      .def_property_readonly("fitted_diagram", [](const PyFit& f) { return DiagramOf(f.fit.fitted_diagram, f.diagram); })
      .def("to_dict", [](const PyFit& f) { return FromJson(f.summary); },
           "fit.json as `motionblocks fit` writes it, less the fitted diagram's file.");
}

void BindImprove(py::module_& m) {
  py::class_<ImproveStep>(m, "ImproveStep", "One diagram of the improve loop (RMSE in the primary output's unit).")
      .def_readonly("round", &ImproveStep::round)
      .def_readonly("accepted", &ImproveStep::accepted)
      .def_readonly("effect", &ImproveStep::effect, "Catalogue name of the added effect ('' at step 0).")
      .def_readonly("element", &ImproveStep::element)
      .def_readonly("verdict", &ImproveStep::verdict)
      .def_readonly("rmse_train_before", &ImproveStep::rmse_train_before)
      .def_readonly("rmse_train", &ImproveStep::rmse_train)
      .def_readonly("rmse_heldout_before", &ImproveStep::rmse_heldout_before)
      .def_readonly("rmse_heldout", &ImproveStep::rmse_heldout)
      .def_property_readonly("parameters", [](const ImproveStep& s) { return FittedParameters(s.training.fit); })
      .def("to_dict", [](const ImproveStep& s) { return FromJson(s.ToJson()); });
  py::class_<PyImprove>(m, "ImproveOutcome", "The improve loop's steps, why it stopped, and the improved diagram.")
      .def_property_readonly("steps", [](const PyImprove& i) { return i.result.steps; })
      .def_property_readonly("stop", [](const PyImprove& i) { return ToString(i.result.stop); })
      .def_property_readonly("stop_reason", [](const PyImprove& i) { return i.result.stop_reason; })
      .def_property_readonly("improved_diagram", [](const PyImprove& i) {
        return DiagramOf(i.result.last_accepted().training.fitted_diagram, i.diagram);
      })
      .def("to_dict", [](const PyImprove& i) { return FromJson(ImproveJson(i)); },
           "improve.json as `motionblocks improve` writes it, less the written files' entries.");
}

}  // namespace

void BindWorkflow(py::module_& m) {
  BindOutcomeParts(m);
  BindCompare(m);
  BindFit(m);
  BindImprove(m);
  // Docstrings outlive this function: pybind11 keeps the pointers.
  static std::string kCompareDoc, kFitDoc, kImproveDoc;
  static const std::string kMeasurement =
      " `measurement`: a CSV path, a dict of columns {name: 1-D array} or a NumPy structured array — time_s [s] "
      "(or the first column), then the measured columns (position_m [m], force_N [N], …); `map` = {connector: "
      "column} as --map; velocity and acceleration are derived from `position_column` when absent; `intersample` 'zoh' "
      "when the measured outputs are held commands (a logged force or current reference), as --intersample.";
  m.def("compare", &Compare, py::arg("diagram"), py::arg("measurement"), py::kw_only(),
        py::arg("fit") = std::vector<std::string>{}, py::arg("no_fit") = false, py::arg("gpr_fallback") = true,
        py::arg("suggest") = false, py::arg("suggest_effect") = "",
        py::arg("map") = std::map<std::string, std::string>{}, py::arg("position_column") = "position_m",
        py::arg("derivative_cutoff_hz") = 100.0, py::arg("intersample") = "foh", py::arg("progress") = false,
        (kCompareDoc = std::string("Compares `diagram` with a measurement as `motionblocks compare` does: refits `fit` "
                     "('block.param'; default the diagram's free list), ranks the missing effects, fits the TISO-GPR "
                     "fallback. Returns a CompareOutcome.") +
         kMeasurement)
            .c_str());
  m.def("fit", &Fit, py::arg("diagram"), py::arg("measurement"), py::kw_only(),
        py::arg("fit") = std::vector<std::string>{}, py::arg("map") = std::map<std::string, std::string>{},
        py::arg("position_column") = "position_m", py::arg("derivative_cutoff_hz") = 100.0,
        py::arg("intersample") = "foh",
        (kFitDoc = std::string("Refits parameters of `diagram` (`fit`: 'block.param'; default its free list) by "
                     "Levenberg–Marquardt, as `motionblocks fit`. Returns a FitOutcome.") +
         kMeasurement)
            .c_str());
  m.def(
      "improve",
      [](const PyDiagram& d, const py::object& measurement, const py::object& validation, int max_effects,
         int max_trials, double min_gain, bool refine_periods, const std::vector<std::string>& validation_fit,
         bool fallback, const std::map<std::string, std::string>& column_map, const std::string& position_column,
         double derivative_cutoff_hz, const std::string& intersample, bool progress) {
        ImproveSettings s;
        s.measurement = SettingsOf(column_map, position_column, derivative_cutoff_hz, intersample);
        s.max_effects = max_effects;
        s.max_trials_per_round = max_trials;
        s.min_relative_gain = min_gain;
        s.refine_periods = refine_periods;
        s.validation_free = validation_fit;
        return Improve(d, measurement, validation, s, fallback, progress);
      },
      py::arg("diagram"), py::arg("measurement"), py::kw_only(), py::arg("validation") = py::none(),
      py::arg("max_effects") = 3, py::arg("max_trials") = 3, py::arg("min_gain") = 0.002,
      py::arg("refine_periods") = true, py::arg("validation_fit") = std::vector<std::string>{},
      py::arg("fallback") = true, py::arg("map") = std::map<std::string, std::string>{},
      py::arg("position_column") = "position_m", py::arg("derivative_cutoff_hz") = 100.0,
      py::arg("intersample") = "foh", py::arg("progress") = false,
      (kImproveDoc = std::string("The loop compare → suggest → fit → compare of `motionblocks improve`: adds ranked effects one at "
                   "a time, keeps those that lower the held-out RMSE (on `validation`, same forms as `measurement`, "
                   "else cross-validated). Returns an ImproveOutcome.") +
       kMeasurement)
          .c_str());
}

}  // namespace mb::python
