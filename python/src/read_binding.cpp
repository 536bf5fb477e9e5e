// vehs.read: measurement files read, checked and detrended by the readers and the data checks of
// identify-vehs and diagnose-vehs (the same code: the same records, the same one-line errors).
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>

#include "bindings.hpp"
#include "bridge.hpp"
#include "records.hpp"
#include "tools/measurement_config.hpp"

namespace vehs::python {

namespace {

/// The keys of vehs.read: `data` and the measurement keys (columns, dt, sampling, detrend,
/// glitches, flat_stretches, units, ...), and `u` (true: every file must have the drive column).
const tools::ConfigSchema& read_schema() {
  static const tools::ConfigSchema schema = tools::with_keys_after(
      "u", tools::measurement_keys(),
      tools::ConfigSchema{"vehs.read",
                          "Reads measurement files as identify-vehs and diagnose-vehs read them.",
                          {{"data", "path | [paths]", "Measurement files (CSV, .npy, .mat).", "", false},
                           {"u", "bool", "true: every file must hold the drive column u (read when present).",
                            "false"}},
                          ""});
  return schema;
}

/// The records and their units block (JSON; {} without `units`), checked as the tools check it.
std::pair<Records, std::string> read_records(const std::string& options_json) {
  const tools::Config c = config_from_json(options_json, "vehs.read", read_schema(), {});
  const std::string units = json_text(tools::units_block(c));
  if (!c.has("data")) c.fail("data", "is missing (the measurement files)");
  const bool need_u = c.boolean_or("u", false);
  ReadOptions options = tools::read_options(c, need_u);
  options.read_u = true;  // the drive whenever a file has it (a record with u is what a rig logs)
  tools::LoadedData loaded = tools::load_measurements(c, options, true);
  Records r;
  *r.data = std::move(loaded.data);
  r.checked = true;
  return {std::move(r), units};
}

}  // namespace

void bind_read(nb::module_& m) { m.def("read", &read_records, nb::arg("options")); }

}  // namespace vehs::python
