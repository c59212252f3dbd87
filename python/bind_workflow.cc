// motionblocks.compare / fit / improve: the `compare`, `fit` and `improve` commands' library calls (tools/workflow)
// with the measurement given as a CSV path, a dict of columns or a NumPy structured array; each returns an outcome
// object whose to_dict() is the JSON the command writes (tools/report), less the entries that name written files.

#include <iostream>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "tools/report/compare_report.h"
#include "tools/report/improve_report.h"
#include "tools/workflow/compare.h"
#include "tools/workflow/fit.h"
#include "tools/workflow/improve.h"
#include "tools/workflow/measurement_in_memory.h"

namespace mb::python {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// ---- The measurement ------------------------------------------------------------------------------------------

// A measurement log in memory from named columns (MeasurementOfColumns checks them as a log file's reader would).
MeasurementLog TableOfColumns(const std::vector<std::pair<std::string, py::object>>& given) {
  const py::module_ numpy = py::module_::import("numpy");
  std::vector<std::pair<std::string, Eigen::VectorXd>> columns;
  for (const auto& [name, values] : given) {
    columns.emplace_back(name, numpy.attr("ravel")(numpy.attr("asarray")(values, "float64")).cast<Eigen::VectorXd>());
  }
  return MeasurementOfColumns(columns, "<measurement arrays>");
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
  Eigen::VectorXd time;  ///< the measurement's sample times [s], the compared outputs' grid
};

struct PyImprove {
  ImproveOutcome outcome;
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
  CompareOutcome outcome =
      mb::Compare(DiagramDocument(d.document.json(), d.document.base_directory(), SourceOf(d)), log, settings,
                  ProgressTo(progress));
  return PyCompare{std::move(outcome), std::move(log), d, name};
}

PyFit Fit(const PyDiagram& d, const py::object& measurement, std::vector<std::string> names,
          const std::map<std::string, std::string>& column_map, const std::string& position_column,
          double derivative_cutoff_hz, const std::string& intersample) {
  FitSettings settings;
  settings.measurement = SettingsOf(column_map, position_column, derivative_cutoff_hz, intersample);
  settings.parameters = std::move(names);
  std::string name;
  const MeasurementLog log = MeasurementFor(d.document.json(), measurement, settings.measurement, &name);
  std::optional<FitOutcome> outcome;
  {
    py::gil_scoped_release release;
    outcome = FitToMeasurement(d.document, log, name, settings);
  }
  outcome->diagram = SourceOf(d);
  json summary = outcome->ToJson();  // fit.json as `motionblocks fit` writes it, less the fitted diagram's file
  return PyFit{std::move(outcome->result), std::move(summary), d, log.time()};
}

PyImprove Improve(const PyDiagram& d, const py::object& measurement, const py::object& validation,
                  const ImproveSettings& settings, bool progress) {
  const json& diagram = d.document.json();
  std::string name, validation_name;
  const MeasurementLog training = MeasurementFor(diagram, measurement, settings.measurement, &name);
  std::optional<MeasurementLog> held_out;
  if (!validation.is_none()) held_out = MeasurementFor(diagram, validation, settings.measurement, &validation_name);
  const DiagramDocument document(diagram, d.document.base_directory(), SourceOf(d));
  py::gil_scoped_release release;
  return PyImprove{ImproveToMeasurement(document, training, name, held_out ? &*held_out : nullptr, validation_name,
                                        settings, ProgressTo(progress)),
                   d};
}

// ---- Named series, DataFrames, reprs ------------------------------------------------------------------------

/// One named series of an outcome (a compared output's measured, model or residual values), in `unit`.
struct NamedSeries {
  std::string name, unit;
  Eigen::VectorXd values;
};

// Per compared output (the primary first): "<connector>.measured", "<connector>.model_before" (the diagram as
// given), "<connector>.model" (after the refit), "<connector>.residual" (measured − model).
std::vector<NamedSeries> ComparedSeries(const std::vector<ComparedOutput>& before,
                                        const std::vector<ComparedOutput>& after) {
  std::vector<NamedSeries> series;
  for (std::size_t i = 0; i < after.size(); ++i) {
    const ComparedOutput& a = after[i];
    series.push_back({a.connector + ".measured", a.unit, a.measured});
    if (i < before.size()) series.push_back({a.connector + ".model_before", a.unit, before[i].model});
    series.push_back({a.connector + ".model", a.unit, a.model});
    series.push_back({a.connector + ".residual", a.unit, a.residual()});
  }
  return series;
}

std::vector<std::string> NamesOf(const std::vector<NamedSeries>& series) {
  std::vector<std::string> names;
  for (const auto& s : series) names.push_back(s.name);
  return names;
}

py::dict UnitsOf(const std::vector<NamedSeries>& series) {
  py::dict units;
  for (const auto& s : series) units[py::str(s.name)] = s.unit;
  return units;
}

// series[name]. @throws py::key_error listing the names.
Eigen::VectorXd SeriesNamed(const std::vector<NamedSeries>& series, const std::string& name) {
  for (const auto& s : series) {
    if (s.name == name) return s.values;
  }
  throw py::key_error(fmt::format("no series '{}'; there are: {}", name, fmt::join(NamesOf(series), ", ")));
}

// The series as a DataFrame over the measurement's time ('time_s' [s]).
py::object SeriesFrame(const std::vector<NamedSeries>& series, const Eigen::VectorXd& time, const char* caller) {
  std::vector<FrameColumn> columns;
  for (const auto& s : series) columns.push_back({s.name, py::cast(s.values), s.unit});
  return DataFrame(columns, py::cast(time), "time_s", caller);
}

// "force_N: RMSE 4.45 → 2.33 N, fit 91.8 % → 95.7 %": the primary output before and after a refit.
std::string PrimaryFigures(const ComparedOutput& before, const ComparedOutput& after) {
  return fmt::format("{}: RMSE {}, fit {:.1f} % → {:.1f} %", after.column, BeforeAfter(before.rmse, after.rmse, after.unit),
                     before.fit_percent, after.fit_percent);
}

std::string CompareRepr(const PyCompare& c) {
  const auto& diagnosis = c.outcome.compared.diagnosis;
  const std::string effect = !diagnosis                 ? "no diagnosis"
                             : diagnosis->effects.empty() ? "no missing effect found"
                                                          : "top effect " + diagnosis->effects.front().effect;
  return fmt::format("<CompareOutcome {}, {}>", PrimaryFigures(c.outcome.primary_before(), c.outcome.primary_after()),
                     effect);
}

std::string FitRepr(const PyFit& f) {
  std::vector<std::string> estimates;
  for (const auto& p : FittedParameters(f.fit.fit)) estimates.push_back(fmt::format("{} = {:.4g}", p.name, p.estimate));
  return fmt::format("<FitOutcome {}; {}; {}>", PrimaryFigures(f.fit.before.front(), f.fit.after.front()),
                     fmt::join(estimates, ", "), f.fit.fit.status);
}

std::string StepRepr(const ImproveStep& s) {
  const std::string what = s.round == 0 && s.effect.empty()
                               ? "the diagram as given, refit"
                               : fmt::format("{} {}", s.effect, s.accepted ? "accepted" : "rejected");
  return fmt::format("<ImproveStep round {}, {}: RMSE {}, held out {}>", s.round, what,
                     BeforeAfter(s.rmse_train_before, s.rmse_train, s.unit()),
                     BeforeAfter(s.rmse_heldout_before, s.rmse_heldout, s.unit()));
}

std::string ImproveRepr(const PyImprove& i) {
  const ImproveStep& first = i.outcome.result.first();
  const ImproveStep& last = i.outcome.result.last_accepted();
  std::vector<std::string> accepted;
  for (std::size_t k = 1; k < i.outcome.result.steps.size(); ++k) {
    if (i.outcome.result.steps[k].accepted) accepted.push_back(i.outcome.result.steps[k].effect);
  }
  // From the diagram as given (refit: step 0) to the last accepted step.
  return fmt::format("<ImproveOutcome {}: {} effects tried, {} accepted{}; RMSE {}, held out {}; stop {}>",
                     first.training.after.front().column, i.outcome.result.steps.size() - 1, accepted.size(),
                     accepted.empty() ? "" : fmt::format(" ({})", fmt::join(accepted, ", ")),
                     BeforeAfter(first.rmse_train, last.rmse_train, first.unit()),
                     BeforeAfter(first.rmse_heldout, last.rmse_heldout, first.unit()), ToString(i.outcome.result.stop));
}

// improve as a table: one row per step, in the order tried.
py::object ImproveFrame(const PyImprove& i) {
  py::list rounds, accepted, effect, element, train_before, train, heldout_before, heldout, verdict;
  for (const auto& s : i.outcome.result.steps) {
    rounds.append(s.round);
    accepted.append(s.accepted);
    effect.append(s.effect);
    element.append(s.element);
    train_before.append(s.rmse_train_before);
    train.append(s.rmse_train);
    heldout_before.append(s.rmse_heldout_before);
    heldout.append(s.rmse_heldout);
    verdict.append(s.verdict);
  }
  const std::string unit = i.outcome.result.first().unit();
  return DataFrame({{"round", rounds, ""},
                    {"accepted", accepted, ""},
                    {"effect", effect, ""},
                    {"element", element, ""},
                    {"rmse_train_before", train_before, unit},
                    {"rmse_train", train, unit},
                    {"rmse_heldout_before", heldout_before, unit},
                    {"rmse_heldout", heldout, unit},
                    {"verdict", verdict, ""}},
                   py::none(), "step", "ImproveOutcome.to_pandas()");
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
      .def_readonly("base_share", &DiagnosedEffect::base_share,
                    "Share of the base's held-out residual energy this effect removed where it was added, 0..1: what "
                    "the ranking sorts by.")
      .def_readonly("selection_order", &DiagnosedEffect::selection_order,
                    "Where the forward selection chose it, 0 first: the order a diagram is amended in.")
      .def_readonly("parameters", &DiagnosedEffect::parameters, "dict of the effect's parameters, SI (period [m], …).")
      .def_readonly("description", &DiagnosedEffect::description, "In words, with the figures.")
      .def("__repr__", [](const DiagnosedEffect& e) {
        return fmt::format("<DiagnosedEffect {}: {:.1f} % of the held-out residual{}>", e.effect, 100.0 * e.score,
                           e.parameters.empty() ? "" : ", " + DescribeParameters(e.parameters));
      });
}

void BindCompare(py::module_& m) {
  py::class_<PyCompare>(m, "CompareOutcome",
                        "What compare found: the fit, the ranked missing effects, the fallback. The primary output "
                        "(the first output connector) as arrays of shape (N,) in its unit (`unit`), N the "
                        "measurement's samples; every compared output by name: c['force.residual'], c.keys(), "
                        "c.units; c.to_pandas() is a DataFrame over the time.")
      .def_property_readonly("mode", [](const PyCompare& c) { return std::string(Name(c.outcome.mode)); },
                             "'equation_error' or 'simulation' (the diagram's connectors choose).")
      .def_property_readonly("output", [](const PyCompare& c) { return c.outcome.primary_after().connector; },
                             "The primary output connector's name.")
      .def_property_readonly("column", [](const PyCompare& c) { return c.outcome.primary_after().column; },
                             "The measured column it is compared with (e.g. 'force_N').")
      .def_property_readonly("unit", [](const PyCompare& c) { return c.outcome.primary_after().unit; },
                             "The primary output's unit (RMSE, arrays).")
      .def_property_readonly("rmse_before", [](const PyCompare& c) { return c.outcome.primary_before().rmse; },
                             "RMSE of the primary output, the diagram as given [`unit`].")
      .def_property_readonly("rmse_after", [](const PyCompare& c) { return c.outcome.primary_after().rmse; },
                             "RMSE after the refit [`unit`] (= rmse_before when nothing was refit).")
      .def_property_readonly("fit_percent_before",
                             [](const PyCompare& c) { return c.outcome.primary_before().fit_percent; },
                             "100·(1 − ‖residual‖/‖measured − its mean‖) [%], as given; 100 is perfect.")
      .def_property_readonly("fit_percent_after",
                             [](const PyCompare& c) { return c.outcome.primary_after().fit_percent; },
                             "The same after the refit [%].")
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
                             },
                             "The diagnosis in words (or why there is none).")
      .def_property_readonly("notes", [](const PyCompare& c) { return c.outcome.compared.notes; },
                             "list of str: how the log was taken in, and the diagnosis's caveats.")
      .def_property_readonly("time", [](const PyCompare& c) { return Eigen::VectorXd(c.log.time()); },
                             "Sample times of the compared log [s], shape (N,).")
      .def_property_readonly("measured", [](const PyCompare& c) { return c.outcome.primary_after().measured; },
                             "The measured primary output, shape (N,) [`unit`].")
      .def_property_readonly("model_before", [](const PyCompare& c) { return c.outcome.primary_before().model; },
                             "The model's primary output as given, shape (N,) [`unit`].")
      .def_property_readonly("model", [](const PyCompare& c) { return c.outcome.primary_after().model; },
                             "The model's primary output after the refit, shape (N,) [`unit`].")
      .def_property_readonly("residual", [](const PyCompare& c) { return c.outcome.primary_after().residual(); },
                             "measured − model (after the refit), shape (N,) [`unit`].")
      .def(
          "keys",
          [](const PyCompare& c) { return NamesOf(ComparedSeries(c.outcome.compared.before, c.outcome.compared.after)); },
          "The named series (list of str): per compared output '<connector>.measured', '.model_before', '.model' and "
          "'.residual'.")
      .def(
          "__getitem__",
          [](const PyCompare& c, const std::string& name) {
            return SeriesNamed(ComparedSeries(c.outcome.compared.before, c.outcome.compared.after), name);
          },
          py::arg("name"), "The series `name` (keys()), shape (N,), in units[name]. Raises KeyError listing them.")
      .def_property_readonly(
          "units",
          [](const PyCompare& c) { return UnitsOf(ComparedSeries(c.outcome.compared.before, c.outcome.compared.after)); },
          "dict series name → unit (the output connector's).")
      .def(
          "to_pandas",
          [](const PyCompare& c) {
            return SeriesFrame(ComparedSeries(c.outcome.compared.before, c.outcome.compared.after), c.log.time(),
                               "CompareOutcome.to_pandas()");
          },
          "A pandas.DataFrame: index 'time_s' [s], N rows; the columns of keys() (float64); df.attrs['units'] = "
          "{column: unit}. Raises ImportError naming Debian's python3-pandas when pandas is missing.")
      .def_property_readonly("fitted_diagram",
                             [](const PyCompare& c) { return DiagramOf(c.outcome.compared.fitted_diagram, c.diagram); },
                             "The Diagram with the refit estimates written in.")
      .def_property_readonly(
          "suggested_diagram",
          [](const PyCompare& c) -> std::optional<PyDiagram> {
            if (!c.outcome.suggestion || !c.outcome.suggestion->diagram) return std::nullopt;
            return DiagramOf(*c.outcome.suggestion->diagram, c.diagram);
          },
          "With suggest=True: the diagram amended in the ranking's order, the friction-law replacements and then "
          "the top missing effect's block (None: see to_dict()).")
      .def_property_readonly(
          "suggested_effects",
          [](const PyCompare& c) {
            return c.outcome.suggestion ? c.outcome.suggestion->effects : std::vector<std::string>{};
          },
          "With suggest=True: the catalogue names of the effects suggested_diagram adds, in the order added (list of "
          "str; empty when none).")
      .def("to_dict",
           [](const PyCompare& c) {
             return FromJson(c.outcome.ToJson(SourceOf(c.diagram), c.measurement));
           },
           "compare.json as `motionblocks compare` writes it, less the written files' entries.")
      .def("__repr__", &CompareRepr);
}

