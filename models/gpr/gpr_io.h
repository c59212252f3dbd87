#pragma once
// The GPR model file: versioned JSON (nlohmann-json).
//
//   { "format": "motionblocks-gpr-model", "version": 1,
//     "kernel": "PS" | "DS",
//     "hyperparameters": { "signal_variance_x", "length_scale_x", "signal_variance_xdot",
//                          "length_scale_xdot", "noise_variance", "period" },
//     "mean": mean(d_g) (eq. 14/24),
//     "trained_range": { "x": [min, max], "xdot": [min, max] },
//     "basis": { "harmonics": J, "period": τ }                               ("PS")
//              { "x_domain": { "center", "half_width", "count" } }          ("DS")
//              plus "xdot_domain": { "center", "half_width", "count" },
//     "weights": [β_1 … β_M],
//     "weight_covariance_lower": [Σ_11, Σ_21, Σ_22, Σ_31, …]   (row-major lower triangle),
//     "provenance": { "created_utc", "library_version", "solver", "source", "sample_count",
//                     "log_marginal_likelihood", "log_posterior", "fit_seconds", "tolerance",
//                     "period_estimated", "priors": { "<parameter>": { "median", "log_sd",
//                     "lower", "upper" } } } }
//
// JSON has no NaN or infinity: nlohmann writes them as null, and the loader rejects null where a
// number is required. A flat prior's log_sd (infinity) and an unbounded upper bound are written as
// the string "inf".

#include <filesystem>
#include <string_view>

#include <nlohmann/json.hpp>

#include "models/gpr/gpr_model.h"

namespace mb {

/// The file format's current version; files of other versions are rejected.
inline constexpr int kGprModelFileVersion = 1;
inline constexpr std::string_view kGprModelFormat = "motionblocks-gpr-model";

/// Serialises a model (layout in the file comment).
nlohmann::json GprModelToJson(const GprModel& model);

/// Parses and validates a model. Collects every problem — missing field, wrong type, NaN/null,
/// non-positive hyperparameter, wrong array length — each with its JSON pointer, and throws one
/// std::invalid_argument listing them all, prefixed with `origin` (e.g. the file name). A wrong
/// "format" or "version" is reported alone (nothing else can be trusted then). A model that is no posterior is
/// refused too: a non-finite number, a weight covariance that is not positive semidefinite (smallest eigenvalue below
/// −1e-9 × the largest), weights whose prediction inside the trained range is not finite.
GprModel GprModelFromJson(const nlohmann::json& json, std::string_view origin = "GPR model");

/// Writes the model to `path` (via a temporary file and a rename, so a reader never sees half a
/// file). Throws std::runtime_error naming the path if it cannot be written.
void SaveGprModel(const GprModel& model, const std::filesystem::path& path);

/// Reads a model file. Throws std::runtime_error if the file cannot be opened or is not JSON
/// (with the byte position of the syntax error), std::invalid_argument as GprModelFromJson.
GprModel LoadGprModel(const std::filesystem::path& path);

}  // namespace mb
