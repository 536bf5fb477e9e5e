#include "vehs/fit/recorded_input.hpp"

#include <algorithm>

namespace vehs {

std::vector<Term> driven_drift_library() {
  std::vector<Term> lib = paper_drift_library(4, 3);
  lib.push_back(Term::drive());
  return lib;
}

namespace {

bool has_drive(const std::vector<Term>& library) {
  return std::any_of(library.begin(), library.end(), [](const Term& t) { return t.depends_on_u(); });
}

/// `library` with the terms of `keep` it lacks appended.
std::vector<Term> with_kept(std::vector<Term> library, const std::vector<Term>& keep) {
  for (const Term& t : keep)
    if (std::find(library.begin(), library.end(), t) == library.end()) library.push_back(t);
  return library;
}

}  // namespace

RecordedInput use_recorded_input(const Dataset& data, const std::string& column, LibrariesGiven given,
                                 identify::Options& options) {
  RecordedInput r;
  if (!data.has_u()) {
    r.in_drift_library = has_drive(options.drift_library);
    return r;
  }
  r.column = column;
  const std::string col = "the recorded input '" + r.column + "'";
  if (!given.drift) {
    options.drift_library = with_kept(driven_drift_library(), options.keep_drift);
    r.added = true;
    r.why = col + " enters the default drift library as the term u (a driven system's input is part of its drift; "
                  "driven data's default drift library is {K1: 4, K2: 3} + u";
    if (!given.diffusion) {
      options.diffusion_library = with_kept(paper_diffusion_library(0), options.keep_diffusion);
      r.why += ", diffusion [1]";
    }
    r.why += "; give drift_library to choose the terms)";
  }
  r.in_drift_library = has_drive(options.drift_library);
  if (r.added)
    return r;
  if (r.in_drift_library)
    r.why = col + " is the term u of the given drift_library";
  else
    r.why = r.warning = col + " is not used: the given drift_library has no term u (add \"u\" to fit the "
                              "input's force, or leave drift_library out for driven data's default library, which takes it)";
  return r;
}

}  // namespace vehs