void BindFit(py::module_& m) {
  py::class_<PyFit>(m, "FitOutcome",
                    "A refit of chosen parameters against a measurement (`motionblocks fit`). Every compared output "
                    "by name, shape (N,): f['force.model'], f.keys(), f.units; f.to_pandas() is a DataFrame.")
      .def_property_readonly("parameters", [](const PyFit& f) { return FittedParameters(f.fit.fit); },
                             "list of FittedParameter, in the order asked.")
      .def_property_readonly("unit", [](const PyFit& f) { return f.fit.after.front().unit; },
                             "The primary output's unit.")
      .def_property_readonly("rmse_before", [](const PyFit& f) { return f.fit.before.front().rmse; },
                             "RMSE of the primary output before the fit [`unit`].")
      .def_property_readonly("rmse_after", [](const PyFit& f) { return f.fit.after.front().rmse; },
                             "RMSE after the fit [`unit`].")
      .def_property_readonly("fit_percent_before", [](const PyFit& f) { return f.fit.before.front().fit_percent; },
                             "100·(1 − ‖residual‖/‖measured − its mean‖) [%] before the fit.")
      .def_property_readonly("fit_percent_after", [](const PyFit& f) { return f.fit.after.front().fit_percent; },
                             "The same after the fit [%].")
      .def_property_readonly("status", [](const PyFit& f) { return f.fit.fit.status; },
                             "Levenberg–Marquardt's status ('converged …') or 'not identifiable'.")
      .def_property_readonly("time", [](const PyFit& f) { return f.time; }, "Sample times [s], shape (N,).")
      .def("keys", [](const PyFit& f) { return NamesOf(ComparedSeries(f.fit.before, f.fit.after)); },
           "The named series: per compared output '<connector>.measured', '.model_before', '.model', '.residual'.")
      .def(
          "__getitem__",
          [](const PyFit& f, const std::string& name) { return SeriesNamed(ComparedSeries(f.fit.before, f.fit.after), name); },
          py::arg("name"), "The series `name`, shape (N,), in units[name]. Raises KeyError listing them.")
      .def_property_readonly("units", [](const PyFit& f) { return UnitsOf(ComparedSeries(f.fit.before, f.fit.after)); },
                             "dict series name → unit.")
      .def(
          "to_pandas",
          [](const PyFit& f) {
            return SeriesFrame(ComparedSeries(f.fit.before, f.fit.after), f.time, "FitOutcome.to_pandas()");
          },
          "A pandas.DataFrame: index 'time_s' [s], N rows; the columns of keys(); df.attrs['units']. Raises "
          "ImportError naming Debian's python3-pandas when pandas is missing.")
      .def_property_readonly("fitted_diagram", [](const PyFit& f) { return DiagramOf(f.fit.fitted_diagram, f.diagram); },
                             "The Diagram with the estimates written in.")
      .def("to_dict", [](const PyFit& f) { return FromJson(f.summary); },
           "fit.json as `motionblocks fit` writes it, less the fitted diagram's file.")
      .def("__repr__", &FitRepr);
}

