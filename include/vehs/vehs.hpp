#pragma once
// Umbrella header of the vehs library.
#include "vehs/conventions.hpp"
#include "vehs/core/config.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/terms.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/core/statistics.hpp"
#include "vehs/core/table.hpp"
#include "vehs/sim/simulate.hpp"
#include "vehs/core/parameters.hpp"
