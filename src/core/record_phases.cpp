#include "vehs/core/record_phases.hpp"

#include "vehs/core/error.hpp"
#include "vehs/effects/from_model.hpp"
#include "vehs/effects/harmonic_forcing.hpp"

namespace vehs {

namespace {
Error count_mismatch(const std::string& where, std::size_t phases, std::size_t records) {
  return Error(where + ": the model has one harmonic_forcing phase per record for " + std::to_string(phases) +
               " records (likelihood.record_phases) but the data have " + std::to_string(records) +
               ": use it on the records it was fitted to, in their order");
}
}  // namespace

const std::vector<double>& record_phases_of(const Model& model) {
  static const std::vector<double> none;
  if (!model.find_effect(EffectId::HarmonicForcing) || !model.fit || !model.fit->likelihood) return none;
  return model.fit->likelihood->record_phases;
}

std::vector<double> leading_record_phases(const Model& model, std::size_t records, const std::string& where) {
  const std::vector<double>& all = record_phases_of(model);
  if (all.empty()) return {};
  if (all.size() < records) throw count_mismatch(where, all.size(), records);
  return std::vector<double>(all.begin(), all.begin() + static_cast<long>(records));
}

std::vector<double> forcing_time_origins(const Model& model, const Dataset& data, const std::string& where,
                                         bool exact) {
  std::vector<double> origin(data.records.size());
  for (std::size_t r = 0; r < origin.size(); ++r) origin[r] = data.records[r].t0;
  const std::vector<double>& all = record_phases_of(model);
  if (all.empty()) return origin;
  if (exact && all.size() != data.records.size()) throw count_mismatch(where, all.size(), data.records.size());
  const std::vector<double> phases = leading_record_phases(model, data.records.size(), where);
  const auto forcing = effects::from_effect<effects::HarmonicForcing>(*model.find_effect(EffectId::HarmonicForcing));
  if (!(forcing.omega != 0.0)) throw Error(where + ": harmonic_forcing with one phase per record needs omega != 0");
  for (std::size_t r = 0; r < origin.size(); ++r) origin[r] += forcing.time_shift_to(phases[r]);
  return origin;
}

}  // namespace vehs
