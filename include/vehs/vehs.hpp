#pragma once
// Umbrella header of the vehs library: every public area.
#include "vehs/conventions.hpp"
// core: terms, models, effects, parameters, statistics, progress, threads
#include "vehs/core/dataset.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/fit_info.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/parallel.hpp"
#include "vehs/core/parameters.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/core/statistics.hpp"
#include "vehs/core/terms.hpp"
// io: measurement files, model files, atomic outputs
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"
// sim: ensembles, steppers, random numbers
#include "vehs/sim/random.hpp"
#include "vehs/sim/simulate.hpp"
#include "vehs/sim/steppers.hpp"
// identify: drift and diffusion from records, dynamic effects, consistency studies
#include "vehs/identify/dynamic.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/identify/report.hpp"
#include "vehs/identify/study.hpp"
// fpk: stationary Fokker-Planck densities and sweeps
#include "vehs/fpk/stationary.hpp"
// diagnose: model adequacy and suspects
#include "vehs/diagnose/diagnose.hpp"
#include "vehs/diagnose/suspects.hpp"