void BindImprove(py::module_& m) {
  py::class_<ImproveStep>(m, "ImproveStep", "One diagram of the improve loop (RMSE in the primary output's unit).")
      .def_readonly("round", &ImproveStep::round, "0 for the diagram as given, then 1, 2, … per effect added.")
      .def_readonly("accepted", &ImproveStep::accepted, "Whether the loop kept it (held-out RMSE fell enough).")
      .def_readonly("effect", &ImproveStep::effect, "Catalogue name of the added effect ('' at step 0).")
      .def_readonly("element", &ImproveStep::element, "The element the effect's block was added as.")
      .def_readonly("verdict", &ImproveStep::verdict, "Why accepted or rejected, in words.")
      .def_property_readonly("unit", &ImproveStep::unit, "The primary output's unit, of every RMSE here.")
      .def_readonly("rmse_train_before", &ImproveStep::rmse_train_before,
                    "RMSE on the measurement of the last accepted step [`unit`].")
      .def_readonly("rmse_train", &ImproveStep::rmse_train, "RMSE on the measurement after this step's refit [`unit`].")
      .def_readonly("rmse_heldout_before", &ImproveStep::rmse_heldout_before,
                    "Held-out RMSE of the last accepted step [`unit`].")
      .def_readonly("rmse_heldout", &ImproveStep::rmse_heldout,
                    "This step's held-out RMSE (validation record, else cross-validated) [`unit`].")
      .def_property_readonly("parameters", [](const ImproveStep& s) { return FittedParameters(s.training.fit); },
                             "list of FittedParameter of this step's joint refit.")
      .def("to_dict", [](const ImproveStep& s) { return FromJson(s.ToJson()); }, "The step as improve.json has it.")
      .def("__repr__", &StepRepr);
  py::class_<PyImprove>(m, "ImproveOutcome",
                        "The improve loop's steps, why it stopped, and the improved diagram; to_pandas(): one row per "
                        "step.")
      .def_property_readonly("steps", [](const PyImprove& i) { return i.outcome.result.steps; },
                             "list of ImproveStep in the order tried; steps[0] is the diagram as given.")
      .def_property_readonly("unit", [](const PyImprove& i) { return i.outcome.result.first().unit(); },
                             "The primary output's unit, of every RMSE.")
      .def_property_readonly("stop", [](const PyImprove& i) { return ToString(i.outcome.result.stop); },
                             "Why it stopped: 'no_missing_effect', 'catalogue_exhausted', 'no_heldout_gain' or "
                             "'max_effects'.")
      .def_property_readonly("stop_reason", [](const PyImprove& i) { return i.outcome.result.stop_reason; },
                             "The same in words.")
      .def_property_readonly("improved_diagram",
                             [](const PyImprove& i) {
                               return DiagramOf(i.outcome.result.last_accepted().training.fitted_diagram, i.diagram);
                             },
                             "The last accepted step's Diagram, refit.")
      .def("to_pandas", &ImproveFrame,
           "A pandas.DataFrame with one row per step (index 'step', 0 = the diagram as given): round, accepted, "
           "effect, element, rmse_train_before, rmse_train, rmse_heldout_before, rmse_heldout (in `unit`), verdict; "
           "df.attrs['units'] = {column: unit}. Raises ImportError naming Debian's python3-pandas when pandas is "
           "missing.")
      .def("to_dict", [](const PyImprove& i) { return FromJson(i.outcome.ToJson()); },
           "improve.json as `motionblocks improve` writes it, less the written files' entries.")
      .def("__repr__", &ImproveRepr);
}

}  // namespace

