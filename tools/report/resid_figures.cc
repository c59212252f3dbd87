#include "tools/report/resid_figures.h"

#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "models/diagnosis/signal_processing.h"  // MedianTimeStep
#include "tools/workflow/measurement.h"
#include "tools/workflow/residual_analysis.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

// The derived velocity as resid's input, if the log has it.
std::optional<ResidInput> VelocityInput(const MeasurementLog& log, const std::string& position_column) {
  const std::string column = DerivedVelocityColumn(position_column);
  if (!log.has_column(column)) return std::nullopt;
  return ResidInput{fmt::format("velocity ({})", column), log.column(column)};
}

// The first input connector of the diagram whose column the log holds (simulation mode's command).
std::optional<ResidInput> ConnectorInput(const nlohmann::json& diagram, const fs::path& base_directory,
                                         const MeasurementLog& log) {
  try {
    const Diagram d = BuildDiagram(diagram, base_directory, "the compared diagram");
    for (const auto& in : d.inputs()) {
      if (log.has_column(in.measurement)) return ResidInput{fmt::format("{} ({})", in.name, in.measurement),
                                                            log.column(in.measurement)};
    }
  } catch (const std::exception&) {  // the diagram was built before; if not here, the velocity stands in
  }
  return std::nullopt;
}

// The ±band as two horizontal lines over [x0, x1].
void AddBand(double band, double x0, double x1, Figure* f) {
  f->series.push_back({{x0, x1}, {band, band}, "+99 % band", "lines"});
  f->series.push_back({{x0, x1}, {-band, -band}, "−99 % band", "lines"});
}

Series CorrelationSeries(const ResidualCorrelation& c, const std::string& label) {
  Series s{{}, c.values, label, "linespoints"};
  for (int lag : c.lags) s.x.push_back(lag);
  return s;
}

}  // namespace

std::optional<ResidInput> ChooseResidInput(ExperimentMode mode, const nlohmann::json& diagram,
                                           const fs::path& base_directory, const MeasurementLog& log,
                                           const std::string& position_column) {
  std::optional<ResidInput> input;
  if (mode == ExperimentMode::kSimulation) input = ConnectorInput(diagram, base_directory, log);
  if (!input) input = VelocityInput(log, position_column);
  if (input && (input->values.size() == 0 || input->values.maxCoeff() == input->values.minCoeff())) return std::nullopt;
  return input;
}

void AddResidFigures(HtmlReport* report, const fs::path& out, const std::string& prefix, const MeasurementLog& log,
                     const Eigen::VectorXd& residual, const Eigen::VectorXd* before,
                     const std::optional<ResidInput>& input) {
  const double dt = MedianTimeStep(log.time());
  ResidualCorrelation autocorrelation;
  try {
    autocorrelation = ResidAutocorrelation(residual);
  } catch (const std::invalid_argument& e) {
    report->Warning(fmt::format("No residual analysis: {}", e.what()));
    return;
  }
  Figure a{prefix + "resid_autocorrelation.png", "Autocorrelation of the residual (as MATLAB resid)",
           "lag [samples]", "normalised autocorrelation ρ", {}};
  if (before) {
    try {
      a.series.push_back(CorrelationSeries(ResidAutocorrelation(*before), "before (step 0)"));
    } catch (const std::invalid_argument&) {  // a constant step-0 residual: only the final one is drawn
    }
  }
  a.series.push_back(CorrelationSeries(autocorrelation, before ? "after (improved)" : "residual"));
  AddBand(autocorrelation.band, 0.0, autocorrelation.lags.back(), &a);
  report->AddFigure(a, out);
  report->Paragraph(DescribeWhiteness(autocorrelation, dt));
  if (!input) {
    report->Paragraph("No input–residual cross-correlation: the log has no input column to correlate with.");
    return;
  }
  ResidualCorrelation cross;
  try {
    cross = ResidCrossCorrelation(input->values, residual);
  } catch (const std::invalid_argument& e) {
    report->Warning(fmt::format("No input–residual cross-correlation: {}", e.what()));
    return;
  }
  Figure c{prefix + "resid_cross_correlation.png",
           fmt::format("Cross-correlation of the {} and the residual (positive lag: the residual after the input)",
                       input->name),
           "lag [samples]", "normalised cross-correlation ρ", {}};
  c.series.push_back(CorrelationSeries(cross, "residual vs " + input->name));
  AddBand(cross.band, cross.lags.front(), cross.lags.back(), &c);
  report->AddFigure(c, out);
  report->Paragraph(DescribeIndependence(cross, input->name, dt));
}

}  // namespace mb
