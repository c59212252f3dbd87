#include "models/diagnosis/effect_catalogue.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/parameter_text.h"

namespace mb {
namespace {

void CheckLength(const Eigen::VectorXd& v, Eigen::Index n, const char* name, bool optional) {
  if (optional && v.size() == 0) return;
  if (v.size() != n) {
    throw std::invalid_argument(fmt::format(
        "DiagnosisSignals: '{}' has {} samples but 'time' has {}; all signals must be equally long{}", name,
        v.size(), n, optional ? " (or empty when absent)" : ""));
  }
  if (!v.allFinite()) {
    Eigen::Index i = 0;
    while (i < v.size() && std::isfinite(v(i))) ++i;
    throw std::invalid_argument(
        fmt::format("DiagnosisSignals: '{}' holds NaN or Inf at sample {}; clean the data first", name, i));
  }
}

}  // namespace

void DiagnosisSignals::Validate() const {
  const Eigen::Index n = time.size();
  if (n < 64) {
    throw std::invalid_argument(fmt::format("DiagnosisSignals: {} samples, at least 64 are needed", n));
  }
  CheckLength(time, n, "time", false);
  CheckLength(position, n, "position", false);
  CheckLength(velocity, n, "velocity", false);
  CheckLength(acceleration, n, "acceleration", false);
  CheckLength(residual, n, "residual", false);
  CheckLength(model_output, n, "model_output", true);
  CheckLength(input, n, "input", true);
  CheckLength(logged_command, n, "logged_command", true);
  CheckLength(drive_force, n, "drive_force", true);
  if (extra_names.size() != extra_columns.size()) {
    throw std::invalid_argument(fmt::format("DiagnosisSignals: {} extra column names for {} extra columns",
                                            extra_names.size(), extra_columns.size()));
  }
  for (std::size_t k = 0; k < extra_columns.size(); ++k) CheckLength(extra_columns[k], n, extra_names[k].c_str(), false);
  for (Eigen::Index i = 1; i < n; ++i) {
    if (!(time(i) > time(i - 1))) {
      throw std::invalid_argument(fmt::format(
          "DiagnosisSignals: time does not increase at sample {} (t = {} after {})", i, time(i), time(i - 1)));
    }
  }
}

std::vector<std::string> EffectNames() {
  std::vector<std::string> names;
  for (const EffectType* e : EffectRegistry::Global().Effects()) names.push_back(e->name);
  return names;
}

std::string EffectPhysics(std::string_view name) { return LookupEffect(name).physics; }

EffectRegressors BuildEffectRegressors(const EffectInstance& effect, const DiagnosisSignals& signals) {
  return LookupEffect(effect.name).regressors(effect, signals);
}

CandidateSearch ProposeCandidateEffects(const DiagnosisSignals& s, const Eigen::Ref<const Eigen::VectorXd>& residual,
                                        const Eigen::Ref<const Eigen::MatrixXd>& base_columns,
                                        const CatalogueOptions& options) {
  s.Validate();
  const Eigen::Index n = s.size();
  if (residual.size() != n || base_columns.rows() != n) {
    throw std::invalid_argument(fmt::format(
        "ProposeCandidateEffects: residual has {} and base_columns {} rows, the signals {}", residual.size(),
        base_columns.rows(), n));
  }
  const Eigen::VectorXd r = residual;
  const Eigen::MatrixXd base = base_columns;
  CandidateSearch out;
  const ProposalContext context(s, r, base, options, &out);
  // The rules are independent (pure functions of the shared analyses): run concurrently, each into a sink of its own,
  // then merged in catalogue order — the candidates and notes a serial run gives, and its first error.
  const std::vector<const EffectType*> effects = EffectRegistry::Global().Effects();
  std::vector<ProposalSink> sinks(effects.size());
  std::vector<std::exception_ptr> errors(effects.size());
  const tbb::blocked_range<std::size_t> all(0, effects.size(), 1);
  tbb::parallel_for(all, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      ProposalContext own = context.WithSink(&sinks[i]);
      try {
        effects[i]->propose(own);
      } catch (const std::invalid_argument& e) {  // what this record cannot support: skip the effect, say why
        own.Note(fmt::format("{} not proposed: {}", effects[i]->name, NoteText(e.what())));
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  });
  for (std::size_t i = 0; i < effects.size(); ++i) {
    if (errors[i]) std::rethrow_exception(errors[i]);
    out.candidates.insert(out.candidates.end(), sinks[i].candidates.begin(), sinks[i].candidates.end());
    for (std::string& note : sinks[i].notes) {  // a note several pairs of the grammar give once
      if (std::find(out.notes.begin(), out.notes.end(), note) == out.notes.end()) out.notes.push_back(std::move(note));
    }
  }
  return out;
}

}  // namespace mb
