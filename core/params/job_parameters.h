// A job's parameters as a whole: the shared ones (render_settings.h, bound to RenderSettings'
// fields) and its algorithm's (declared in its registry entry, held by name in
// RenderSettings::parameters). Front ends apply what a user or a client gave with
// applyJobParameters; everything that writes a job's settings out (metadata, EXR attributes,
// the reference key, the shard plan) iterates jobParameters.
#pragma once

#include <string>
#include <vector>

#include "algorithm.h"
#include "params/parameter.h"
#include "params/parameter_values.h"
#include "render_settings.h"

namespace partita {

/// The registered algorithm `name`; throws std::invalid_argument naming the ones there are.
const AlgorithmRegistry::Entry& registeredAlgorithm(const std::string& name);

/// Every parameter a job of `entry` takes: the shared ones, then the algorithm's.
std::vector<ParameterSpec> jobParameterSpecs(const AlgorithmRegistry::Entry& entry);

/// Applies `given` to `settings`: the shared parameters into its fields, the algorithm's into
/// settings.parameters, each converted to its declared type (text is parsed) and checked.
/// Names may be written with '-' for '_'. "" or one line: an unknown name (with the algorithm's
/// parameters), a value of the wrong type, a value outside its declared range.
std::string applyJobParameters(const AlgorithmRegistry::Entry& entry, const ParameterValues& given,
                               RenderSettings& settings);

struct JobParameter {
    const ParameterSpec* spec;
    ParameterValue value;  // monostate: unset (no default)
};

/// Every parameter of the job as it runs, the shared ones first, then the algorithm's with its
/// defaults filled in, in declaration order. Throws std::invalid_argument for a bad value in
/// settings.parameters.
std::vector<JobParameter> jobParameters(const AlgorithmRegistry::Entry& entry,
                                        const RenderSettings& settings);

/// settings.parameters completed with the algorithm's defaults: every declared parameter set
/// (what the job runs with, stored with it so that a later run uses the same values).
void fillAlgorithmDefaults(const AlgorithmRegistry::Entry& entry, RenderSettings& settings);

/// validateSettings, then the algorithm's parameters: no name it does not declare, every value
/// of its type and in its range, the start-up samples within limits.maxBootstrapSamples.
/// "" or one line.
std::string validateJob(const AlgorithmRegistry::Entry& entry, const RenderSettings& settings,
                        const RenderLimits& limits = {});

}  // namespace partita
