// Declared parameters on the wire (proto JobSpec.parameters, AlgorithmInfo.parameter_info): a
// job's given values from its typed fields (kept for older clients) and its parameter map, the
// resolved values written back into the stored spec, and each algorithm's declarations for
// GetServerInfo.
#pragma once

#include <string>

#include "algorithm.h"
#include "params/parameter_values.h"
#include "proto.h"
#include "render_settings.h"

namespace partita::server {

ParameterValue fromWire(const pb::ParameterValue& value);
void toWire(const ParameterValue& value, pb::ParameterValue& out);

/// The parameters `spec` gives: its typed fields (each under its parameter's name: max_type_layers
/// is "layers", bootstrap_samples "bootstrap", ...; a 0 bootstrap_samples or an empty text is
/// unset) and its parameter map. "" or one line: a parameter given both ways with two values
/// (compared as entry's declaration reads them), an environment_color without 3 values.
std::string givenParameters(const AlgorithmRegistry::Entry& entry, const pb::JobSpec& spec,
                            ParameterValues& out);

/// Writes every parameter of the job as it runs (params/job_parameters.h) into spec.parameters.
void storeResolvedParameters(const AlgorithmRegistry::Entry& entry, const RenderSettings& settings,
                             pb::JobSpec& spec);

/// entry's declarations (the shared ones first) into info.parameter_info, and their names in the
/// CLI's spelling, with the budgets, into info.parameters.
void describeAlgorithmParameters(const AlgorithmRegistry::Entry& entry, pb::AlgorithmInfo& info);

}  // namespace partita::server