void BindWorkflow(py::module_& m) {
  BindOutcomeParts(m);
  BindCompare(m);
  BindFit(m);
  BindImprove(m);
  // Docstrings outlive this function: pybind11 keeps the pointers.
  static std::string kCompareDoc, kFitDoc, kImproveDoc;
  // The defaults are the settings structs' (the only ones: the command line takes them from there too).
  const MeasurementSettings measured;
  const CompareSettings compared;
  const ImproveSettings improved;
  const std::string hold = IntersampleName(measured.intersample);
  static const std::string kMeasurement =
      " `measurement`: a CSV path, a dict of columns {name: 1-D array} or a NumPy structured array — time_s [s] "
      "(or the first column), then the measured columns (position_m [m], force_N [N], …); `map` = {connector: "
      "column} as --map; velocity and acceleration are derived from `position_column` when absent; `intersample` 'zoh' "
      "when the measured outputs are held commands (a logged force or current reference), as --intersample.";
  m.def("compare", &Compare, py::arg("diagram"), py::arg("measurement"), py::kw_only(),
        py::arg("fit") = std::vector<std::string>{}, py::arg("no_fit") = false, py::arg("gpr_fallback") = compared.gpr_fallback,
        py::arg("suggest") = false, py::arg("suggest_effect") = "",
        py::arg("map") = std::map<std::string, std::string>{}, py::arg("position_column") = measured.position_column,
        py::arg("derivative_cutoff_hz") = measured.derivative_cutoff_hz, py::arg("intersample") = hold,
        py::arg("progress") = false,
        (kCompareDoc = std::string("Compares `diagram` with a measurement as `motionblocks compare` does: refits `fit` "
                     "('block.param'; default the diagram's free list), ranks the missing effects, fits the TISO-GPR "
                     "fallback. Returns a CompareOutcome.") +
         kMeasurement)
            .c_str());
  m.def("fit", &Fit, py::arg("diagram"), py::arg("measurement"), py::kw_only(),
        py::arg("fit") = std::vector<std::string>{}, py::arg("map") = std::map<std::string, std::string>{},
        py::arg("position_column") = measured.position_column,
        py::arg("derivative_cutoff_hz") = measured.derivative_cutoff_hz, py::arg("intersample") = hold,
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
        s.fallback = fallback;
        return Improve(d, measurement, validation, s, progress);
      },
      py::arg("diagram"), py::arg("measurement"), py::kw_only(), py::arg("validation") = py::none(),
      py::arg("max_effects") = improved.max_effects, py::arg("max_trials") = improved.max_trials_per_round,
      py::arg("min_gain") = improved.min_relative_gain, py::arg("refine_periods") = improved.refine_periods,
      py::arg("validation_fit") = std::vector<std::string>{}, py::arg("fallback") = improved.fallback,
      py::arg("map") = std::map<std::string, std::string>{}, py::arg("position_column") = measured.position_column,
      py::arg("derivative_cutoff_hz") = measured.derivative_cutoff_hz, py::arg("intersample") = hold,
      py::arg("progress") = false,
      (kImproveDoc = std::string("The loop compare → suggest → fit → compare of `motionblocks improve`: adds ranked effects one at "
                   "a time, keeps those that lower the held-out RMSE (on `validation`, same forms as `measurement`, "
                   "else cross-validated). Returns an ImproveOutcome.") +
       kMeasurement)
          .c_str());
}

}  // namespace mb::python
